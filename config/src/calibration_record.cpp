#include "volcomp/config/calibration_record.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <functional>
#include <limits>

namespace volcomp::config {
namespace {

using Json = nlohmann::json;

std::vector<std::string> readStrings(const JsonReader& node) {
  std::vector<std::string> out;
  for (const JsonReader& element : node.elements()) out.push_back(element.string());
  return out;
}

int readCount(const JsonReader& node) {
  return static_cast<int>(node.integer(0, std::numeric_limits<int>::max()));
}

// Distance from x to the affine hull of the points in `subset` when the closest point lies inside
// their simplex; nullopt when it does not, or when the points are affinely dependent (a smaller
// subset then covers the same simplex).
std::optional<double> simplexDistance(const std::vector<Eigen::Vector3d>& points,
                                      const std::vector<std::size_t>& subset,
                                      const Eigen::Vector3d& x) {
  const Eigen::Vector3d& origin = points[subset[0]];
  const auto extra = static_cast<Eigen::Index>(subset.size() - 1);
  if (extra == 0) return (x - origin).norm();
  Eigen::Matrix<double, 3, Eigen::Dynamic> edges(3, extra);
  for (Eigen::Index k = 0; k < extra; ++k) {
    edges.col(k) = points[subset[static_cast<std::size_t>(k + 1)]] - origin;
  }
  const Eigen::ColPivHouseholderQR<Eigen::Matrix<double, 3, Eigen::Dynamic>> qr(edges);
  if (qr.rank() < extra) return std::nullopt;
  const Eigen::VectorXd weights = qr.solve(x - origin);
  const double tolerance = 1e-12;
  if ((weights.array() < -tolerance).any() || weights.sum() > 1.0 + tolerance) return std::nullopt;
  return (edges * weights + origin - x).norm();
}

}  // namespace

CalibrationRecord readCalibrationRecord(const JsonReader& node) {
  node.allowOnly({"volcomp_version", "date", "template", "measurements", "validation", "points",
                  "parameter_count", "rank", "residual_rms_mm", "s0_mm", "not_identifiable",
                  "tools_mm"});
  CalibrationRecord record;
  record.volcompVersion = node.stringOr("volcomp_version", "");
  record.date = node.stringOr("date", "");
  record.templateFile = node.stringOr("template", "");
  record.validationFile = node.stringOr("validation", "");
  if (const auto files = node.find("measurements")) record.measurementFiles = readStrings(*files);
  if (const auto points = node.find("points")) record.points = readCount(*points);
  if (const auto count = node.find("parameter_count")) record.parameterCount = readCount(*count);
  if (const auto rank = node.find("rank")) record.rank = readCount(*rank);
  if (const auto residuals = node.find("residual_rms_mm")) {
    residuals->allowOnly({"before", "after", "validation"});
    if (const auto v = residuals->find("before")) record.residualRmsBeforeMm = v->number();
    if (const auto v = residuals->find("after")) record.residualRmsAfterMm = v->number();
    if (const auto v = residuals->find("validation")) record.residualRmsValidationMm = v->number();
  }
  if (const auto s0 = node.find("s0_mm")) record.s0Mm = s0->number();
  if (const auto names = node.find("not_identifiable")) record.notIdentifiable = readStrings(*names);
  if (const auto tools = node.find("tools_mm")) {
    for (const JsonReader& tool : tools->elements()) {
      if (!tool.isArray() || tool.size() != 3) tool.failExpected("[x, y, z] in mm");
      const auto v = tool.fixedNumbers<3>();
      record.toolsMm.emplace_back(v[0], v[1], v[2]);
    }
  }
  return record;
}

nlohmann::json writeCalibrationRecord(const CalibrationRecord& record) {
  Json out = Json::object();
  const auto text = [&](const char* key, const std::string& value) {
    if (!value.empty()) out[key] = value;
  };
  text("volcomp_version", record.volcompVersion);
  text("date", record.date);
  text("template", record.templateFile);
  if (!record.measurementFiles.empty()) out["measurements"] = record.measurementFiles;
  text("validation", record.validationFile);
  if (record.points) out["points"] = *record.points;
  if (record.parameterCount) out["parameter_count"] = *record.parameterCount;
  if (record.rank) out["rank"] = *record.rank;
  Json residuals = Json::object();
  if (record.residualRmsBeforeMm) residuals["before"] = *record.residualRmsBeforeMm;
  if (record.residualRmsAfterMm) residuals["after"] = *record.residualRmsAfterMm;
  if (record.residualRmsValidationMm) residuals["validation"] = *record.residualRmsValidationMm;
  if (!residuals.empty()) out["residual_rms_mm"] = residuals;
  if (record.s0Mm) out["s0_mm"] = *record.s0Mm;
  if (!record.notIdentifiable.empty()) out["not_identifiable"] = record.notIdentifiable;
  if (!record.toolsMm.empty()) {
    Json tools = Json::array();
    for (const Eigen::Vector3d& t : record.toolsMm) tools.push_back({t.x(), t.y(), t.z()});
    out["tools_mm"] = tools;
  }
  return out;
}

std::optional<double> toolDistanceMm(const CalibrationRecord& record,
                                     const Eigen::Vector3d& toolMm) {
  if (record.toolsMm.empty()) return std::nullopt;
  // The closest point of a convex hull in 3-D lies in a simplex of at most 4 of its points
  // (Caratheodory), so trying every subset of up to 4 tools finds it exactly; calibrations use
  // a handful of tools, so this costs microseconds.
  std::vector<Eigen::Vector3d> tools;
  for (const Eigen::Vector3d& t : record.toolsMm) {
    const bool seen = std::any_of(tools.begin(), tools.end(), [&](const Eigen::Vector3d& u) {
      return (u - t).norm() <= 1e-9;
    });
    if (!seen) tools.push_back(t);
  }
  double best = std::numeric_limits<double>::infinity();
  std::vector<std::size_t> subset;
  const std::function<void(std::size_t)> visit = [&](std::size_t next) {
    if (!subset.empty()) {
      if (const auto d = simplexDistance(tools, subset, toolMm)) best = std::min(best, *d);
    }
    if (subset.size() == 4) return;
    for (std::size_t i = next; i < tools.size(); ++i) {
      subset.push_back(i);
      visit(i + 1);
      subset.pop_back();
    }
  };
  visit(0);
  return best;
}

}  // namespace volcomp::config
