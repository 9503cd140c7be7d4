#include "volcomp/config/model_plausibility.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <variant>
#include <vector>

#include "volcomp/config/config_error.hpp"
#include "volcomp/config/display_units.hpp"
#include "volcomp/model/topology.hpp"

namespace volcomp::config {
namespace {

constexpr const char* kAxes = "XYZ";
// Samples of one component along its axis (besides every table node): enough to find the
// overshoot of a natural spline or the extremum of a polynomial to well under 0.1 %.
constexpr int kComponentSamples = 2001;

std::string pointText(const Eigen::Vector3d& q) {
  return "(" + significant(q.x()) + ", " + significant(q.y()) + ", " + significant(q.z()) + ") mm";
}

// The range to sample on each axis: its travel, else what its tables and grids span.
void chooseRanges(const model::MachineModelSpec& spec, ModelAssessment& a) {
  for (int axis = 0; axis < 3; ++axis) {
    if (spec.travelMm[axis]) {
      a.rangeMm[axis] = *spec.travelMm[axis];
      a.rangeIsTravel[axis] = true;
      continue;
    }
    double lo = std::numeric_limits<double>::infinity();
    double hi = -lo;
    for (int kind = 0; kind < 6; ++kind) {
      if (const auto* t = std::get_if<model::TableSpec>(&spec.motion[axis * 6 + kind])) {
        lo = std::min(lo, t->positionsMm.front());
        hi = std::max(hi, t->positionsMm.back());
      }
    }
    for (const model::GridSpec& g : spec.grids) {
      for (std::size_t l = 0; l < g.over.size(); ++l) {
        if (static_cast<int>(g.over[l]) != axis) continue;
        lo = std::min(lo, g.axesMm[l].front());
        hi = std::max(hi, g.axesMm[l].back());
      }
    }
    a.rangeMm[axis] = lo <= hi ? std::array<double, 2>{lo, hi} : std::array<double, 2>{0.0, 0.0};
  }
}

std::vector<double> axisSamples(const std::array<double, 2>& range, int count) {
  if (range[1] <= range[0]) return {range[0]};
  std::vector<double> q(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) q[i] = range[0] + (range[1] - range[0]) * i / (count - 1);
  return q;
}

void assessComponents(const model::MachineModel& model, ModelAssessment& a) {
  const model::MachineModelSpec& spec = model.spec();
  for (int i = 0; i < 18; ++i) {
    const int axis = i / 6;
    std::vector<double> q = axisSamples(a.rangeMm[axis], kComponentSamples);
    if (const auto* t = std::get_if<model::TableSpec>(&spec.motion[i])) {
      q.insert(q.end(), t->positionsMm.begin(), t->positionsMm.end());
    }
    const model::ErrorFunction& f = model.motion(i);
    for (double x : q) {
      // A table is held at its end values; outside the range nothing is evaluated.
      const double clamped = std::clamp(x, a.rangeMm[axis][0], a.rangeMm[axis][1]);
      for (const model::Direction d : {model::Direction::Positive, model::Direction::Negative}) {
        const double v = std::abs(f.value(clamped, d));
        if (!(v <= a.motionPeak[i])) {  // NaN counts as the largest value
          a.motionPeak[i] = v;
          a.motionPeakAtMm[i] = clamped;
        }
      }
    }
  }
  for (int i = 0; i < 9; ++i) a.locationPeakRad[i] = std::abs(spec.locationRad[i]);
  for (const model::GridSpec& g : spec.grids) {
    double peak = 0.0;
    for (double v : g.valuesMm) peak = std::max(peak, std::abs(v));
    a.gridPeakMm.push_back(peak);
  }
}

void assessVolume(const model::MachineModel& model, ModelAssessment& a) {
  std::array<std::vector<double>, 3> axes;
  for (int k = 0; k < 3; ++k) {
    axes[k] = axisSamples(a.rangeMm[k], kPlausibilityGridPoints);
    a.gridPoints[k] = static_cast<int>(axes[k].size());
  }
  std::vector<Eigen::Vector3d> points;
  points.reserve(axes[0].size() * axes[1].size() * axes[2].size());
  for (double x : axes[0])
    for (double y : axes[1])
      for (double z : axes[2]) points.emplace_back(x, y, z);
  a.points = points.size();

  model::Workspace ws;
  std::vector<model::PointError> errors(points.size());
  std::vector<model::OffsetSolution> offsets(points.size());
  for (const model::Direction d : {model::Direction::Positive, model::Direction::Negative}) {
    const std::vector<model::Directions> directions(points.size(), model::Directions{d, d, d});
    model::evaluateBatch(model, ws, points, errors, model::EvalMode::Exact, directions);
    model::solveOffsetBatch(model, ws, points, offsets, directions);
    for (std::size_t i = 0; i < points.size(); ++i) {
      const model::PointError& e = errors[i];
      const model::OffsetSolution& o = offsets[i];
      if (!e.errorMm.allFinite() || !e.angularErrorRad.allFinite() || !o.offsetMm.allFinite()) {
        if (!a.nonFiniteAtMm) a.nonFiniteAtMm = points[i];
        continue;
      }
      if (!o.converged && !a.notConvergedAtMm) a.notConvergedAtMm = points[i];
      const double norm = e.errorMm.norm();
      if (norm > a.peakErrorMm) {
        a.peakErrorMm = norm;
        a.peakErrorAtMm = points[i];
      }
      a.peakAngleRad = std::max(a.peakAngleRad, e.angularErrorRad.norm());
      for (int k = 0; k < 3; ++k) {
        if (std::abs(o.offsetMm[k]) > a.peakOffsetMm[k]) {
          a.peakOffsetMm[k] = std::abs(o.offsetMm[k]);
          a.peakOffsetAtMm[k] = points[i];
        }
      }
    }
  }
}

// "mm instead of um" is the mistake that makes values 1000 times too large; say so when it fits.
std::string unitHint(const ModelDocument& doc, bool translation, double peak, double limit) {
  const AngleUnit angleUnit = doc.units.angle;
  std::string hint;
  if (translation && doc.units.length == LengthUnit::Millimetre && peak < 1000.0 * limit) {
    hint = " Were values in um entered as mm? Then set \"error_units\": {\"length\": \"um\"}.";
  } else if (!translation &&
             (angleUnit == AngleUnit::Radian || angleUnit == AngleUnit::Milliradian) &&
             peak < 1e6 * limit) {
    hint = std::string(" Were values in urad entered as ") + unitName(angleUnit) +
           "? Then set \"error_units\": {\"angle\": \"urad\"}.";
  }
  return hint;
}

}  // namespace

ModelAssessment assessModel(const model::MachineModel& model) {
  ModelAssessment a;
  chooseRanges(model.spec(), a);
  assessComponents(model, a);
  assessVolume(model, a);
  return a;
}

void requirePlausible(const ModelDocument& doc, const ModelAssessment& a,
                      const std::optional<OffsetBound>& bound, bool requireUnits) {
  const auto* spec = std::get_if<model::MachineModelSpec>(&doc.spec);
  if (spec == nullptr) return;
  const PlausibilityLimits& limits = doc.plausibility;
  if (requireUnits && !doc.unitsStated) {
    throw ConfigError(doc.file, "error_units",
                      "missing: state the units of the error values, e.g. \"error_units\": "
                      "{\"length\": \"um\", \"angle\": \"urad\"} (without it every value is read "
                      "as mm and rad, and a laser reading typed in um becomes 1000 times too "
                      "large)");
  }
  const std::string limitText =
      limits.stated ? " (the file's \"plausibility\" limit)"
                    : " (the default plausibility limit: \"plausibility\" in the file raises it)";
  for (int i = 0; i < 18; ++i) {
    const bool translation = i % 6 < 3;
    const double limit = translation ? limits.maxLengthMm : limits.maxAngleRad;
    const double peak = a.motionPeak[i];
    if (peak <= limit) continue;
    const double factor = translation ? doc.units.lengthToMm() : doc.units.angleToRad();
    const std::string unit = translation ? unitName(doc.units.length) : unitName(doc.units.angle);
    throw ConfigError(
        doc.file, "components." + model::motionName(i),
        "implausible for a machine tool: |value| reaches " + significant(peak / factor) + " " +
            unit + " (" +
            (translation ? micrometres(peak) : angle(peak, AngleDisplay::Microradian)) + ") at " +
            kAxes[i / 6] + " = " + significant(a.motionPeakAtMm[i]) + " mm, beyond " +
            (translation ? micrometres(limit) : angle(limit, AngleDisplay::Microradian)) +
            limitText + "." + unitHint(doc, translation, peak / factor, limit / factor));
  }
  for (int i = 0; i < 9; ++i) {
    if (a.locationPeakRad[i] <= limits.maxAngleRad) continue;
    throw ConfigError(doc.file, "components." + model::locationName(i),
                      "implausible for a machine tool: " +
                          angle(a.locationPeakRad[i], AngleDisplay::Microradian) + ", beyond " +
                          angle(limits.maxAngleRad, AngleDisplay::Microradian) + limitText + "." +
                          unitHint(doc, false, a.locationPeakRad[i] / doc.units.angleToRad(),
                                   limits.maxAngleRad / doc.units.angleToRad()));
  }
  for (std::size_t g = 0; g < a.gridPeakMm.size(); ++g) {
    if (a.gridPeakMm[g] <= limits.maxLengthMm) continue;
    throw ConfigError(doc.file, "grids[" + std::to_string(g) + "].values",
                      "implausible for a machine tool: |value| reaches " +
                          micrometres(a.gridPeakMm[g]) + ", beyond " +
                          micrometres(limits.maxLengthMm) + limitText + "." +
                          unitHint(doc, true, a.gridPeakMm[g] / doc.units.lengthToMm(),
                                   limits.maxLengthMm / doc.units.lengthToMm()));
  }
  if (a.nonFiniteAtMm) {
    throw ConfigError(doc.file, "",
                      "the model evaluates to NaN or infinity at " + pointText(*a.nonFiniteAtMm) +
                          ": it cannot compensate a machine");
  }
  if (a.peakErrorMm > limits.maxLengthMm) {
    throw ConfigError(doc.file, "",
                      "implausible for a machine tool: the volumetric error reaches " +
                          micrometres(a.peakErrorMm) + " at " + pointText(a.peakErrorAtMm) +
                          ", beyond " + micrometres(limits.maxLengthMm) + limitText +
                          "; every component alone is within it: check the angles and the "
                          "tool length, which multiply them.");
  }
  if (a.notConvergedAtMm) {
    throw ConfigError(doc.file, "",
                      "the compensation offset does not converge at " +
                          pointText(*a.notConvergedAtMm) +
                          ": an error that changes faster than the axis moves cannot be "
                          "compensated (check the table values and their units)");
  }
  if (!bound) return;
  for (int k = 0; k < 3; ++k) {
    if (a.peakOffsetMm[k] <= bound->maxOffsetMm[k]) continue;
    throw ConfigError(
        doc.file, "",
        std::string("the model asks for an offset of ") + micrometres(a.peakOffsetMm[k]) + " on " +
            kAxes[k] + " at " + pointText(a.peakOffsetAtMm[k]) + ", beyond " +
            micrometres(bound->maxOffsetMm[k]) + " (" + bound->source +
            "): the limiter would clamp it there and miscompensate. Check the model's values and "
            "units, or raise max_offset_mm if the machine needs it");
  }
}

std::optional<ModelAssessment> checkPlausible(const ModelDocument& doc,
                                              const std::optional<OffsetBound>& bound) {
  const auto* spec = std::get_if<model::MachineModelSpec>(&doc.spec);
  if (spec == nullptr) return std::nullopt;
  const model::MachineModel model(*spec);
  ModelAssessment assessment = assessModel(model);
  requirePlausible(doc, assessment, bound);
  return assessment;
}

}  // namespace volcomp::config
