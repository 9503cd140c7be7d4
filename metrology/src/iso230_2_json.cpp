#include "volcomp/metrology/iso230_2_json.hpp"

#include "volcomp/metrology/axis_tables.hpp"

namespace volcomp::metrology {

nlohmann::json toJson(const Iso230Result& result) {
  using nlohmann::json;
  json targets = json::array();
  for (std::size_t i = 0; i < result.targets.size(); ++i) {
    const TargetFigures& t = result.targets[i];
    targets.push_back({
        {"index", i + 1},
        {"position", t.positionMm},
        {"deviations_positive", t.deviationsPositiveMm},
        {"deviations_negative", t.deviationsNegativeMm},
        {"mean_positive", t.meanPositiveMm},
        {"mean_negative", t.meanNegativeMm},
        {"mean_bidirectional", t.meanBidirectionalMm},
        {"reversal", t.reversalMm},
        {"s_positive", t.sPositiveMm},
        {"s_negative", t.sNegativeMm},
        {"repeatability_positive", t.repeatabilityPositiveMm},
        {"repeatability_negative", t.repeatabilityNegativeMm},
        {"repeatability_bidirectional", t.repeatabilityBidirectionalMm},
    });
  }
  const AxisFigures& a = result.figures;
  json axis = {
      {"reversal", a.reversalMm},
      {"mean_reversal", a.meanReversalMm},
      {"repeatability_positive", a.repeatabilityPositiveMm},
      {"repeatability_negative", a.repeatabilityNegativeMm},
      {"repeatability_bidirectional", a.repeatabilityBidirectionalMm},
      {"systematic_positive", a.systematicPositiveMm},
      {"systematic_negative", a.systematicNegativeMm},
      {"systematic_bidirectional", a.systematicBidirectionalMm},
      {"mean_bidirectional_range", a.meanBidirectionalRangeMm},
      {"accuracy_positive", a.accuracyPositiveMm},
      {"accuracy_negative", a.accuracyNegativeMm},
      {"accuracy_bidirectional", a.accuracyBidirectionalMm},
  };
  return {
      {"format", kIso230JsonFormat},
      {"standard", "ISO 230-2:2014"},
      {"source", result.source},
      {"axis", result.axis ? json(axisName(*result.axis)) : json(nullptr)},
      {"units", {{"position", "mm"}, {"deviation", "mm"}}},
      {"runs_positive", result.runsPositive},
      {"runs_negative", result.runsNegative},
      {"targets", std::move(targets)},
      {"axis_figures", std::move(axis)},
      {"warnings", result.warnings},
  };
}

}  // namespace volcomp::metrology
