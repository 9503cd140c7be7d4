// volcomp: command-line access to volumetric error models (verbs `eval`, `check`, `calibrate`,
// `plan`, `iso230-2`, `export`, `report`, `nc`).
// Errors are caught here only: one line on stderr, exit status 2 for bad arguments or files.

#include <exception>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "calibrate_verb.hpp"
#include "check_verb.hpp"
#include "cli_support.hpp"
#include "eval_verb.hpp"
#include "export_verb.hpp"
#include "iso230_2_verb.hpp"
#include "nc_verb.hpp"
#include "plan_verb.hpp"
#include "report_verb.hpp"
#include "volcomp/config/config_error.hpp"
#include "volcomp/config/printable.hpp"
#include "volcomp/model/types.hpp"
#include "volcomp/nc/nc_error.hpp"
#include "volcomp/output/output_file.hpp"

namespace {

// The contract is one line on stderr; some CLI11 messages span several. Messages quote the
// arguments and files they refer to: whatever those hold is shown escaped and bounded, never
// passed to the terminal as it is.
std::string oneLine(std::string text) {
  for (char& c : text) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return volcomp::config::printable(text, 4096);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace volcomp::cli;
  CLI::App app{
      "volcomp: volumetric error models of 3-axis machine tools (ISO 230-1 components, grids, "
      "D-H chains). Units: mm and rad unless stated.",
      "volcomp"};
  app.set_version_flag("--version", std::string("volcomp ") + VOLCOMP_VERSION);
  app.require_subcommand(1);
  app.footer(
      "Exit status: 0 success; 2 bad arguments or bad file; 3 (eval, nc) an offset did not "
      "converge. Run 'volcomp VERB --help' for a verb's options.");
  EvalOptions evalOptions;
  CheckOptions checkOptions;
  CLI::App* eval = addEvalVerb(app, evalOptions);
  CLI::App* check = addCheckVerb(app, checkOptions);
  CalibrateArguments calibrateArguments;
  calibrateArguments.options.volcompVersion = VOLCOMP_VERSION;
  CLI::App* calibrate = addCalibrateVerb(app, calibrateArguments);
  Iso230Arguments iso230Arguments;
  CLI::App* iso230 = addIso230Verb(app, iso230Arguments);
  ExportOptions exportOptions;
  CLI::App* exportVerb = addExportVerb(app, exportOptions);
  ReportOptions reportOptions;
  CLI::App* report = addReportVerb(app, reportOptions);
  PlanArguments planArguments;
  CLI::App* plan = addPlanVerb(app, planArguments);
  NcOptions ncOptions;
  CLI::App* ncVerb = addNcVerb(app, ncOptions);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
    std::cerr << "volcomp: " << oneLine(e.what()) << " (see volcomp --help)\n";
    return kExitBadInput;
  }

  try {
    if (eval->parsed()) return runEval(evalOptions, std::cout, std::cerr);
    if (check->parsed()) return runCheck(checkOptions, std::cout);
    if (calibrate->parsed()) {
      resolveCalibrateArguments(calibrateArguments);
      return runCalibrate(calibrateArguments.options, std::cout);
    }
    if (iso230->parsed()) {
      resolveIso230Arguments(iso230Arguments);
      return runIso230(iso230Arguments.options, std::cout, std::cerr);
    }
    if (exportVerb->parsed()) return runExport(exportOptions, std::cout);
    if (report->parsed()) return runReport(reportOptions, std::cout, std::cerr);
    if (plan->parsed()) {
      resolvePlanArguments(planArguments);
      planArguments.options.progress = &std::cerr;
      return runPlan(planArguments.options, std::cout);
    }
    if (ncVerb->parsed()) return runNc(ncOptions, std::cerr);
  } catch (const volcomp::config::ConfigError& e) {
    std::cerr << "volcomp: " << oneLine(e.what()) << '\n';
    return kExitBadInput;
  } catch (const volcomp::nc::NcError& e) {
    std::cerr << "volcomp: " << oneLine(e.what()) << '\n';
    return kExitBadInput;
  } catch (const UsageError& e) {
    std::cerr << "volcomp: " << oneLine(e.what()) << '\n';
    return kExitBadInput;
  } catch (const volcomp::output::OutputError& e) {
    std::cerr << "volcomp: " << oneLine(e.what()) << '\n';
    return kExitBadInput;
  } catch (const volcomp::model::ModelError& e) {
    std::cerr << "volcomp: invalid model: " << oneLine(e.what()) << '\n';
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "volcomp: internal error: " << oneLine(e.what()) << '\n';
    return 1;
  }
  return kExitBadInput;
}
