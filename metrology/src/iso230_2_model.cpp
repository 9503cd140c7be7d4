#include "volcomp/metrology/iso230_2_model.hpp"

namespace volcomp::metrology {

double deviationToComponentSign(const model::Topology& topology, model::Axis axis) noexcept {
  return topology.isWorkpieceSide(axis) ? -1.0 : 1.0;
}

model::TableSpec positioningComponent(const Iso230Result& result, const model::Topology& topology,
                                      model::Axis axis) {
  const double sign = deviationToComponentSign(topology, axis);
  model::TableSpec table;
  table.interpolation = model::Interpolation::Linear;
  for (const TargetFigures& t : result.targets) {
    table.positionsMm.push_back(t.positionMm);
    table.values.push_back(sign * t.meanPositiveMm);
    table.valuesNegative.push_back(sign * t.meanNegativeMm);
  }
  return table;
}

}  // namespace volcomp::metrology
