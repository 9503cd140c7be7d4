#pragma once
/// Residuals of a calibration per measured point, recomputed from the measurements: a
/// calibration report holds only their statistics. r = E_model(q, tool) - measured (the sign
/// of the calibration's residuals), |r| in µm, for the template at its start values ("before")
/// and for the model of the report ("after"). Bidirectional tables are taken at the mean of their
/// curves, as the calibration does for points without a direction.

#include <optional>
#include <vector>

#include "volcomp/calibration/measurements.hpp"
#include "volcomp/model/machine_model.hpp"

namespace volcomp::report {

struct PointResiduals {
  std::vector<int> lines;        ///< line of each point in the measurement file
  std::vector<double> beforeUm;  ///< |r| with the template (empty when no template is given)
  std::vector<double> afterUm;   ///< |r| with the report's model
  double rmsBeforeUm = 0, rmsAfterUm = 0, maxBeforeUm = 0, maxAfterUm = 0;
};

/// `before` may be null (no template at hand). Each point's tool offset replaces the model's
/// when the measurements give one.
PointResiduals pointResiduals(const model::MachineModel* before, const model::MachineModel& after,
                              const calibration::MeasurementSet& measurements);

}  // namespace volcomp::report
