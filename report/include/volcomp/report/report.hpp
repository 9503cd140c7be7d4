#pragma once
/// The HTML report (`volcomp report`): one self-contained file (stylesheet, script, data and the
/// Vega runtime inlined; it opens offline) from a model and, where given, a calibration report,
/// an ISO 230-2 result and a compensation run. Sections: summary with headline figures, the
/// error components along their axes, volumetric error maps, calibration, ISO 230-2, the run, and
/// the inputs with what could not be shown.

#include <cstdint>
#include <ctime>
#include <optional>
#include <string>
#include <vector>

#include "volcomp/calibration/measurements.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/report/inputs.hpp"

namespace volcomp::report {

/// A file the report was built from, listed in its appendix.
struct InputFile {
  std::string role;  ///< "model", "calibration report", ...
  std::string path;
  std::uintmax_t bytes = 0;
  std::string modified;  ///< ISO 8601 local time, "" when unknown
};

struct ReportInputs {
  config::ModelDocument model;
  std::optional<CalibrationReport> calibration;
  /// The calibration's measurements and template (for residuals per point), when at hand.
  std::optional<calibration::MeasurementSet> measurements;
  std::optional<config::ModelDocument> calibrationTemplate;
  /// ISO 230-2 evaluations, one per axis.
  std::vector<IsoAxis> iso;
  std::optional<RunSummary> run;
  std::vector<RecordedWrite> writes;  ///< the run's recorded writes (may be empty)
  std::vector<InputFile> files;
  /// What the readers skipped; the report lists them in its appendix.
  Notes notes;
};

struct ReportOptions {
  std::string title = "Machine accuracy report";
  /// The machine's name; empty: the model's name (or its file name).
  std::string machine;
  std::string volcompVersion;
  /// Date shown in the report (seconds since the epoch, local time).
  std::time_t date = 0;
  /// Z levels of the XY maps (mm); empty: top, middle and bottom of the Z range.
  std::vector<double> zLevelsMm;
  /// Cells along the longer side of a map.
  int mapResolution = 24;
  /// Samples along an axis for each component curve.
  int curveSamples = 161;
};

struct RenderedReport {
  std::string html;
  /// Section ids and titles in order, as in the table of contents.
  std::vector<std::pair<std::string, std::string>> sections;
  int charts = 0;
  /// Notes of the inputs plus what the report itself could not show.
  Notes notes;
};

/// Builds the report. Throws config::ConfigError when the model cannot be evaluated (e.g. a
/// template with nothing usable); everything optional that is missing or unusable is left out
/// and named in `notes`.
RenderedReport renderReport(const ReportInputs& inputs, const ReportOptions& options);

}  // namespace volcomp::report
