#include "volcomp/report/model_views.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <variant>

namespace volcomp::report {
namespace {

using model::Axis;
using model::Direction;
using model::MotionKind;

constexpr Axis kAxes[3] = {Axis::X, Axis::Y, Axis::Z};

std::size_t at(Axis axis) {
  return static_cast<std::size_t>(axis);
}

// Roll is the rotation about the axis itself; for X and Y pitch turns about the other
// horizontal axis; Z's two tilts are named by the axis they turn about.
std::string meaningOf(Axis axis, MotionKind kind) {
  const std::string k = axisName(axis);
  const int about = static_cast<int>(kind) - 3;
  switch (kind) {
    case MotionKind::EX:
    case MotionKind::EY:
    case MotionKind::EZ: {
      const auto along = static_cast<Axis>(static_cast<int>(kind));
      if (along == axis) return "positioning of " + k;
      return "straightness of " + k + " in " + axisName(along);
    }
    default:
      break;
  }
  if (about == static_cast<int>(axis)) return "roll of " + k;
  if (axis == Axis::Z) return "tilt of Z about " + axisName(static_cast<Axis>(about));
  if (about == 2) return "yaw of " + k;
  return "pitch of " + k;
}

const char* interpolationText(model::Interpolation interpolation) {
  switch (interpolation) {
    case model::Interpolation::Quadratic:
      return "quadratic elements";
    case model::Interpolation::Cubic:
      return "cubic spline";
    case model::Interpolation::Linear:
      break;
  }
  return "linear";
}

std::string kindOf(const model::ErrorFunctionSpec& spec) {
  if (std::holds_alternative<double>(spec)) return "constant";
  if (const auto* table = std::get_if<model::TableSpec>(&spec)) {
    std::string text = "table (" + std::string(interpolationText(table->interpolation)) + ", " +
                       std::to_string(table->positionsMm.size()) + " nodes";
    if (!table->valuesNegative.empty()) text += ", bidirectional";
    return text + ")";
  }
  const auto& polynomial = std::get<model::PolynomialSpec>(spec);
  return "polynomial (degree " + std::to_string(polynomial.coefficients.size() - 1) + ")";
}

// Evenly spaced positions over [lo, hi], both ends included.
std::vector<double> linspace(double lo, double hi, int n) {
  std::vector<double> out(static_cast<std::size_t>(std::max(n, 2)));
  const double step = (hi - lo) / static_cast<double>(out.size() - 1);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = lo + step * static_cast<double>(i);
  out.back() = hi;
  return out;
}

void widen(std::array<double, 2>& range, bool& any, double lo, double hi) {
  if (!any) {
    range = {lo, hi};
    any = true;
  } else {
    range = {std::min(range[0], lo), std::max(range[1], hi)};
  }
}

}  // namespace

std::string axisName(Axis axis) {
  static const char* const names[3] = {"X", "Y", "Z"};
  return names[at(axis)];
}

WorkingVolume workingVolume(const model::MachineModel& model) {
  WorkingVolume volume;
  const model::MachineModelSpec& spec = model.spec();
  for (Axis axis : kAxes) {
    const std::size_t k = at(axis);
    if (spec.travelMm[k]) {
      volume.rangeMm[k] = *spec.travelMm[k];
      volume.fromTravel[k] = true;
      continue;
    }
    bool any = false;
    for (int kind = 0; kind < 6; ++kind) {
      const auto& f = model.motion(model::motionIndex(axis, static_cast<MotionKind>(kind)));
      if (std::isfinite(f.lowerMm()) && std::isfinite(f.upperMm())) {
        widen(volume.rangeMm[k], any, f.lowerMm(), f.upperMm());
      }
    }
    for (const model::Grid& grid : model.grids()) {
      const auto& g = grid.spec();
      for (std::size_t i = 0; i < g.over.size(); ++i) {
        if (g.over[i] == axis)
          widen(volume.rangeMm[k], any, g.axesMm[i].front(), g.axesMm[i].back());
      }
    }
    if (!any || volume.rangeMm[k][1] <= volume.rangeMm[k][0]) volume.rangeMm[k] = {0.0, 100.0};
  }
  return volume;
}

std::vector<ComponentView> componentViews(const model::MachineModel& model,
                                          const WorkingVolume& volume, int samples) {
  std::vector<ComponentView> views;
  for (Axis axis : kAxes) {
    const auto [lo, hi] = volume.rangeMm[at(axis)];
    const std::vector<double> positions = linspace(lo, hi, samples);
    for (int kind = 0; kind < 6; ++kind) {
      const int index = model::motionIndex(axis, static_cast<MotionKind>(kind));
      const model::ErrorFunction& function = model.motion(index);
      if (function.isZero()) continue;
      ComponentView view;
      view.index = index;
      view.axis = axis;
      view.angular = kind >= 3;
      view.name = model::motionName(index);
      view.meaning = meaningOf(axis, static_cast<MotionKind>(kind));
      view.kind = kindOf(function.spec());
      view.unit = view.angular ? "µrad" : "µm";
      const double scale = view.angular ? kUradPerRad : kUmPerMm;
      const std::vector<Direction> directions =
          function.isBidirectional()
              ? std::vector<Direction>{Direction::Positive, Direction::Negative}
              : std::vector<Direction>{Direction::Unknown};
      const auto* table = std::get_if<model::TableSpec>(&function.spec());
      for (Direction direction : directions) {
        ComponentCurve curve;
        curve.direction = direction;
        curve.positionsMm = positions;
        for (double q : positions) {
          const double value = function.value(q, direction) * scale;
          curve.values.push_back(value);
          view.peakAbs = std::max(view.peakAbs, std::abs(value));
        }
        std::vector<std::array<double, 2>> nodes;
        if (table != nullptr) {
          const std::vector<double>& values =
              direction == Direction::Negative ? table->valuesNegative : table->values;
          for (std::size_t i = 0; i < table->positionsMm.size(); ++i) {
            const double q = table->positionsMm[i];
            if (q >= lo && q <= hi) nodes.push_back({q, values[i] * scale});
          }
        }
        view.curves.push_back(std::move(curve));
        view.nodes.push_back(std::move(nodes));
      }
      views.push_back(std::move(view));
    }
  }
  return views;
}

std::vector<std::pair<std::string, double>> locationErrors(const model::MachineModel& model) {
  std::vector<std::pair<std::string, double>> out;
  for (int i = 0; i < 9; ++i) {
    const double value = model.spec().locationRad[static_cast<std::size_t>(i)];
    if (value != 0.0) out.emplace_back(model::locationName(i), value * kUradPerRad);
  }
  return out;
}

Axis normalAxis(const PlaneSpec& plane) {
  return static_cast<Axis>(3 - static_cast<int>(plane.across) - static_cast<int>(plane.up));
}

ErrorMap errorMap(const model::MachineModel& model, model::Workspace& ws,
                  const WorkingVolume& volume, const PlaneSpec& plane) {
  ErrorMap map;
  map.plane = plane;
  const std::size_t a = at(plane.across), b = at(plane.up), n = at(normalAxis(plane));
  const auto [aLo, aHi] = volume.rangeMm[a];
  const auto [bLo, bHi] = volume.rangeMm[b];
  const double da = (aHi - aLo) / plane.cellsAcross, db = (bHi - bLo) / plane.cellsUp;
  std::vector<Eigen::Vector3d> points;
  for (int j = 0; j < plane.cellsUp; ++j) {
    for (int i = 0; i < plane.cellsAcross; ++i) {
      MapCell cell;
      cell.a0 = aLo + da * i;
      cell.a1 = i + 1 == plane.cellsAcross ? aHi : cell.a0 + da;
      cell.b0 = bLo + db * j;
      cell.b1 = j + 1 == plane.cellsUp ? bHi : cell.b0 + db;
      cell.a = 0.5 * (cell.a0 + cell.a1);
      cell.b = 0.5 * (cell.b0 + cell.b1);
      const int half = plane.arrowEvery / 2;
      cell.arrow =
          plane.arrowEvery <= 1 || (i % plane.arrowEvery == half && j % plane.arrowEvery == half);
      Eigen::Vector3d q;
      q[static_cast<Eigen::Index>(a)] = cell.a;
      q[static_cast<Eigen::Index>(b)] = cell.b;
      q[static_cast<Eigen::Index>(n)] = plane.levelMm;
      points.push_back(q);
      map.cells.push_back(cell);
    }
  }
  std::vector<model::PointError> errors(points.size());
  model::evaluateBatch(model, ws, points, errors);
  for (std::size_t i = 0; i < map.cells.size(); ++i) {
    MapCell& cell = map.cells[i];
    cell.errorUm = errors[i].errorMm * kUmPerMm;
    cell.inPlaneA = cell.errorUm[static_cast<Eigen::Index>(a)];
    cell.inPlaneB = cell.errorUm[static_cast<Eigen::Index>(b)];
    cell.outOfPlane = cell.errorUm[static_cast<Eigen::Index>(n)];
    cell.magnitude = cell.errorUm.norm();
    map.maxMagnitudeUm = std::max(map.maxMagnitudeUm, cell.magnitude);
    map.maxInPlaneUm = std::max(map.maxInPlaneUm, std::hypot(cell.inPlaneA, cell.inPlaneB));
    map.maxAbsOutOfPlaneUm = std::max(map.maxAbsOutOfPlaneUm, std::abs(cell.outOfPlane));
  }
  return map;
}

std::vector<PlaneSpec> reportPlanes(const WorkingVolume& volume, std::span<const double> zLevelsMm,
                                    int resolution) {
  const auto middle = [&](Axis axis) {
    return 0.5 * (volume.rangeMm[at(axis)][0] + volume.rangeMm[at(axis)][1]);
  };
  // Cells of about equal size in both directions; at least 4 along the shorter side.
  const auto plane = [&](Axis across, Axis up, double level) {
    PlaneSpec p;
    p.across = across;
    p.up = up;
    p.levelMm = level;
    const double wa = volume.rangeMm[at(across)][1] - volume.rangeMm[at(across)][0];
    const double wb = volume.rangeMm[at(up)][1] - volume.rangeMm[at(up)][0];
    const double cell = std::max(wa, wb) / resolution;
    p.cellsAcross = std::max(4, static_cast<int>(std::lround(wa / cell)));
    p.cellsUp = std::max(4, static_cast<int>(std::lround(wb / cell)));
    p.arrowEvery = 2;
    return p;
  };
  std::vector<PlaneSpec> planes;
  std::vector<double> levels(zLevelsMm.begin(), zLevelsMm.end());
  if (levels.empty()) {
    const auto [zLo, zHi] = volume.rangeMm[2];
    levels = {zHi, 0.5 * (zLo + zHi), zLo};
  }
  for (double z : levels) planes.push_back(plane(Axis::X, Axis::Y, z));
  planes.push_back(plane(Axis::X, Axis::Z, middle(Axis::Y)));
  planes.push_back(plane(Axis::Y, Axis::Z, middle(Axis::X)));
  return planes;
}

VolumeStatistics volumeStatistics(const model::MachineModel& model, model::Workspace& ws,
                                  const WorkingVolume& volume, int perAxis) {
  std::array<std::vector<double>, 3> grid;
  for (Axis axis : kAxes) {
    grid[at(axis)] = linspace(volume.rangeMm[at(axis)][0], volume.rangeMm[at(axis)][1], perAxis);
  }
  std::vector<Eigen::Vector3d> points;
  for (double x : grid[0])
    for (double y : grid[1])
      for (double z : grid[2]) points.emplace_back(x, y, z);
  std::vector<model::PointError> errors(points.size());
  model::evaluateBatch(model, ws, points, errors);
  VolumeStatistics stats;
  stats.points = static_cast<int>(points.size());
  double sumSquares = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d e = errors[i].errorMm * kUmPerMm;
    const double magnitude = e.norm();
    sumSquares += magnitude * magnitude;
    if (magnitude > stats.maxUm) {
      stats.maxUm = magnitude;
      stats.maxAtMm = points[i];
    }
    for (std::size_t k = 0; k < 3; ++k) {
      stats.maxAbsPerAxisUm[k] =
          std::max(stats.maxAbsPerAxisUm[k], std::abs(e[static_cast<Eigen::Index>(k)]));
    }
    stats.maxAngularUrad =
        std::max(stats.maxAngularUrad, errors[i].angularErrorRad.norm() * kUradPerRad);
  }
  stats.rmsUm =
      std::sqrt(sumSquares / static_cast<double>(std::max<std::size_t>(1, points.size())));
  return stats;
}

}  // namespace volcomp::report
