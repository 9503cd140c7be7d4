#include "volcomp/model/grid.hpp"

#include <cmath>
#include <string>
#include <utility>

#include "piecewise.hpp"

namespace volcomp::model {

Grid::Grid(GridSpec spec) : spec_(std::move(spec)) {
  if (spec_.component < 0 || spec_.component > 2) {
    throw ModelError("grid: component must be 0, 1 or 2 (EX, EY, EZ), got " +
                     std::to_string(spec_.component));
  }
  const std::size_t dims = spec_.over.size();
  if (dims != 2 && dims != 3) {
    throw ModelError("grid: must be over 2 or 3 axes, got " + std::to_string(dims));
  }
  for (std::size_t a = 0; a < dims; ++a) {
    if (static_cast<int>(spec_.over[a]) > 2) throw ModelError("grid: unknown axis in over");
    for (std::size_t b = 0; b < a; ++b) {
      if (spec_.over[a] == spec_.over[b]) throw ModelError("grid: an axis appears twice in over");
    }
  }
  if (spec_.axesMm.size() != dims) {
    throw ModelError("grid: " + std::to_string(spec_.axesMm.size()) + " node lists for " +
                     std::to_string(dims) + " axes");
  }
  std::size_t expected = 1;
  for (std::size_t a = 0; a < dims; ++a) {
    const std::vector<double>& nodes = spec_.axesMm[a];
    const std::string where = "grid: axes[" + std::to_string(a) + "]";
    if (nodes.size() < 2) throw ModelError(where + " needs at least 2 nodes");
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      if (!std::isfinite(nodes[i])) {
        throw ModelError(where + "[" + std::to_string(i) + "] is not a finite number");
      }
      if (i > 0 && !(nodes[i] > nodes[i - 1])) {
        throw ModelError(where + " must be strictly increasing (at index " + std::to_string(i) +
                         ")");
      }
    }
    uniform_[a] = detail::isUniform(nodes);
    expected *= nodes.size();
  }
  if (spec_.valuesMm.size() != expected) {
    throw ModelError("grid: values has " + std::to_string(spec_.valuesMm.size()) +
                     " entries, expected " + std::to_string(expected));
  }
  for (std::size_t i = 0; i < expected; ++i) {
    if (!std::isfinite(spec_.valuesMm[i])) {
      throw ModelError("grid: values (flattened index " + std::to_string(i) +
                       ") is not a finite number");
    }
  }
}

double Grid::valueMm(const double* qMm) const noexcept {
  detail::TableLocation at[3];
  std::size_t count[3] = {1, 1, 1};
  const std::size_t dims = spec_.over.size();
  for (std::size_t a = 0; a < dims; ++a) {
    const detail::TableAxis axis = detail::makeTableAxis(spec_.axesMm[a], uniform_[a]);
    at[a] = axis.locate(qMm[static_cast<int>(spec_.over[a])]);
    count[a] = spec_.axesMm[a].size();
  }
  const double* v = spec_.valuesMm.data();
  const std::size_t i = static_cast<std::size_t>(at[0].index);
  const std::size_t j = static_cast<std::size_t>(at[1].index);
  const double t = at[0].t, u = at[1].t;
  if (dims == 2) {
    const std::size_t n1 = count[1];
    const double* row0 = v + i * n1 + j;
    const double* row1 = row0 + n1;
    return (1 - t) * ((1 - u) * row0[0] + u * row0[1]) + t * ((1 - u) * row1[0] + u * row1[1]);
  }
  const std::size_t n1 = count[1], n2 = count[2];
  const std::size_t k = static_cast<std::size_t>(at[2].index);
  const double w = at[2].t;
  // Corner (di, dj, dk) sits at ((i + di) n1 + j + dj) n2 + k + dk.
  auto plane = [&](std::size_t ii) {
    const double* p0 = v + (ii * n1 + j) * n2 + k;
    const double* p1 = p0 + n2;
    return (1 - u) * ((1 - w) * p0[0] + w * p0[1]) + u * ((1 - w) * p1[0] + w * p1[1]);
  };
  return (1 - t) * plane(i) + t * plane(i + 1);
}

}  // namespace volcomp::model
