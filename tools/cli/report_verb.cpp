#include "report_verb.hpp"

#include <chrono>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <ostream>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_support.hpp"
#include "volcomp/config/config_error.hpp"
#include "volcomp/output/output_file.hpp"
#include "volcomp/report/report.hpp"

namespace volcomp::cli {
namespace {

namespace fs = std::filesystem;

report::InputFile describe(const std::string& role, const std::string& path) {
  report::InputFile file{role, path, 0, {}};
  std::error_code ec;
  file.bytes = fs::file_size(path, ec);
  if (ec) file.bytes = 0;
  const auto modified = fs::last_write_time(path, ec);
  if (!ec) {
    const std::time_t t = std::chrono::system_clock::to_time_t(
        std::chrono::time_point_cast<std::chrono::system_clock::duration>(
            std::chrono::file_clock::to_sys(modified)));
    std::tm local{};
    localtime_r(&t, &local);
    char buffer[32];
    std::strftime(buffer, sizeof buffer, "%Y-%m-%d %H:%M", &local);
    file.modified = buffer;
  }
  return file;
}

// A path named inside the calibration report: as written (relative to where calibrate ran), or
// next to the report.
std::string findBeside(const std::string& named, const std::string& reportPath) {
  if (named.empty()) return {};
  if (fs::exists(named)) return named;
  const fs::path beside = fs::path(reportPath).parent_path() / fs::path(named).filename();
  if (fs::exists(beside)) return beside.string();
  return {};
}

// Reproducible output: SOURCE_DATE_EPOCH (reproducible-builds.org) fixes the date when set.
std::time_t reportDate() {
  if (const char* epoch = std::getenv("SOURCE_DATE_EPOCH")) {
    char* end = nullptr;
    const long long seconds = std::strtoll(epoch, &end, 10);
    if (end != epoch && *end == '\0') return static_cast<std::time_t>(seconds);
  }
  return std::time(nullptr);
}

void loadCalibration(const ReportOptions& options, report::ReportInputs& inputs) {
  inputs.calibration = report::loadCalibrationReport(options.calibrationPath, inputs.notes);
  inputs.files.push_back(describe("calibration report", options.calibrationPath));
  // Measurements and template: given, or found where the calibration report names them.
  // A file the user named must load; one found by its name in the report may fail with a note.
  const auto load = [&](const std::string& given, const std::string& named, const char* role,
                        auto&& reader) {
    const std::string path = given.empty() ? findBeside(named, options.calibrationPath) : given;
    if (path.empty()) {
      if (!named.empty()) {
        inputs.notes.push_back(std::string(role) + " " + named +
                               " (named in the calibration report) was not found");
      }
      return;
    }
    try {
      reader(path);
      inputs.files.push_back(describe(role, path));
    } catch (const config::ConfigError& e) {
      if (!given.empty()) throw;
      inputs.notes.push_back(std::string(role) + " not used: " + e.what());
    }
  };
  load(options.measurementsPath, inputs.calibration->measurementFile, "calibration measurements",
       [&](const std::string& path) {
         inputs.measurements = calibration::readMeasurementsCsv(path);
       });
  load(options.templatePath, inputs.calibration->templateFile, "calibration template",
       [&](const std::string& path) {
         config::ParseOptions parse;
         parse.allowIdentify = true;
         inputs.calibrationTemplate = config::loadModelFile(path, parse);
       });
}

}  // namespace

CLI::App* addReportVerb(CLI::App& app, ReportOptions& options) {
  CLI::App* verb = app.add_subcommand(
      "report",
      "Write one self-contained HTML report (opens offline): the model's error components and "
      "volumetric error maps, and where given a calibration, an ISO 230-2 evaluation and a "
      "compensation run, with a summary at the top.");
  verb->add_option("model", options.modelPath, "Model file (volcomp-model/1)")->required();
  verb->add_option("--out,-o", options.outPath,
                   "HTML file to write (default: MODEL's name with -report.html, here)");
  verb->add_option("--calibration", options.calibrationPath,
                   "Calibration report (volcomp calibrate --report)");
  verb->add_option("--measurements", options.measurementsPath,
                   "The calibration's measurement CSV, for residuals per point (default: as "
                   "named in the calibration report, or beside it)");
  verb->add_option("--template", options.templatePath,
                   "The calibration template, for the residuals before the fit (default: as "
                   "named in the calibration report, or beside it)");
  verb->add_option("--iso230-2", options.isoPaths,
                   "ISO 230-2 evaluation of one axis (volcomp iso230-2 --json); repeat per axis");
  verb->add_option("--run", options.runPath,
                   "Compensation run: volcomp-sim's JSON report line (a file holding it)");
  verb->add_option("--writes", options.writesPath, "The run's writes (volcomp-sim --record CSV)");
  verb->add_option("--title", options.title, "Title of the report")->capture_default_str();
  verb->add_option("--machine", options.machine, "Machine name (default: the model's name)");
  verb->add_option("--z-levels", options.zLevels,
                   "Z levels of the XY maps, mm, comma-separated (default: top, middle, bottom)");
  verb->add_option("--map-cells", options.mapCells, "Cells along the longer side of each map")
      ->capture_default_str()
      ->check(CLI::Range(4, 200));
  verb->footer(
      "The date shown is now, or SOURCE_DATE_EPOCH when set. Exit status: 0 written; 2 bad "
      "arguments or a bad input file (one line on stderr naming the file and key or line).");
  return verb;
}

int runReport(const ReportOptions& options, std::ostream& out, std::ostream& err) {
  report::ReportInputs inputs;
  inputs.model = config::loadModelFile(options.modelPath);
  inputs.files.push_back(describe("model", options.modelPath));
  if (!options.calibrationPath.empty()) {
    loadCalibration(options, inputs);
  } else if (!options.measurementsPath.empty() || !options.templatePath.empty()) {
    throw UsageError("--measurements and --template belong to --calibration");
  }
  for (const std::string& path : options.isoPaths) {
    inputs.iso.push_back(report::loadIsoAxis(path, inputs.notes));
    inputs.files.push_back(describe("ISO 230-2 evaluation", path));
  }
  if (!options.runPath.empty()) {
    inputs.run = report::loadRunSummary(options.runPath, inputs.notes);
    inputs.files.push_back(describe("compensation run", options.runPath));
  }
  if (!options.writesPath.empty()) {
    inputs.writes = report::loadRecordedWrites(options.writesPath);
    inputs.files.push_back(describe("recorded writes", options.writesPath));
  }

  report::ReportOptions reportOptions;
  reportOptions.title = options.title;
  reportOptions.machine = options.machine;
  reportOptions.volcompVersion = VOLCOMP_VERSION;
  reportOptions.date = reportDate();
  reportOptions.mapResolution = options.mapCells;
  if (!options.zLevels.empty()) {
    reportOptions.zLevelsMm = parseNumberList(options.zLevels, "--z-levels", 0);
  }
  const report::RenderedReport rendered = report::renderReport(inputs, reportOptions);

  const std::string outPath = options.outPath.empty()
                                  ? fs::path(options.modelPath).stem().string() + "-report.html"
                                  : options.outPath;
  std::vector<fs::path> inputPaths{options.modelPath, options.calibrationPath, options.runPath,
                                   options.writesPath};
  inputPaths.insert(inputPaths.end(), options.isoPaths.begin(), options.isoPaths.end());
  std::erase_if(inputPaths, [](const fs::path& p) { return p.empty(); });
  output::writeOutputFile(outPath, rendered.html, inputPaths);
  for (const std::string& note : rendered.notes) err << "note: " << note << '\n';
  std::string sections;
  for (const auto& [id, title] : rendered.sections)
    sections += (sections.empty() ? "" : ", ") + title;
  out << "report written to " << outPath << " (" << (rendered.html.size() + 512) / 1024 << " KiB, "
      << rendered.charts << " charts: " << sections << ")\n";
  return kExitOk;
}

}  // namespace volcomp::cli
