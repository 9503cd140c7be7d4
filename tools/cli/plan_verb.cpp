#include "plan_verb.hpp"

#include <CLI/CLI.hpp>

#include "cli_support.hpp"

namespace volcomp::cli {

CLI::App* addPlanVerb(CLI::App& app, PlanArguments& arguments) {
  calibration::PlanVerbOptions& options = arguments.options;
  CLI::App* verb = app.add_subcommand(
      "plan",
      "Plan a calibration measurement: choose the N points (and tool offsets) among candidates "
      "that identify the template's parameters best (D-optimal on what the candidates can "
      "identify, or I-optimal on the mean prediction variance), and print the sigma "
      "each parameter and the predicted error will have for a given instrument noise, before "
      "anyone measures.");
  verb->add_option("template", options.templatePath, "Calibration template (volcomp-model/1)")
      ->required();
  CLI::Option* candidates = verb->add_option(
      "--candidates", options.candidatesPath,
      "Candidate points: CSV x,y,z [,tx,ty,tz] [,direction] (mm; without tool columns each "
      "point is a candidate with every tool of --tools)");
  CLI::Option* grid =
      verb->add_option("--grid", arguments.grid,
                       "Candidates on a grid of NX,NY,NZ nodes over the template's travel");
  candidates->excludes(grid);
  verb->add_option("--points", options.points, "Number of points N to measure")
      ->required()
      ->check(CLI::PositiveNumber);
  verb->add_option("--tools", arguments.tools,
                   "Tool offsets to choose from, \"TX,TY,TZ;TX,TY,TZ\" (mm); default the "
                   "template's tool");
  verb->add_option("--noise", options.noiseMm,
                   "Standard deviation of the instrument per coordinate (mm)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  verb->add_option("--rank-tol", options.rankTolerance,
                   "Relative singular-value threshold of the rank decision (as calibrate)")
      ->capture_default_str()
      ->check(CLI::Range(1e-16, 0.5));
  verb->add_option("--criterion", options.criterion,
                   "d: D-optimal (volume of the parameters' confidence region); i: then an "
                   "I-optimal exchange on the mean prediction variance over the candidates "
                   "(docs/calibration.md gives figures for both)")
      ->capture_default_str()
      ->check(CLI::IsMember({"d", "i"}));
  verb->add_option("--out", options.outPath,
                   "Write the chosen points as CSV x,y,z,tx,ty,tz (mm), tool by tool");
  verb->add_option("--report", options.reportPath, "Write the plan as JSON");
  verb->add_option("--angle-unit", options.angleUnit, "Angles on screen: urad or arcsec")
      ->capture_default_str()
      ->check(CLI::IsMember({"urad", "arcsec"}));
  verb->footer(
      "Exit status: 0 planned (a rank-deficient design is reported, not an error); 2 bad "
      "arguments or a bad template/CSV.");
  return verb;
}

void resolvePlanArguments(PlanArguments& arguments) {
  calibration::PlanVerbOptions& options = arguments.options;
  if (options.candidatesPath.empty()) {
    if (arguments.grid.empty()) throw UsageError("plan: give --candidates FILE or --grid NX,NY,NZ");
    const std::vector<double> nodes = parseNumberList(arguments.grid, "--grid NX,NY,NZ", 3);
    for (std::size_t axis = 0; axis < 3; ++axis) {
      const double n = nodes[axis];
      if (!(n >= 1.0 && n <= 1000.0 && n == static_cast<int>(n))) {
        throw UsageError("--grid: expected three whole numbers of nodes 1..1000, got " +
                         arguments.grid);
      }
      options.grid[axis] = static_cast<int>(n);
    }
  }
  std::string_view rest = arguments.tools;
  while (!rest.empty()) {
    const std::size_t end = rest.find(';');
    const std::vector<double> t =
        parseNumberList(rest.substr(0, end), "--tools TX,TY,TZ;TX,TY,TZ (mm)", 3);
    options.toolsMm.emplace_back(t[0], t[1], t[2]);
    rest = end == std::string_view::npos ? std::string_view{} : rest.substr(end + 1);
  }
}

}  // namespace volcomp::cli
