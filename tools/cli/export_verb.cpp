#include "export_verb.hpp"

#include <filesystem>
#include <fstream>
#include <ostream>
#include <sstream>

#include <CLI/CLI.hpp>

#include "cli_support.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/format/text.hpp"
#include "volcomp/metrology/controller_files.hpp"
#include "volcomp/metrology/export_plan.hpp"
#include "volcomp/metrology/remaining_error.hpp"
#include "volcomp/output/output_file.hpp"

namespace volcomp::cli {
namespace {

using metrology::AxisTable;
using metrology::ExportPlan;

/// "10" (every axis) or "X=10,Z=5" (the others automatic); empty: automatic.
metrology::GridSteps parseSteps(const std::string& text) {
  metrology::GridSteps steps{0.0, 0.0, 0.0};
  if (text.empty()) return steps;
  if (text.find('=') == std::string::npos) {
    const double step = parseNumberList(text, "--step", 1)[0];
    if (step <= 0.0) throw UsageError("--step: expected a positive step in mm");
    steps.fill(step);
    return steps;
  }
  for (std::string_view field : splitFields(text)) {
    const std::size_t eq = field.find('=');
    double value = 0.0;
    const std::string_view axis = eq == std::string_view::npos ? field : trim(field.substr(0, eq));
    if (eq == std::string_view::npos || axis.size() != 1 ||
        std::string_view("XYZ").find(axis[0]) == std::string_view::npos ||
        !parseDouble(trim(field.substr(eq + 1)), value) || value <= 0.0) {
      throw UsageError("--step: expected a step in mm or AXIS=STEP pairs such as X=10,Z=5, got \"" +
                       text + "\"");
    }
    steps[static_cast<std::size_t>(std::string_view("XYZ").find(axis[0]))] = value;
  }
  return steps;
}

std::array<std::string, 3> parseNames(const std::string& text, const std::string& option) {
  const std::vector<std::string_view> fields = splitFields(text);
  if (fields.size() != 3) {
    throw UsageError(option + ": expected three comma-separated names for X, Y, Z, got \"" + text +
                     "\"");
  }
  std::array<std::string, 3> names;
  for (std::size_t i = 0; i < 3; ++i) {
    if (fields[i].empty()) throw UsageError(option + ": empty name in \"" + text + "\"");
    names[i] = std::string(fields[i]);
  }
  return names;
}

/// Every file goes through output::writeOutputFile: written whole or not at all, never over the
/// model it was made from.
void writeFile(const ExportOptions& options, const std::filesystem::path& path,
               const std::string& text) {
  output::writeOutputFile(path, text, {options.modelPath});
}

std::filesystem::path outputDirectory(const std::string& out) {
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec || !std::filesystem::is_directory(out)) {
    throw UsageError("--out: cannot create the directory " + out +
                     (ec ? " (" + ec.message() + ")" : std::string()));
  }
  return out;
}

std::vector<std::string> writeLinuxCnc(const ExportOptions& options, const ExportPlan& plan) {
  const std::array<std::string, 3> joints = parseNames(options.joints, "--joints");
  const std::filesystem::path dir = outputDirectory(options.out);
  std::vector<std::string> written;
  std::string ini =
      "# LinuxCNC joint compensation written by volcomp export (machine units: mm).\n"
      "# Add these lines to the [JOINT_n] sections of the machine's INI file.\n";
  for (std::size_t a = 0; a < 3; ++a) {
    const AxisTable* forward = nullptr;
    const AxisTable* reverse = nullptr;
    for (const AxisTable& table : plan.tables) {
      if (static_cast<std::size_t>(table.input) != a) continue;
      if (table.direction >= 0) forward = &table;
      if (table.direction <= 0) reverse = &table;
    }
    if (forward == nullptr) continue;
    if (forward->errorMm.size() > metrology::kLinuxCncMaxPoints) {
      throw UsageError("--step: " + std::to_string(forward->errorMm.size()) + " points along " +
                       metrology::axisName(forward->input) +
                       ", LinuxCNC takes at most 256 per joint: choose a larger step");
    }
    std::ostringstream text;
    metrology::writeLinuxCncCompFile(text, *forward, *reverse, options.compType);
    const std::string name = "joint" + joints[a] + ".comp";
    writeFile(options, dir / name, text.str());
    written.push_back((dir / name).string());
    ini += "\n[JOINT_" + joints[a] + "]\n# axis " + metrology::axisName(forward->input) + ": " +
           forward->components.front() + "\nCOMP_FILE = " + name +
           "\nCOMP_FILE_TYPE = " + std::to_string(options.compType) + "\n";
  }
  writeFile(options, dir / "comp.ini", ini);
  written.push_back((dir / "comp.ini").string());
  return written;
}

std::vector<std::string> writeSiemens(const ExportOptions& options, const ExportPlan& plan,
                                      const model::MachineModelSpec& spec) {
  const std::array<std::string, 3> names = parseNames(options.axisNames, "--axis-names");
  const std::filesystem::path dir = outputDirectory(options.out);
  std::vector<AxisTable> lec, cec;
  for (const AxisTable& table : plan.tables) {
    (table.input == table.output && table.direction == 0 ? lec : cec).push_back(table);
  }
  const std::string source = "volcomp export of " + options.modelPath +
                             (spec.name.empty() ? std::string() : " (" + spec.name + ")");
  std::vector<std::string> written;
  if (!lec.empty()) {
    std::size_t most = 0;
    for (const AxisTable& t : lec) most = std::max(most, t.errorMm.size());
    metrology::CommentLines comments{
        source, "leadscrew / measuring system error compensation (LEC, MSEC), values in mm",
        "load with MD32700 $MA_ENC_COMP_ENABLE[" + std::to_string(options.encoder) +
            ",axis]=0, then set it to 1 (NewConfig)",
        "needs MD38000 $MA_MM_ENC_COMP_MAX_POINTS[" + std::to_string(options.encoder) +
            ",axis] >= " + std::to_string(most)};
    std::ostringstream text;
    metrology::writeSiemensLec(text, lec, names, options.encoder, comments);
    writeFile(options, dir / "AX_EEC.INI", text.str());
    written.push_back((dir / "AX_EEC.INI").string());
  }
  if (!cec.empty()) {
    metrology::CommentLines comments{
        source, "sag / angularity compensation (CEC), values in mm",
        "load with MD32710 $MA_CEC_ENABLE[output axis]=0, then set it to 1 (NewConfig)",
        "needs MD18342 $MN_MM_CEC_MAX_POINTS[t] >= the points of table t, and the tables "
        "enabled in the CEC setting data"};
    std::ostringstream text;
    metrology::writeSiemensCec(text, cec, names, comments);
    writeFile(options, dir / "NC_CEC.INI", text.str());
    written.push_back((dir / "NC_CEC.INI").string());
  }
  return written;
}

/// "RMS" and "max" in µm, right-aligned in the summary's columns (10 and 11 wide).
std::string rmsAndMax(const metrology::ErrorStatistics& e) {
  return format::padLeft(fixedMicrometres(e.rmsMm), 10) +
         format::padLeft(fixedMicrometres(e.maxMm), 11);
}

void printSummary(const ExportOptions& options, const ExportPlan& plan,
                  const std::vector<std::string>& written, const model::MachineModelSpec& spec,
                  std::ostream& out) {
  out << "volcomp export " << options.format << " of " << options.modelPath << " (" << spec.topology
      << ")\n";
  for (const std::string& file : written) out << "wrote " << file << '\n';
  out << "\ncarried:\n";
  if (plan.carried.empty()) out << "  nothing (the model has no component this format carries)\n";
  for (const std::string& line : plan.carried) out << "  " << line << '\n';
  if (!plan.notCarried.empty()) {
    out << "not carried (needs volumetric compensation, e.g. volcompd):\n";
    for (const std::string& line : plan.notCarried) out << "  " << line << '\n';
  }
  const metrology::RemainingError r =
      metrology::remainingError(spec, plan.tables, static_cast<std::size_t>(options.checkPoints));
  out << "\nposition error |p - p0| the model predicts over";
  for (std::size_t a = 0; a < 3; ++a) {
    out << (a == 0 ? " " : ", ") << "XYZ"[a] << ' ' << formatDouble(r.box[a].lowMm) << ".."
        << formatDouble(r.box[a].highMm);
  }
  out << " mm\n(" << r.pointsPerAxis[0] << 'x' << r.pointsPerAxis[1] << 'x' << r.pointsPerAxis[2]
      << " points";
  if (r.directionCombinations > 1) out << " x " << r.directionCombinations << " direction sets";
  out << ", um):\n"
      << "                            RMS        max\n"
      << "  uncompensated      " << rmsAndMax(r.uncompensated) << '\n'
      << "  these tables only  " << rmsAndMax(r.tablesOnly) << '\n'
      << "  live (volcompd)    " << rmsAndMax(r.live) << '\n';
  if (r.tablesOnly.rmsMm > r.uncompensated.rmsMm) {
    out << "  note: these tables alone leave a larger error than none: in this model the errors "
           "they\n"
           "  carry partly offset errors they cannot carry (angles, squareness, straightness)\n";
  }
  if (r.liveNotConverged > 0) {
    out << "  (the live offset did not converge at " << r.liveNotConverged << " point(s))\n";
  }
}

}  // namespace

CLI::App* addExportVerb(CLI::App& app, ExportOptions& options) {
  CLI::App* verb = app.add_subcommand(
      "export",
      "Write controller compensation tables from a model: linuxcnc (a COMP_FILE per joint from "
      "EXX/EYY/EZZ, forward and reverse curves, plus an INI snippet), siemens (840D part programs: "
      "LEC $AA_ENC_COMP for positioning, CEC $AN_CEC for straightness, squareness and reversal), "
      "csv (one component on a grid). Prints what the tables carry and cannot carry, and the "
      "error the model predicts to remain over the travel with only these tables applied, next "
      "to the live compensation's. See docs/export.md.");
  verb->add_option("model", options.modelPath, "Model file (volcomp-model/1, 3-axis)")->required();
  verb->add_option("--format", options.format, "linuxcnc, siemens or csv")
      ->required()
      ->check(CLI::IsMember({"linuxcnc", "siemens", "csv"}));
  verb->add_option("--out", options.out,
                   "Directory for linuxcnc and siemens (created), file for csv")
      ->required();
  verb->add_option("--step", options.step,
                   "Grid step in mm for every axis, or per axis as X=10,Z=5 (default: the "
                   "smallest of 1, 2, 2.5, 5 x 10^k mm giving at most 101 points)");
  verb->add_option("--comp-type", options.compType,
                   "linuxcnc: COMP_FILE_TYPE 0 (columns are where the joint really is) or 1 "
                   "(columns are the trims LinuxCNC adds)")
      ->capture_default_str()
      ->check(CLI::IsMember({0, 1}));
  verb->add_option("--joints", options.joints, "linuxcnc: joint numbers of X, Y, Z")
      ->capture_default_str();
  verb->add_option("--axis-names", options.axisNames,
                   "siemens: machine axis names of X, Y, Z (AX1.. or X1..)")
      ->capture_default_str();
  verb->add_option("--encoder", options.encoder, "siemens: measuring system of the LEC (0 or 1)")
      ->capture_default_str()
      ->check(CLI::IsMember({0, 1}));
  verb->add_option("--component", options.component,
                   "csv: the component to tabulate (EXX, EYX, EBX, EC0Y, ...)");
  verb->add_option("--check-points", options.checkPoints,
                   "Grid points per axis for the remaining-error check")
      ->capture_default_str()
      ->check(CLI::Range(2, 101));
  verb->footer(
      "Exit status: 0 written; 2 bad arguments or a bad model (one line on stderr). Signs: "
      "docs/export.md.");
  return verb;
}

int runExport(const ExportOptions& options, std::ostream& out) {
  const metrology::GridSteps steps = parseSteps(options.step);
  if (options.format == "csv" && options.component.empty()) {
    throw UsageError("--format csv needs --component (e.g. EXX)");
  }
  if (options.format != "csv" && !options.component.empty()) {
    throw UsageError("--component goes with --format csv");
  }
  const config::ModelDocument document = config::loadModelFile(options.modelPath);
  const auto* spec = std::get_if<model::MachineModelSpec>(&document.spec);
  if (spec == nullptr) {
    throw UsageError(options.modelPath +
                     ": a D-H chain; controller tables are exported from 3-axis models");
  }
  ExportPlan plan;
  std::vector<std::string> written;
  if (options.format == "linuxcnc") {
    plan = metrology::planLinuxCnc(*spec, steps);
    written = writeLinuxCnc(options, plan);
  } else if (options.format == "siemens") {
    plan = metrology::planSiemens(*spec, steps);
    written = writeSiemens(options, plan, *spec);
  } else {
    try {
      plan = metrology::planComponent(*spec, options.component, steps);
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string("--component: ") + e.what());
    }
    int axis = 0;
    for (int index = 0; index < 18; ++index) {
      if (model::motionName(index) == options.component) axis = index / 6;
    }
    for (int index = 0; index < 9; ++index) {
      if (model::locationName(index) == options.component) axis = index / 3;
    }
    std::ostringstream text;
    metrology::writeComponentCsv(text, *spec, options.component,
                                 metrology::planGrid(*spec, static_cast<model::Axis>(axis), steps));
    writeFile(options, options.out, text.str());
    written.push_back(options.out);
  }
  printSummary(options, plan, written, *spec, out);
  return kExitOk;
}

}  // namespace volcomp::cli
