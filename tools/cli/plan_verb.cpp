#include "plan_verb.hpp"

#include <CLI/CLI.hpp>

#include "calibration_files.hpp"
#include "cli_support.hpp"
#include "volcomp/calibration/calibrate.hpp"
#include "volcomp/config/config_error.hpp"
#include "volcomp/config/csv_table.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/output/output_file.hpp"

namespace volcomp::cli {
namespace {

using config::ConfigError;
using Json = nlohmann::json;
using namespace calibration;

std::vector<PlanCandidate> readCandidates(const std::string& path,
                                          const std::vector<Eigen::Vector3d>& tools,
                                          bool& hasDirection) {
  std::ifstream input = config::CsvReader::open(path);
  config::CsvReader csv(input, path, config::positionsSchema());
  const int direction = csv.column("direction");
  hasDirection = direction >= 0;
  std::vector<PlanCandidate> positions;
  while (csv.next()) {
    PlanCandidate c;
    c.qMm = {csv.number("x"), csv.number("y"), csv.number("z")};
    if (csv.has("tx")) c.toolMm = {csv.number("tx"), csv.number("ty"), csv.number("tz")};
    if (direction >= 0) c.directions = csv.directions(direction);
    c.line = static_cast<int>(csv.line());
    positions.push_back(c);
  }
  if (positions.empty()) throw ConfigError(path, "", "no candidate rows after the header");
  if (csv.has("tx")) return positions;
  std::vector<PlanCandidate> candidates;
  for (const Eigen::Vector3d& tool : tools) {
    for (PlanCandidate c : positions) {
      c.toolMm = tool;
      candidates.push_back(c);
    }
  }
  return candidates;
}

std::string directionText(const model::Directions& d) {
  std::string text;
  for (model::Direction a : d) {
    text += a == model::Direction::Positive ? '+' : a == model::Direction::Negative ? '-' : '0';
  }
  return text;
}

void writePlan(const std::string& path, const std::vector<PlanCandidate>& candidates,
               std::vector<std::size_t> chosen, bool withDirection,
               const std::vector<std::filesystem::path>& inputs) {
  // In the order a measurement runs: tool by tool, then along x, y, z.
  std::sort(chosen.begin(), chosen.end(), [&](std::size_t a, std::size_t b) {
    const PlanCandidate& p = candidates[a];
    const PlanCandidate& q = candidates[b];
    const auto key = [](const PlanCandidate& c) {
      return std::make_tuple(c.toolMm.x(), c.toolMm.y(), c.toolMm.z(), c.qMm.x(), c.qMm.y(),
                             c.qMm.z());
    };
    return key(p) < key(q);
  });
  std::ostringstream file;
  file.precision(17);
  file << "x,y,z,tx,ty,tz" << (withDirection ? ",direction" : "") << "\n";
  for (std::size_t i : chosen) {
    const PlanCandidate& c = candidates[i];
    file << c.qMm.x() << ',' << c.qMm.y() << ',' << c.qMm.z() << ',' << c.toolMm.x() << ','
         << c.toolMm.y() << ',' << c.toolMm.z();
    if (withDirection) file << ',' << directionText(c.directions);
    file << '\n';
  }
  output::writeOutputFile(path, file.str(), inputs);
}

std::string criterionText(PlanCriterion criterion) {
  return criterion == PlanCriterion::I
             ? "I-optimal (mean prediction variance over the candidates), from the D-optimal "
               "design"
             : "D-optimal on the identifiable subspace";
}

Json planJson(const PlanVerbOptions& options, const PlanResult& plan,
              const std::vector<PlanCandidate>& candidates,
              const std::vector<ParameterInfo>& info) {
  const FitStatistics& st = plan.statistics;
  Json parameters = Json::array();
  for (std::size_t j = 0; j < info.size(); ++j) {
    const double s = st.standardDeviation(static_cast<Eigen::Index>(j));
    parameters.push_back({{"name", info[j].name},
                          {"unit", info[j].unit},
                          {"std", std::isfinite(s) ? Json(s * info[j].toDisplay) : Json(nullptr)},
                          {"identifiable", static_cast<bool>(st.identifiable[j])}});
  }
  Json combinations = Json::array();
  for (const Combination& c : st.unidentifiable) {
    Json names = Json::array();
    for (const auto& [j, coefficient] : c.terms)
      names.push_back(info[static_cast<std::size_t>(j)].name);
    combinations.push_back(
        {{"parameters", names},
         {"description", c.description},
         {"physical", physicalDescription(c, info, false, AngleDisplay::Microradian)}});
  }
  Json selected = Json::array();
  for (std::size_t i : plan.selected) {
    const PlanCandidate& c = candidates[i];
    Json point{{"position_mm", {c.qMm.x(), c.qMm.y(), c.qMm.z()}},
               {"tool_mm", {c.toolMm.x(), c.toolMm.y(), c.toolMm.z()}}};
    if (c.line > 0) point["line"] = c.line;
    selected.push_back(point);
  }
  return Json{{"format", "volcomp-plan-report/1"},
              {"template", options.templatePath},
              {"criterion", criterionText(plan.criterion)},
              {"points", plan.selected.size()},
              {"candidates", candidates.size()},
              {"candidate_rank", plan.candidateRank},
              {"rank", st.rank},
              {"parameter_count", st.parameterCount},
              {"rank_deficient", st.rank < plan.candidateRank},
              {"noise_mm", options.plan.noiseMm},
              {"log_det", plan.logDeterminant},
              {"exchanges", plan.exchanges},
              {"prediction",
               {{"coverage_factor", kCoverageFactor},
                {"where", "candidates"},
                {"max_std_mm", plan.maxStdMm},
                {"rms_std_mm", plan.rmsStdMm},
                {"max_expanded_mm", kCoverageFactor * plan.maxStdMm},
                {"undetermined", plan.undetermined}}},
              {"parameters", parameters},
              {"unidentifiable", combinations},
              {"selected", selected}};
}

}  // namespace

CLI::App* addPlanVerb(CLI::App& app, PlanArguments& arguments) {
  PlanVerbOptions& options = arguments.options;
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
  verb->add_option("--points", options.plan.points, "Number of points N to measure")
      ->required()
      ->check(CLI::PositiveNumber);
  verb->add_option("--tools", arguments.tools,
                   "Tool offsets to choose from, \"TX,TY,TZ;TX,TY,TZ\" (mm); default the "
                   "template's tool");
  verb->add_option("--noise", options.plan.noiseMm,
                   "Standard deviation of the instrument per coordinate (mm)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  verb->add_option("--rank-tol", options.plan.rankTolerance,
                   "Relative singular-value threshold of the rank decision (as calibrate)")
      ->capture_default_str()
      ->check(CLI::Range(1e-16, 0.5));
  verb->add_option("--criterion", arguments.criterion,
                   "d: D-optimal (volume of the parameters' confidence region); i: then an "
                   "I-optimal exchange on the mean prediction variance over the candidates "
                   "(docs/calibration.md gives figures for both)")
      ->capture_default_str()
      ->check(CLI::IsMember({"d", "i"}));
  verb->add_option("--out", options.outPath,
                   "Write the chosen points as CSV x,y,z,tx,ty,tz (mm), tool by tool");
  verb->add_option("--report", options.reportPath, "Write the plan as JSON");
  verb->add_option("--angle-unit", arguments.angleUnit, "Angles on screen: urad or arcsec")
      ->capture_default_str()
      ->check(CLI::IsMember({"urad", "arcsec"}));
  verb->footer(
      "Exit status: 0 planned (a rank-deficient design is reported, not an error); 2 bad "
      "arguments or a bad template/CSV.");
  return verb;
}

void resolvePlanArguments(PlanArguments& arguments) {
  PlanVerbOptions& options = arguments.options;
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
  if (arguments.criterion == "d") {
    options.plan.criterion = calibration::PlanCriterion::D;
  } else if (arguments.criterion == "i") {
    options.plan.criterion = calibration::PlanCriterion::I;
  } else {
    throw config::ConfigError(kCommandLine, "--criterion", "expected d or i");
  }
  options.angleDisplay = angleDisplayFromText(arguments.angleUnit);
}

namespace {

const char* optionOf(PlanOptions::Field field) {
  switch (field) {
    case PlanOptions::Field::Points:
      return "--points";
    case PlanOptions::Field::Noise:
      return "--noise";
    case PlanOptions::Field::RankTolerance:
      return "--rank-tol";
    case PlanOptions::Field::MaxPasses:
      break;
  }
  return "passes";
}

}  // namespace

int runPlan(const PlanVerbOptions& options, std::ostream& out) {
  std::string invalid;
  PlanOptions::Field field{};
  if (!options.plan.isValid(&invalid, &field)) {
    throw ConfigError(kCommandLine, optionOf(field), invalid);
  }
  const PlanCriterion criterion = options.plan.criterion;
  config::ParseOptions parseOptions;
  parseOptions.allowIdentify = true;
  const config::ModelDocument document = config::loadModelFile(options.templatePath, parseOptions);
  const auto* spec = std::get_if<model::MachineModelSpec>(&document.spec);
  if (spec == nullptr) {
    throw ConfigError(options.templatePath, "chain",
                      "planning is for 3-axis templates (a D-H chain has no travel grid)");
  }
  requireSomethingToIdentify(document);
  const std::vector<Eigen::Vector3d> tools =
      options.toolsMm.empty() ? std::vector<Eigen::Vector3d>{spec->toolMm} : options.toolsMm;
  bool withDirection = false;
  std::vector<PlanCandidate> candidates;
  if (!options.candidatesPath.empty()) {
    candidates = readCandidates(options.candidatesPath, tools, withDirection);
  } else {
    try {
      candidates = gridCandidates(*spec, options.grid, tools);
    } catch (const std::invalid_argument& e) {
      throw ConfigError(options.templatePath, "travel", e.what());
    }
  }
  if (static_cast<std::size_t>(options.plan.points) > candidates.size()) {
    throw ConfigError(
        kCommandLine, "--points",
        "expected at most the number of candidates (" + std::to_string(candidates.size()) + ")");
  }
  out << "planning " << options.plan.points << " of " << candidates.size() << " candidates ("
      << criterionText(criterion) << ")" << std::endl;
  PlanOptions planOptions = options.plan;
  std::ostream& progress = options.progress != nullptr ? *options.progress : out;
  planOptions.progress = [&progress](const std::string& line) {
    progress << "  " << line << std::endl;
  };
  const PlanResult plan = planMeasurements(document, candidates, planOptions);

  const auto problem = makeIdentificationProblem(document, designMeasurements(candidates, {0}));
  const std::vector<ParameterInfo>& info = problem->parameterInfo();
  const AngleDisplay angles = options.angleDisplay;
  const FitStatistics& st = plan.statistics;
  out << "\ndesign: " << plan.selected.size() << " points, rank " << st.rank << " of "
      << st.parameterCount << " (all candidates together reach " << plan.candidateRank << ")"
      << (st.rank < plan.candidateRank ? ": RANK DEFICIENT, more points are needed" : "") << "\n";
  out << "expected with an instrument noise of " << significant(options.plan.noiseMm * 1e3, 3)
      << " µm per coordinate:\n"
      << "  predicted error over the candidates, U = k sigma with k = "
      << significant(kCoverageFactor, 2) << ": max " << significant(2.0 * plan.maxStdMm * 1e3, 3)
      << " µm, rms " << significant(2.0 * plan.rmsStdMm * 1e3, 3) << " µm";
  if (plan.undetermined > 0) out << " (" << plan.undetermined << " candidates not determined)";
  out << "\n\n";
  std::size_t width = 9;
  for (const ParameterInfo& p : info) width = std::max(width, p.name.size());
  out << std::left << std::setw(static_cast<int>(width)) << "parameter" << std::right
      << std::setw(11) << "sigma"
      << "  unit\n";
  for (std::size_t j = 0; j < info.size(); ++j) {
    const DisplayUnit unit = screenUnit(info[j], angles);
    out << std::left << std::setw(static_cast<int>(width)) << info[j].name << std::right
        << std::setw(11)
        << significant(st.standardDeviation(static_cast<Eigen::Index>(j)) * unit.factor, 3) << "  "
        << unit.unit << (st.identifiable[j] ? "" : "  not identifiable") << "\n";
  }
  if (!st.unidentifiable.empty()) {
    out << "\nnot identifiable with this design:\n";
    for (const Combination& c : st.unidentifiable) out << "  - " << c.description << "\n";
  }
  std::vector<std::filesystem::path> inputs{options.templatePath};
  if (!options.candidatesPath.empty()) inputs.emplace_back(options.candidatesPath);
  if (!options.outPath.empty()) {
    writePlan(options.outPath, candidates, plan.selected, withDirection, inputs);
  }
  if (!options.reportPath.empty()) {
    writeJsonFile(options.reportPath, planJson(options, plan, candidates, info), inputs);
  }
  if (!options.outPath.empty()) out << "\nplan written to " << options.outPath;
  if (!options.reportPath.empty())
    out << (options.outPath.empty() ? "\n" : ", ") << "report to " << options.reportPath;
  out << std::endl;
  return 0;
}

}  // namespace volcomp::cli
