#pragma once
/// The documents a report is built from besides the model, read defensively: what is present is
/// shown, what is absent is left out, and a field of the wrong type is skipped with a note (the
/// formats grow; a report should not fail because one field changed). A file that is not JSON,
/// or not the kind of document expected, throws config::ConfigError (file, key path, expectation).
///
/// Units: lengths of errors in µm, positions in mm, angles as the file states.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "volcomp/model/types.hpp"

namespace volcomp::report {

/// Things the reader skipped or could not use, in words (shown in the report and on stderr).
using Notes = std::vector<std::string>;

/// A labelled figure for generic tables ("validation.rms_mm" -> 0.0004).
struct Figure {
  std::string key;
  std::string text;  ///< the value as shown
};

// ---- calibration (`volcomp calibrate --report`, format volcomp-calibration-report/1) ----------

struct CalibrationParameter {
  std::string name;
  std::string unit;  ///< unit of start, value and sigma as the report gives it ("um", "urad", ...)
  std::optional<double> start;
  std::optional<double> value;
  std::optional<double> sigma;
  std::optional<bool> identifiable;
  bool nuisance = false;
};

/// Residual statistics of one side (before or after the fit), mm as in the file.
struct ResidualSide {
  std::optional<double> rmsMm;
  std::optional<double> maxMm;
  std::optional<int> maxLine;
  /// Every other number in the object (e.g. per-axis figures), by key, as given.
  std::vector<std::pair<std::string, double>> more;
};

struct CalibrationReport {
  std::string file;
  std::string templateFile;     ///< as written by calibrate (may be relative to its cwd)
  std::string measurementFile;  ///< same
  std::string method, loss, termination;
  std::optional<bool> converged;
  std::optional<int> points, iterations, rank, parameterCount, dof;
  std::optional<double> conditionNumber, s0Mm;
  std::vector<CalibrationParameter> parameters;
  /// Row-major n x n, n = parameters.size(); empty when absent or inconsistent.
  std::vector<double> correlation;
  ResidualSide before, after;
  /// Descriptions of the combinations the data cannot separate.
  std::vector<std::string> unidentifiable;
  /// Top-level fields not shown elsewhere (scalars, and scalars one object deep), for the
  /// "further figures" table: what newer calibrate versions add is shown without code here.
  std::vector<Figure> otherFields;
};

CalibrationReport readCalibrationReport(const nlohmann::json& document, const std::string& file,
                                        Notes& notes);
CalibrationReport loadCalibrationReport(const std::string& path, Notes& notes);

// ---- ISO 230-2 (`volcomp iso230-2 --json`, format volcomp-iso230-2/1, one axis a file) -------

/// One target position P_i; deviations converted to µm.
struct IsoTarget {
  double positionMm = 0.0;
  std::optional<double> meanUp, meanDown, mean;        ///< x̄↑_i, x̄↓_i, x̄_i
  std::optional<double> reversal;                      ///< B_i = x̄↑_i − x̄↓_i
  std::optional<double> sUp, sDown;                    ///< s↑_i, s↓_i
  std::optional<double> repeatUp, repeatDown, repeat;  ///< R↑_i, R↓_i, R_i
  std::vector<double> runsUp, runsDown;                ///< the deviations x_ij read, when given
};

/// An axis figure of ISO 230-2:2014 in µm: B, B̄, R↑, R↓, R, E↑, E↓, E, M, A↑, A↓, A.
struct IsoFigure {
  std::string symbol;  ///< as printed, e.g. "A↑"
  std::string meaning;
  double valueUm = 0.0;
};

struct IsoAxis {
  std::string file;
  std::optional<model::Axis> axis;  ///< when the evaluation names it
  std::string source;               ///< the runs' CSV as the evaluation names it
  std::string standard;
  int runsUp = 0, runsDown = 0;    ///< runs per direction
  std::vector<IsoTarget> targets;  ///< ascending by position
  std::vector<IsoFigure> figures;
  std::vector<std::string> warnings;  ///< what the evaluation warned about
};

/// One axis's evaluation; lengths in the document's `units` (mm by the format) become mm and µm.
IsoAxis readIsoAxis(const nlohmann::json& document, const std::string& file, Notes& notes);
IsoAxis loadIsoAxis(const std::string& path, Notes& notes);

// ---- a compensation run (volcomp-sim's report line) -------------------------------------------

/// Error statistics of the true tool-tip error, µm.
struct ErrorStats {
  std::optional<double> rmsBefore, rmsAfter, maxBefore, maxAfter;
};

struct RunSummary {
  std::string file;
  ErrorStats total;                ///< of the 3-D error vector
  std::array<ErrorStats, 3> axes;  ///< X, Y, Z
  std::optional<double> durationS;
  std::optional<std::int64_t> samples, writes, partialWrites, limiterViolations, sessions;
  std::optional<std::int64_t> daemonCycles, daemonOverruns, daemonExitStatus;
  std::string positionSemantics;
  std::optional<std::array<double, 3>> appliedOffsetMm;  ///< left applied at the end
  /// True when the error statistics come from a snapshot taken while compensating (the demo's
  /// "compensating" object) rather than from the end of the run.
  bool whileCompensating = false;
  std::vector<Figure> otherFields;
};

/// The simulator's final JSON line, optionally with "compensating" (a STATUS snapshot whose error
/// statistics replace the final ones) and "daemon" ({cycles, overruns, exit_status}).
RunSummary readRunSummary(const nlohmann::json& document, const std::string& file, Notes& notes);
/// Reads a file holding that JSON (the last line that starts with '{' when it has several lines).
RunSummary loadRunSummary(const std::string& path, Notes& notes);

/// One write of volcomp-sim --record: time (s), offsets (mm), whether it broke the limits.
struct RecordedWrite {
  double tS = 0.0;
  std::array<double, 3> offsetMm{};
  bool violation = false;
};

/// Reads volcomp-sim's --record CSV (t_s,offset_x_mm,offset_y_mm,offset_z_mm,...,violation).
/// Throws config::ConfigError naming the file and line on a malformed row.
std::vector<RecordedWrite> loadRecordedWrites(const std::string& path);

/// Reads a whole file as JSON; throws config::ConfigError (file, "", what went wrong).
nlohmann::json readJsonFile(const std::string& path);

}  // namespace volcomp::report
