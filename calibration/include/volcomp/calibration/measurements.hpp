#pragma once
/// Calibration measurements from CSV, read with config::CsvReader (comments, any column order,
/// unit suffixes such as ex_um; bare names are mm and rad). Columns:
///   x,y,z        commanded position (mm)                               required
///   ex,ey,ez     measured volumetric error, actual - nominal (mm)       required
///   tx,ty,tz     tool offset of this point (mm), overrides the model's  optional (all three)
///   ea,eb,ec     measured angular error, rotation vector (rad)          optional (all three)
///   weight       relative weight (> 0) of the point, 1 by default       optional
///   direction    direction of approach per axis, e.g. +-+ (0 unknown)   optional
///   q1..q9       joint values of a D-H chain (mm, revolute in deg)      optional, D-H chains only
///   ox,oy,oz     ignored (so that `volcomp eval --points` output can be read back)
/// For a D-H chain with 3 joints x,y,z are the joint values when no q columns are given.
/// Every error names the file, the line and the column (throws config::ConfigError with key path
/// "line N" or "line N, column NAME").

#include <iosfwd>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "volcomp/model/types.hpp"

namespace volcomp::calibration {

struct Measurement {
  Eigen::Vector3d qMm = Eigen::Vector3d::Zero();
  Eigen::Vector3d errorMm = Eigen::Vector3d::Zero();
  Eigen::Vector3d toolMm = Eigen::Vector3d::Zero();
  Eigen::Vector3d angularErrorRad = Eigen::Vector3d::Zero();
  /// q1..qn as read (mm, deg); empty when the file has no q columns.
  std::vector<double> joints;
  /// Direction of approach per axis (Unknown when the file has no direction column).
  model::Directions directions{};
  double weight = 1.0;
  /// Line number in the file (1-based), for messages.
  int line = 0;
};

struct MeasurementSet {
  std::string file;
  std::vector<Measurement> points;
  bool hasTool = false;
  bool hasAngles = false;
  bool hasDirection = false;
  int jointColumns = 0;
};

/// Reads a measurement CSV; throws config::ConfigError naming the file, line and column.
MeasurementSet readMeasurementsCsv(const std::string& path);
/// Same from a stream; `file` is used in messages.
MeasurementSet parseMeasurementsCsv(std::istream& input, const std::string& file);

}  // namespace volcomp::calibration
