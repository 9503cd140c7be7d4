#include "fit_analysis.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

namespace volcomp::calibration::detail {
namespace {

// Predictions are propagated in blocks: the sensitivity rows of many points times W and D V_N
// are two matrix products instead of one small product per row.
constexpr Eigen::Index kBlockPoints = 256;

const model::MachineModelSpec* machineSpec(const config::ModelDocument& document) {
  return std::get_if<model::MachineModelSpec>(&document.spec);
}

}  // namespace

std::vector<Eigen::Vector3d> distinctTools(const MeasurementSet& measurements,
                                           const Eigen::Vector3d& templateToolMm) {
  std::vector<Eigen::Vector3d> tools;
  if (!measurements.hasTool) return {templateToolMm};
  for (const Measurement& m : measurements.points) {
    const bool seen = std::any_of(tools.begin(), tools.end(), [&](const Eigen::Vector3d& t) {
      return (t - m.toolMm).norm() <= 1e-9;
    });
    if (!seen) tools.push_back(m.toolMm);
  }
  return tools;
}

DataCoverage coverageOf(const MeasurementSet& measurements, const config::ModelDocument& document) {
  DataCoverage coverage;
  coverage.points = static_cast<int>(measurements.points.size());
  for (int axis = 0; axis < 3; ++axis) {
    auto& span = coverage.spanMm[static_cast<std::size_t>(axis)];
    span = {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
    for (const Measurement& m : measurements.points) {
      span[0] = std::min(span[0], m.qMm[axis]);
      span[1] = std::max(span[1], m.qMm[axis]);
    }
  }
  if (const auto* spec = machineSpec(document)) {
    coverage.travelMm = spec->travelMm;
    coverage.toolsMm = distinctTools(measurements, spec->toolMm);
  }
  return coverage;
}

std::vector<PointPrediction> measuredPoints(const MeasurementSet& measurements,
                                            const config::ModelDocument& document) {
  const auto* spec = machineSpec(document);
  std::vector<PointPrediction> points;
  points.reserve(measurements.points.size());
  for (const Measurement& m : measurements.points) {
    PointPrediction p;
    p.qMm = m.qMm;
    p.toolMm = measurements.hasTool || spec == nullptr ? m.toolMm : spec->toolMm;
    p.directions = m.directions;
    p.line = m.line;
    points.push_back(p);
  }
  return points;
}

void predictPoints(const IdentificationProblem& problem, const FitResult& fit,
                   std::vector<PointPrediction>& points) {
  const FitStatistics& st = fit.statistics;
  const Eigen::Index n = fit.parameters.size();
  const double s0 = std::sqrt(st.varianceFactor);
  const Eigen::MatrixXd scaledNull = st.columnScale.asDiagonal() * st.nullBasis;
  Eigen::MatrixXd rows(3 * kBlockPoints, n);
  Eigen::Matrix<double, 3, Eigen::Dynamic> g(3, n);
  for (std::size_t first = 0; first < points.size(); first += kBlockPoints) {
    const Eigen::Index count =
        std::min<Eigen::Index>(kBlockPoints, static_cast<Eigen::Index>(points.size() - first));
    for (Eigen::Index i = 0; i < count; ++i) {
      PointPrediction& point = points[first + static_cast<std::size_t>(i)];
      PredictionPoint at;
      at.qMm = point.qMm;
      at.toolMm = point.toolMm;
      at.directions = point.directions;
      problem.prediction(fit.parameters, at, point.errorMm, g);
      // The sensitivities where the statistics were linearised (see FitResult::linearisedAt).
      if (fit.linearisedAt.size() == fit.parameters.size() && fit.linearisedAt != fit.parameters) {
        Eigen::Vector3d ignored;
        problem.prediction(fit.linearisedAt, at, ignored, g);
      }
      rows.middleRows(3 * i, 3) = g;
    }
    const auto block = rows.topRows(3 * count);
    // The criteria of predictionUncertainty(), for many rows at once.
    const Eigen::MatrixXd propagated = block * st.rangeFactor;
    const Eigen::MatrixXd unseen = block * scaledNull;
    for (Eigen::Index i = 0; i < count; ++i) {
      PointPrediction& point = points[first + static_cast<std::size_t>(i)];
      point.determined = true;
      for (Eigen::Index axis = 0; axis < 3; ++axis) {
        const Eigen::Index r = 3 * i + axis;
        const bool seen = unseen.cols() == 0 || unseen.row(r).norm() <= st.nullThreshold;
        point.determined = point.determined && seen;
        point.stdMm(axis) =
            seen ? s0 * propagated.row(r).norm() : std::numeric_limits<double>::quiet_NaN();
      }
    }
  }
}

std::vector<SampledCurve> sampleCurves(const IdentificationProblem& problem, const FitResult& fit) {
  std::vector<SampledCurve> out;
  for (Curve& curve : problem.curves()) {
    SampledCurve sampled;
    Eigen::RowVectorXd mean = Eigen::RowVectorXd::Zero(fit.parameters.size());
    for (const Eigen::RowVectorXd& g : curve.gradients) {
      sampled.values.push_back(g.dot(fit.parameters));
      sampled.std.push_back(functionUncertainty(fit.statistics, g).std);
      sampled.relativeStd.push_back(
          functionUncertainty(fit.statistics, g - curve.gradients.front()).std);
      mean += g / static_cast<double>(curve.gradients.size());
    }
    sampled.mean = mean.dot(fit.parameters);
    sampled.meanStd = functionUncertainty(fit.statistics, mean).std;
    sampled.curve = std::move(curve);
    out.push_back(std::move(sampled));
  }
  return out;
}

ValidationResult validateWith(const ProblemFactory& factory, const MeasurementSet& heldOut,
                              const FitResult& fit) {
  const auto problem = factory(heldOut);
  ValidationResult result;
  result.kind = ValidationKind::File;
  result.file = heldOut.file;
  result.stats = residualStats(*problem, fit.parameters);
  for (const Measurement& m : heldOut.points) result.lines.push_back(m.line);
  return result;
}

ValidationResult crossValidate(const ProblemFactory& factory, const MeasurementSet& measurements,
                               int folds, const SolveOptions& options) {
  const std::size_t count = measurements.points.size();
  std::vector<std::size_t> order(count);
  std::iota(order.begin(), order.end(), 0);
  std::mt19937 generator(20261201);
  std::shuffle(order.begin(), order.end(), generator);
  ValidationResult result;
  result.kind = ValidationKind::KFold;
  result.folds = folds;
  SolveOptions quiet = options;
  quiet.progress = nullptr;
  std::optional<ResidualAccumulator> accumulator;
  for (int fold = 0; fold < folds; ++fold) {
    MeasurementSet train = measurements, test = measurements;
    train.points.clear();
    test.points.clear();
    for (std::size_t k = 0; k < count; ++k) {
      (static_cast<int>(k % static_cast<std::size_t>(folds)) == fold ? test : train)
          .points.push_back(measurements.points[order[k]]);
    }
    if (test.points.empty() || train.points.empty()) continue;
    const auto trainProblem = factory(train);
    const FitResult fit = solve(*trainProblem, trainProblem->startVector(), quiet);
    const auto testProblem = factory(test);
    if (!accumulator) {
      accumulator.emplace(
          std::min(testProblem->residualsPerObservation(), testProblem->statisticsRows()));
    }
    accumulateResiduals(*testProblem, fit.parameters, *accumulator,
                        static_cast<int>(result.lines.size()));
    for (const Measurement& m : test.points) result.lines.push_back(m.line);
    result.foldRmsMm.push_back(residualStats(*testProblem, fit.parameters).rms);
    result.foldRank.push_back(fit.statistics.rank);
  }
  if (accumulator) result.stats = accumulator->finish();
  return result;
}

}  // namespace volcomp::calibration::detail
