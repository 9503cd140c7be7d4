#pragma once
/// Calibration report: JSON (machine-readable) and a readable text summary. Values and standard
/// deviations are shown in the template's error units (ParameterInfo::unit); residual statistics
/// in mm.

#include <iosfwd>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "volcomp/calibration/identification.hpp"
#include "volcomp/calibration/least_squares.hpp"

namespace volcomp::calibration {

struct ReportContext {
  std::string templateFile;
  std::string measurementFile;
  std::string method;  ///< "linear" or "levenberg-marquardt"
  std::string loss;    ///< "none", "huber", "cauchy"
  double rankTolerance = 0.0;
  /// Line numbers of the measurement rows (for "worst point" messages); may be empty.
  std::vector<int> lines;
};

/// {"format": "volcomp-calibration-report/1", "parameters": [{name, key, unit, value, std,
/// identifiable, nuisance}], "correlation", "residuals": {"before", "after"} (rms_mm, max_mm,
/// max_line), "rank", "parameter_count", "condition_number", "full_condition_number",
/// "singular_values", "s0_mm", "dof", "unidentifiable": [{parameters, coefficients,
/// relative_singular_value, description}], ...}.
nlohmann::json reportJson(const FitResult& fit, const std::vector<ParameterInfo>& info,
                          const ReportContext& context);

/// The readable summary (parameters with sigma, residuals before/after, rank and conditioning,
/// strongest correlations, and the combinations the data cannot separate, in words).
void writeSummary(std::ostream& out, const FitResult& fit, const std::vector<ParameterInfo>& info,
                  const ReportContext& context);

}  // namespace volcomp::calibration
