#include "iso230_2_verb.hpp"

#include <filesystem>
#include <ostream>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_support.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/format/numbers.hpp"
#include "volcomp/metrology/axis_tables.hpp"
#include "volcomp/metrology/iso230_2.hpp"
#include "volcomp/metrology/iso230_2_json.hpp"
#include "volcomp/metrology/iso230_2_model.hpp"
#include "volcomp/metrology/positioning_runs.hpp"
#include "volcomp/output/output_file.hpp"

namespace volcomp::cli {
namespace {

using metrology::Iso230Result;
using metrology::TargetFigures;

/// The files the verb reads, which its outputs must never replace.
std::vector<std::filesystem::path> inputsOf(const Iso230Options& options) {
  std::vector<std::filesystem::path> inputs{options.runsPath};
  if (!options.mergePath.empty()) inputs.emplace_back(options.mergePath);
  return inputs;
}

/// Writes one output file of the verb; a refusal names the option as well as the file
/// ("--model-out m.json: is a directory, not a file").
void writeOutput(const char* option, const std::string& path, const std::string& contents,
                 const Iso230Options& options) {
  try {
    output::writeOutputFile(path, contents, inputsOf(options));
  } catch (const output::OutputError& e) {
    throw UsageError(std::string(option) + " " + e.what());
  }
}

/// mm -> um with 4 significant digits, at most 3 decimals (sub-nm digits mean nothing here).
std::string um(double valueMm) {
  return format::fixedSignificant(valueMm * 1000.0, 4, 3);
}

std::string column(const std::string& text, int width) {
  return text.size() >= static_cast<std::size_t>(width)
             ? " " + text
             : std::string(static_cast<std::size_t>(width) - text.size(), ' ') + text;
}

void printTable(const Iso230Result& r, std::ostream& out) {
  out << "ISO 230-2:2014 positioning evaluation"
      << (r.axis ? std::string(", axis ") + metrology::axisName(*r.axis) : std::string()) << " ("
      << r.source << ")\n"
      << r.targets.size() << " targets, " << r.runsPositive.size() << " runs \xE2\x86\x91, "
      << r.runsNegative.size() << " runs \xE2\x86\x93; deviations in um, positions in mm\n\n";
  const char* headers[] = {
      "target",        "x\xCC\x84\xE2\x86\x91", "x\xCC\x84\xE2\x86\x93", "x\xCC\x84",     "B",
      "s\xE2\x86\x91", "s\xE2\x86\x93",         "R\xE2\x86\x91",         "R\xE2\x86\x93", "R"};
  // Header cells hold multi-byte characters: pad by their display width (1 per code point).
  for (const char* h : headers) {
    std::size_t width = 0;
    for (const char* c = h; *c != '\0'; ++c)
      width += (static_cast<unsigned char>(*c) & 0xC0) != 0x80;
    out << std::string(10 - width, ' ') << h;
  }
  out << '\n';
  for (const TargetFigures& t : r.targets) {
    out << column(formatDouble(t.positionMm), 10) << column(um(t.meanPositiveMm), 10)
        << column(um(t.meanNegativeMm), 10) << column(um(t.meanBidirectionalMm), 10)
        << column(um(t.reversalMm), 10) << column(um(t.sPositiveMm), 10)
        << column(um(t.sNegativeMm), 10) << column(um(t.repeatabilityPositiveMm), 10)
        << column(um(t.repeatabilityNegativeMm), 10)
        << column(um(t.repeatabilityBidirectionalMm), 10) << '\n';
  }
  const metrology::AxisFigures& a = r.figures;
  out << "\naxis (um)                               \xE2\x86\x91          \xE2\x86\x93   "
         "bidirectional\n"
      << "  repeatability R                " << column(um(a.repeatabilityPositiveMm), 10)
      << column(um(a.repeatabilityNegativeMm), 10) << column(um(a.repeatabilityBidirectionalMm), 14)
      << '\n'
      << "  systematic deviation E         " << column(um(a.systematicPositiveMm), 10)
      << column(um(a.systematicNegativeMm), 10) << column(um(a.systematicBidirectionalMm), 14)
      << '\n'
      << "  accuracy A                     " << column(um(a.accuracyPositiveMm), 10)
      << column(um(a.accuracyNegativeMm), 10) << column(um(a.accuracyBidirectionalMm), 14) << '\n'
      << "  reversal value B               " << column(um(a.reversalMm), 34) << '\n'
      << "  mean reversal value B\xCC\x84           " << column(um(a.meanReversalMm), 34) << '\n'
      << "  range of mean bidirectional M  " << column(um(a.meanBidirectionalRangeMm), 34) << '\n';
}

void writeModelTable(const Iso230Options& options, const Iso230Result& result, std::ostream& out) {
  if (!result.axis) {
    throw UsageError("--model-out " + options.modelOutPath + ": " + options.runsPath +
                     " has no axis column, so the component's axis is not known; name it with "
                     "--axis");
  }
  const model::Axis axis = *result.axis;
  const int index = model::motionIndex(axis, static_cast<model::MotionKind>(axis));
  model::MachineModelSpec spec;
  config::ErrorUnits units;
  units.length = config::LengthUnit::Micrometre;
  units.angle = config::AngleUnit::Microradian;
  if (!options.mergePath.empty()) {
    config::ModelDocument document = config::loadModelFile(options.mergePath);
    auto* machine = std::get_if<model::MachineModelSpec>(&document.spec);
    if (machine == nullptr) {
      throw UsageError("--merge: " + options.mergePath +
                       " is a D-H chain; a positioning table goes into a 3-axis model");
    }
    spec = *machine;
    units = document.units;
  } else {
    spec.name = "ISO 230-2 " + model::motionName(index) + " from " + result.source;
    spec.topology = options.topology.value().text();
  }
  const model::Topology topology = model::Topology::parse(spec.topology);
  spec.motion[static_cast<std::size_t>(index)] =
      metrology::positioningComponent(result, topology, axis);
  const nlohmann::json document = config::writeModel(spec, units);
  writeOutput("--model-out", options.modelOutPath, document.dump(2) + '\n', options);
  out << "\nwrote " << model::motionName(index) << " (values from x\xCC\x84\xE2\x86\x91, "
      << "values_negative from x\xCC\x84\xE2\x86\x93, " << result.targets.size()
      << " positions) to " << options.modelOutPath << ": axis " << metrology::axisName(axis)
      << " is " << (topology.isWorkpieceSide(axis) ? "workpiece-side in " : "tool-side in ")
      << topology.text() << ", so " << model::motionName(index) << " = "
      << (topology.isWorkpieceSide(axis) ? "-" : "+") << "x\xCC\x84\n";
}

}  // namespace

CLI::App* addIso230Verb(CLI::App& app, Iso230Arguments& arguments) {
  Iso230Options& options = arguments.options;
  CLI::App* verb = app.add_subcommand(
      "iso230-2",
      "ISO 230-2:2014 evaluation of a linear positioning test: reads the bidirectional runs "
      "(CSV with header target_<unit>, deviation_<unit> or actual_<unit>, run, direction "
      "[, axis]; units nm|um|mm|m|in), prints per target x\xCC\x84\xE2\x86\x91 "
      "x\xCC\x84\xE2\x86\x93 "
      "x\xCC\x84 B s R and per axis B B\xCC\x84 R E M A in um, and writes the full result as JSON. "
      "Refuses fewer than 5 runs per direction or 5 targets and runs that do not visit the same "
      "targets. See docs/iso230-2.md.");
  verb->add_option("runs", options.runsPath, "CSV of the runs")->required();
  verb->add_option("--axis", arguments.axis,
                   "Axis evaluated (X, Y, Z): selects its rows when the CSV has an axis column")
      ->transform(CLI::IsMember({"X", "Y", "Z"}, CLI::ignore_case));
  verb->add_option("--json", options.jsonPath,
                   "Write the result as JSON (volcomp-iso230-2/1, mm, full precision)");
  verb->add_option("--model-out", options.modelOutPath,
                   "Write the axis' positioning component (EXX, EYY or EZZ; values from "
                   "x\xCC\x84\xE2\x86\x91, values_negative from x\xCC\x84\xE2\x86\x93) as a model "
                   "file; needs --topology or --merge");
  verb->add_option("--topology", arguments.topology,
                   "Topology of the machine (e.g. XYFZ): decides the sign, EKK = +x\xCC\x84 on a "
                   "tool-side axis, -x\xCC\x84 on a workpiece-side axis");
  verb->add_option("--merge", options.mergePath,
                   "Model file to copy (topology, units, all other components) with the "
                   "component replaced");
  verb->footer(
      "Exit status: 0 evaluated; 2 bad arguments, a bad CSV or data ISO 230-2 does not allow "
      "(one line on stderr: file, line and column, what was expected).");
  return verb;
}

void resolveIso230Arguments(Iso230Arguments& arguments) {
  Iso230Options& options = arguments.options;
  const bool topology = !arguments.topology.empty();
  if (!options.modelOutPath.empty() && topology == !options.mergePath.empty()) {
    throw UsageError("--model-out " + options.modelOutPath +
                     ": needs exactly one of --topology and --merge");
  }
  if (options.modelOutPath.empty() && (topology || !options.mergePath.empty())) {
    throw UsageError("--topology and --merge only go with --model-out");
  }
  if (!arguments.axis.empty()) {
    options.axis = model::axisFromName(arguments.axis);
    if (!options.axis) {
      throw UsageError("--axis: expected X, Y or Z, got \"" + arguments.axis + "\"");
    }
  }
  if (topology) {
    try {
      options.topology = model::Topology::parse(arguments.topology);
    } catch (const model::ModelError& e) {
      throw UsageError(std::string("--topology: ") + e.what());
    }
  }
}

int runIso230(const Iso230Options& options, std::ostream& out, std::ostream& err) {
  // The model to merge into is checked before anything is printed.
  if (!options.mergePath.empty()) config::loadModelFile(options.mergePath);
  const metrology::PositioningRuns runs =
      metrology::readPositioningCsv(options.runsPath, options.axis);
  const Iso230Result result = metrology::evaluateIso230_2(runs);
  for (const std::string& warning : result.warnings) {
    err << "volcomp: warning: " << warning << '\n';
  }
  printTable(result, out);
  if (!options.jsonPath.empty()) {
    writeOutput("--json", options.jsonPath, metrology::toJson(result).dump(2) + '\n', options);
  }
  if (!options.modelOutPath.empty()) writeModelTable(options, result, out);
  return kExitOk;
}

}  // namespace volcomp::cli
