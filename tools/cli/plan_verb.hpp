#pragma once
// `volcomp plan TEMPLATE.json (--candidates C.csv | --grid NX,NY,NZ) --points N ...`: argument
// parsing only; the work is volcomp::calibration::runPlan.

#include <string>

#include <CLI/App.hpp>

#include "volcomp/calibration/run_plan.hpp"

namespace volcomp::cli {

struct PlanArguments {
  calibration::PlanVerbOptions options;
  std::string grid;   ///< "NX,NY,NZ"
  std::string tools;  ///< "TX,TY,TZ;TX,TY,TZ"
};

CLI::App* addPlanVerb(CLI::App& app, PlanArguments& arguments);

/// Fills arguments.options.grid and .toolsMm from the text options; throws UsageError.
void resolvePlanArguments(PlanArguments& arguments);

}  // namespace volcomp::cli
