#include "volcomp/report/calibration_views.hpp"

#include <algorithm>
#include <cmath>

#include "volcomp/report/model_views.hpp"

namespace volcomp::report {
namespace {

// |r| per point, and its RMS and maximum. One point at a time: each may carry its own tool.
std::vector<double> residuals(const model::MachineModel& model,
                              const calibration::MeasurementSet& measurements, double& rms,
                              double& max) {
  model::Workspace ws;
  std::vector<double> out;
  out.reserve(measurements.points.size());
  double sumSquares = 0.0;
  max = 0.0;
  for (const calibration::Measurement& m : measurements.points) {
    const Eigen::Vector3d& tool = measurements.hasTool ? m.toolMm : model.toolMm();
    const model::PointError e = model::evaluate(model, ws, m.qMm, tool);
    const double r = (e.errorMm - m.errorMm).norm() * kUmPerMm;
    out.push_back(r);
    sumSquares += r * r;
    max = std::max(max, r);
  }
  rms = out.empty() ? 0.0 : std::sqrt(sumSquares / static_cast<double>(out.size()));
  return out;
}

}  // namespace

PointResiduals pointResiduals(const model::MachineModel* before, const model::MachineModel& after,
                              const calibration::MeasurementSet& measurements) {
  PointResiduals out;
  for (const calibration::Measurement& m : measurements.points) out.lines.push_back(m.line);
  if (before != nullptr) {
    out.beforeUm = residuals(*before, measurements, out.rmsBeforeUm, out.maxBeforeUm);
  }
  out.afterUm = residuals(after, measurements, out.rmsAfterUm, out.maxAfterUm);
  return out;
}

}  // namespace volcomp::report
