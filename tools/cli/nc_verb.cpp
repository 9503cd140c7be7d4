#include "nc_verb.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <ostream>
#include <variant>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/format/numbers.hpp"
#include "volcomp/nc/canon_reader.hpp"
#include "volcomp/nc/compensator.hpp"
#include "volcomp/nc/nc_error.hpp"
#include "volcomp/nc/ngc_reader.hpp"
#include "volcomp/nc/text_io.hpp"
#include "volcomp/output/output_file.hpp"

namespace volcomp::cli {
namespace {

using OrderedJson = nlohmann::ordered_json;

// The compensated program into an output file's stream (buffered there).
class StreamSink final : public nc::TextSink {
 public:
  explicit StreamSink(std::ostream& out) : out_(out) {}
  void write(std::string_view text) override {
    out_.write(text.data(), static_cast<std::streamsize>(text.size()));
  }

 private:
  std::ostream& out_;
};

OrderedJson listedLines(const std::vector<nc::ListedLine>& lines, bool withAxes) {
  OrderedJson a = OrderedJson::array();
  for (const nc::ListedLine& l : lines) {
    if (withAxes) {
      a.push_back(OrderedJson{{"line", l.line}, {"axes", axisList(l.axes)}});
    } else {
      a.push_back(l.line);
    }
  }
  return a;
}

OrderedJson reportJson(const nc::NcReport& r, const NcOptions& options) {
  OrderedJson j;
  j["input"] = options.inputPath;
  j["output"] = options.outPath;
  j["model"] = options.modelPath;
  j["format"] = r.format;
  j["tolerance_mm"] = r.toleranceMm;
  j["check_step_mm"] = r.checkStepMm;
  j["decimals"] = {{"mm", r.decimalsMm}, {"inch", r.decimalsInch}};
  j["lines_in"] = r.linesIn;
  j["lines_out"] = r.linesOut;
  j["moves"] = {{"rapid", r.rapidMoves}, {"feed", r.feedMoves}, {"arc", r.arcMoves}};
  j["motion_lines_out"] = r.motionLinesOut;
  j["pieces_added"] = r.piecesAdded;
  j["reversal_moves"] = r.reversalMoves;
  j["offset_mm"] = {{"vertices", r.vertices}, {"peak", r.peakOffsetMm}, {"rms", r.rmsOffsetMm()}};
  j["deviation_mm"] = {{"max_checked", r.maxDeviationMm},
                       {"max_bound", r.maxBoundMm},
                       {"check_points", r.checkPoints},
                       {"unresolved_pieces", r.unresolvedPieces}};
  j["outside_travel"] = {{"points", r.outsideTravel},
                         {"lines", listedLines(r.outsideTravelLines, true)}};
  j["not_converged"] = {{"points", r.notConverged},
                        {"lines", listedLines(r.notConvergedLines, false)}};
  j["uncompensated"] = {{"moves", r.uncompensatedMoves},
                        {"lines", listedLines(r.uncompensatedLines, false)}};
  j["end_point_only"] = {{"moves", r.endOnlyMoves}, {"lines", listedLines(r.endOnlyLines, false)}};
  OrderedJson ignored = OrderedJson::object();
  for (const auto& [name, count] : r.ignoredCanonical) ignored[name] = count;
  j["ignored_canonical"] = ignored;
  j["offset_solves"] = r.offsetSolves;
  j["time_s"] = r.timeS;
  j["stages_s"] = {
      {"read", r.readS}, {"offsets", r.offsetsS}, {"split", r.splitS}, {"write", r.writeS}};
  j["lines_per_s"] = r.timeS > 0.0 ? static_cast<double>(r.linesIn) / r.timeS : 0.0;
  return j;
}

std::string firstLines(const std::vector<nc::ListedLine>& lines) {
  std::string text;
  for (std::size_t i = 0; i < lines.size() && i < 5; ++i) {
    text += (i == 0 ? "" : ", ") + std::to_string(lines[i].line);
    if (lines[i].axes != 0) text += " (" + axisList(lines[i].axes) + ")";
  }
  if (lines.size() > 5) text += ", ...";
  return text;
}

void summary(std::ostream& err, const nc::NcReport& r, const NcOptions& o) {
  err << "volcomp nc: " << o.inputPath << " -> " << o.outPath << " (" << r.format << ", tolerance "
      << fixedMicrometres(r.toleranceMm) << " um)\n"
      << "  lines: " << r.linesIn << " in, " << r.linesOut << " out; moves: " << r.rapidMoves
      << " rapid, " << r.feedMoves << " feed, " << r.arcMoves << " arc; " << r.piecesAdded
      << " pieces added, " << r.reversalMoves << " reversal moves\n"
      << "  offsets at " << r.vertices << " vertices: peak " << fixedMicrometres(r.peakOffsetMm)
      << " um, RMS " << fixedMicrometres(r.rmsOffsetMm()) << " um\n"
      << "  deviation from the ideal compensated path: max " << fixedMicrometres(r.maxDeviationMm)
      << " um at " << r.checkPoints << " check points (at most " << formatDouble(r.checkStepMm)
      << " mm apart), " << fixedMicrometres(r.maxBoundMm) << " um with the curvature allowance\n";
  if (r.unresolvedPieces > 0) {
    err << "  warning: " << r.unresolvedPieces
        << " pieces could not be split within the tolerance (see max_bound)\n";
  }
  if (r.outsideTravel > 0) {
    err << "  warning: " << r.outsideTravel
        << " points outside the model's travel, compensated at the nearest travel end (lines "
        << firstLines(r.outsideTravelLines) << ")\n";
  }
  if (r.uncompensatedMoves > 0) {
    err << "  note: " << r.uncompensatedMoves
        << " moves copied unchanged: the position was not known yet (lines "
        << firstLines(r.uncompensatedLines) << "; give --start)\n";
  }
  if (r.endOnlyMoves > 0) {
    err << "  note: " << r.endOnlyMoves
        << " feed moves from an unknown position: end point compensated only (lines "
        << firstLines(r.endOnlyLines) << ")\n";
  }
  if (!r.ignoredCanonical.empty()) {
    err << "  canonical commands without an effect on the motion:";
    for (const auto& [name, count] : r.ignoredCanonical) err << ' ' << name << " x" << count;
    err << '\n';
  }
  if (r.notConverged > 0) {
    err << "  error: the offset did not converge at " << r.notConverged << " points (lines "
        << firstLines(r.notConvergedLines) << "): the program is not reliable there\n";
  }
  using format::fixed;
  err << "  time: " + fixed(r.timeS, 3) + " s (read " + fixed(r.readS, 3) + ", offsets " +
             fixed(r.offsetsS, 3) + ", split " + fixed(r.splitS, 3) + ", write " +
             fixed(r.writeS, 3) + "), " +
             fixed(r.timeS > 0.0 ? static_cast<double>(r.linesIn) / r.timeS : 0.0, 0) +
             " lines/s\n";
}

bool detectCanonical(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  for (int i = 0; i < 50 && std::getline(in, line); ++i) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    return nc::CanonReader::looksCanonical(line);
  }
  return false;
}

// Progress on stderr once a second, after the first second.
class Progress {
 public:
  Progress(std::ostream& err, bool quiet) : err_(err), quiet_(quiet) {}
  void operator()(std::uint64_t done, std::uint64_t total, long lines) {
    if (quiet_) return;
    const auto now = std::chrono::steady_clock::now();
    if (now - last_ < std::chrono::seconds(1)) return;
    last_ = now;
    err_ << "volcomp nc: ";
    if (total > 0) err_ << (100 * done / total) << " %, ";
    err_ << lines << " lines" << std::endl;
  }

 private:
  std::ostream& err_;
  bool quiet_;
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace

CLI::App* addNcVerb(CLI::App& app, NcOptions& options) {
  CLI::App* verb = app.add_subcommand(
      "nc",
      "Compensate an NC program offline: every programmed point p moves to p + o(q), q its "
      "machine position (p + work offset + tool offset), o the model's compensation offset; "
      "feed moves and arcs become polylines within --tolerance of the ideal compensated path. "
      "Input: RS274/NGC (the subset a CAM post-processor emits) or the output of LinuxCNC's "
      "rs274 -g (any program LinuxCNC runs). See docs/nc.md.");
  verb->add_option("model", options.modelPath, "Model file (volcomp-model/1, 3-axis)")->required();
  verb->add_option("program", options.inputPath, "NC program (.ngc) or rs274 -g output")
      ->required()
      ->check(CLI::ExistingFile);
  verb->add_option("--out", options.outPath, "Compensated program to write")->required();
  verb->add_option("--report", options.reportPath, "Also write the report as JSON");
  verb->add_option("--tolerance", options.toleranceMm,
                   "Largest deviation of the written path from the ideal compensated path (mm)")
      ->capture_default_str()
      ->check(CLI::Range(1e-6, 1.0));
  verb->add_option("--work-offsets", options.workOffsets,
                   "Work offsets: a LinuxCNC parameter file (.var) and/or a JSON file (.json); "
                   "repeatable, later files override")
      ->check(CLI::ExistingFile);
  verb->add_option("--tool-table", options.toolTable, "LinuxCNC tool table (.tbl) for G43")
      ->check(CLI::ExistingFile);
  verb->add_option("--machine-units", options.machineUnits,
                   "Units of the .var and .tbl values (LinuxCNC [TRAJ]LINEAR_UNITS)")
      ->capture_default_str()
      ->check(CLI::IsMember({"mm", "inch"}));
  verb->add_option("--tool", options.tool,
                   "Tool offset TX,TY,TZ of the model in mm (overrides the model's)");
  verb->add_option("--start", options.start,
                   "Machine position X,Y,Z (mm) at the program start (default: unknown)");
  verb->add_option("--input", options.input, "Input format")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "ngc", "canon"}));
  verb->add_option("--check-step", options.checkStepMm,
                   "Largest distance between check points along a move (mm; default: a quarter of "
                   "the model's smallest table spacing, within 0.1 .. 5)")
      ->check(CLI::Range(1e-4, 1000.0));
  verb->add_option("--mode", options.mode, "exact (the reference) or first-order")
      ->capture_default_str()
      ->check(CLI::IsMember({"exact", "first-order"}));
  verb->add_flag("--quiet", options.quiet, "No summary and no progress on stderr");
  verb->footer(
      "Exit status: 0 written; 2 bad arguments, a bad file or a program line outside the "
      "supported subset (one line on stderr: file:line:column and what was found); 3 written, "
      "but an offset did not converge somewhere (listed in the report).");
  return verb;
}

int runNc(const NcOptions& options, std::ostream& err) {
  const config::ModelDocument doc = config::loadModelFile(options.modelPath);
  const auto* specPtr = std::get_if<model::MachineModelSpec>(&doc.spec);
  if (specPtr == nullptr) {
    throw UsageError(
        "nc: " + options.modelPath +
        " is a D-H chain; NC compensation needs a 3-axis model (topology and components)");
  }
  model::MachineModelSpec spec = *specPtr;
  if (!options.tool.empty()) {
    const std::vector<double> t = parseNumberList(options.tool, "--tool TX,TY,TZ (mm)", 3);
    spec.toolMm = Eigen::Vector3d(t[0], t[1], t[2]);
  }
  std::optional<nc::Vec3> start;
  if (!options.start.empty()) {
    const std::vector<double> s = parseNumberList(options.start, "--start X,Y,Z (mm)", 3);
    start = nc::Vec3(s[0], s[1], s[2]);
  }
  const nc::LengthUnit machineUnits =
      options.machineUnits == "inch" ? nc::LengthUnit::Inch : nc::LengthUnit::Mm;
  nc::WorkOffsets offsets;
  nc::ToolTable tools;
  for (const std::string& file : options.workOffsets) {
    nc::readWorkOffsetsFile(file, machineUnits, offsets, tools);
  }
  if (!options.toolTable.empty()) nc::readToolTableFile(options.toolTable, machineUnits, tools);

  auto modelPtr = std::make_shared<const model::MachineModel>(std::move(spec));
  nc::OffsetField field(modelPtr, options.mode == "first-order" ? model::EvalMode::FirstOrder
                                                                : model::EvalMode::Exact);
  nc::CompensateOptions compensate;
  compensate.toleranceMm = options.toleranceMm;
  compensate.checkStepMm = options.checkStepMm;
  const nc::Decimals decimals = nc::decimalsForTolerance(options.toleranceMm);

  const bool canonical =
      options.input == "canon" || (options.input == "auto" && detectCanonical(options.inputPath));
  std::unique_ptr<nc::ProgramReader> reader;
  if (canonical) {
    reader = std::make_unique<nc::CanonReader>(options.inputPath, start, decimals);
  } else {
    reader = std::make_unique<nc::NgcReader>(options.inputPath, offsets, tools, start, decimals);
  }

  // The program goes through volcomp::output (a temporary file beside the target, renamed when
  // complete): a rejected program leaves the target as it was, and no input is overwritten.
  std::vector<std::filesystem::path> inputs{options.inputPath, options.modelPath};
  for (const std::string& file : options.workOffsets) inputs.emplace_back(file);
  if (!options.toolTable.empty()) inputs.emplace_back(options.toolTable);
  output::OutputFile program(options.outPath, inputs);
  if (!options.reportPath.empty()) output::refuseInputAsOutput(options.reportPath, inputs);
  nc::NcReport report;
  {
    nc::FileSource source(options.inputPath);
    StreamSink sink(program.stream());
    nc::Compensator compensator(field, compensate, start);
    Progress progress(err, options.quiet);
    report = compensator.run(*reader, source, sink, std::ref(progress));
  }
  program.commit();
  report.input = options.inputPath;
  report.decimalsMm = decimals.mm;
  report.decimalsInch = decimals.inch;
  if (const auto* canon = dynamic_cast<const nc::CanonReader*>(reader.get())) {
    report.ignoredCanonical = canon->ignored();
  }
  if (!options.reportPath.empty()) {
    inputs.emplace_back(options.outPath);
    output::writeOutputFile(options.reportPath, reportJson(report, options).dump(2) + "\n", inputs);
  }
  if (!options.quiet) summary(err, report, options);
  return report.notConverged > 0 ? kExitNotConverged : kExitOk;
}

}  // namespace volcomp::cli
