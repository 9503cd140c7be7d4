#include "eval_verb.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <ostream>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "eval_points.hpp"
#include "volcomp/config/display_units.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/model/dh_chain.hpp"
#include "volcomp/model/machine_model.hpp"

namespace volcomp::cli {
namespace {

using OrderedJson = nlohmann::ordered_json;

// Adding 0.0 turns -0 into 0: a sign on zero means nothing to a reader of the output.
double tidy(double v) {
  return v + 0.0;
}

OrderedJson jsonVector(const Eigen::Vector3d& v) {
  return OrderedJson::array({tidy(v.x()), tidy(v.y()), tidy(v.z())});
}

OrderedJson jsonMatrix(const Eigen::Matrix4d& m) {
  OrderedJson rows = OrderedJson::array();
  for (int r = 0; r < 4; ++r) {
    rows.push_back(
        OrderedJson::array({tidy(m(r, 0)), tidy(m(r, 1)), tidy(m(r, 2)), tidy(m(r, 3))}));
  }
  return rows;
}

std::string triple(const Eigen::Vector3d& v) {
  return formatDouble(tidy(v.x())) + ", " + formatDouble(tidy(v.y())) + ", " +
         formatDouble(tidy(v.z()));
}

// Results on screen: um and urad (or arcsec) to 4 significant digits; --json keeps mm and rad.
std::string lengthTriple(const Eigen::Vector3d& mm) {
  return config::significant(mm.x() * 1e3) + ", " + config::significant(mm.y() * 1e3) + ", " +
         config::significant(mm.z() * 1e3) + "  um";
}

std::string angleTriple(const Eigen::Vector3d& rad, const std::string& unit) {
  const double factor = unit == "arcsec" ? 648000.0 / std::numbers::pi : 1e6;
  return config::significant(rad.x() * factor) + ", " + config::significant(rad.y() * factor) +
         ", " + config::significant(rad.z() * factor) + "  " + unit;
}

// Rows of shortest round-trip numbers, right-aligned in columns.
std::string matrixText(const Eigen::Matrix4d& m) {
  std::size_t width = 0;
  for (int i = 0; i < 16; ++i) width = std::max(width, formatDouble(tidy(m(i / 4, i % 4))).size());
  std::string text;
  for (int r = 0; r < 4; ++r) {
    text += "   ";
    for (int c = 0; c < 4; ++c) {
      const std::string v = formatDouble(tidy(m(r, c)));
      text += std::string(width + 2 - v.size(), ' ') + v;
    }
    text += '\n';
  }
  return text;
}

void warnClamped(std::ostream& err, const model::MachineModelSpec& spec, std::uint8_t mask) {
  if (mask == 0) return;
  std::string detail;
  for (int axis = 0; axis < 3; ++axis) {
    if ((mask & (1u << axis)) == 0 || !spec.travelMm[axis]) continue;
    if (!detail.empty()) detail += ", ";
    detail += std::string(1, "XYZ"[axis]) + " [" + formatDouble((*spec.travelMm[axis])[0]) + ", " +
              formatDouble((*spec.travelMm[axis])[1]) + "]";
  }
  err << "volcomp eval: warning: outside the travel (" << detail
      << " mm): error functions evaluated at the nearest end of the travel\n";
}

// A model that records the tools it was calibrated with: a tool far outside them means the
// errors that act through the tool's lever arms are extrapolated.
void warnFarTool(std::ostream& err, const config::ModelDocument& doc, const Eigen::Vector3d& toolMm,
                 const std::string& where) {
  if (!doc.calibration) return;
  const std::optional<double> distance = config::toolDistanceMm(*doc.calibration, toolMm);
  if (!distance || *distance <= config::kCalibratedToolToleranceMm) return;
  std::string tools;
  for (const Eigen::Vector3d& t : doc.calibration->toolsMm) {
    tools += (tools.empty() ? "(" : "; (") + triple(t) + ")";
  }
  err << "volcomp eval: warning: tool (" << triple(toolMm) << ") mm" << where << " is "
      << formatDouble(std::round(*distance * 10.0) / 10.0)
      << " mm outside the tools the model was calibrated with, " << tools
      << " mm: errors that act through the tool's lever arms are extrapolated\n";
}

model::EvalMode evalMode(const EvalOptions& options) {
  return options.mode == "first-order" ? model::EvalMode::FirstOrder : model::EvalMode::Exact;
}

int evalChain(const EvalOptions& options, const model::DhChainSpec& spec, std::ostream& out) {
  if (!options.tool.empty() || !options.direction.empty() || !options.points.empty()) {
    throw UsageError("--tool, --direction and --points apply to 3-axis models, not to D-H chains");
  }
  const model::DhChain chain(spec);
  const std::vector<double> given =
      parseNumberList(options.at, "--at (one value per joint: mm prismatic, deg revolute)",
                      static_cast<std::size_t>(chain.jointCount()));
  std::vector<double> joints;
  std::size_t next = 0;
  for (const model::DhLinkSpec& link : spec.links) {
    if (link.joint == model::JointType::Prismatic) joints.push_back(given[next++]);
    if (link.joint == model::JointType::Revolute) {
      joints.push_back(given[next++] * std::numbers::pi / 180.0);
    }
  }
  const model::DhResult r = chain.evaluate(joints.data());
  if (options.json) {
    OrderedJson o;
    o["position"] = given;
    o["error"] = jsonVector(r.errorMm);
    o["angular_error"] = jsonVector(r.angularErrorRad);
    o["T_nominal"] = jsonMatrix(r.tNominal);
    o["T_actual"] = jsonMatrix(r.tActual);
    out << o.dump() << '\n';
    return kExitOk;
  }
  std::string joined;
  for (double v : given) joined += (joined.empty() ? "" : ", ") + formatDouble(v);
  out << "chain          " << (spec.name.empty() ? std::string("(unnamed)") : spec.name) << ", "
      << spec.links.size() << " links, " << chain.jointCount() << " joints\n"
      << "joints         " << joined << "  (mm prismatic, deg revolute)\n"
      << "error          " << lengthTriple(r.errorMm) << '\n'
      << "angular error  " << angleTriple(r.angularErrorRad, options.angleUnit) << '\n'
      << "T_nominal\n"
      << matrixText(r.tNominal) << "T_actual\n"
      << matrixText(r.tActual);
  return kExitOk;
}

int evalPoint(const EvalOptions& options, const model::MachineModel& model,
              const model::Directions& directions, std::ostream& out, std::ostream& err) {
  const std::vector<double> at = parseNumberList(options.at, "--at X,Y,Z (mm)", 3);
  const Eigen::Vector3d qMm(at[0], at[1], at[2]);
  model::Workspace ws;
  const model::EvalMode mode = evalMode(options);
  const model::PointError e = model::evaluate(model, ws, qMm, directions, mode);
  model::OffsetOptions offsetOptions;
  offsetOptions.mode = mode;
  const model::OffsetSolution o = model::solveOffset(model, ws, qMm, directions, offsetOptions);
  warnClamped(err, model.spec(), e.clampedAxes);
  if (options.json) {
    OrderedJson j;
    j["position"] = jsonVector(qMm);
    j["error"] = jsonVector(e.errorMm);
    j["angular_error"] = jsonVector(e.angularErrorRad);
    j["offset"] = jsonVector(o.offsetMm);
    out << j.dump() << '\n';
  } else {
    const model::MachineModelSpec& spec = model.spec();
    out << "model          " << (spec.name.empty() ? std::string("(unnamed)") : spec.name) << " ("
        << spec.topology << ")\n"
        << "position       " << triple(qMm) << "  mm\n"
        << "tool           " << triple(spec.toolMm) << "  mm\n"
        << "error          " << lengthTriple(e.errorMm) << '\n'
        << "angular error  " << angleTriple(e.angularErrorRad, options.angleUnit) << '\n'
        << "offset         " << lengthTriple(o.offsetMm) << " ("
        << (o.converged ? "converged" : "NOT converged") << " in " << o.iterations
        << " iterations, residual " << formatDouble(o.residualMm) << " mm)\n";
  }
  if (!o.converged) {
    err << "volcomp eval: the compensation offset did not converge (residual "
        << formatDouble(o.residualMm) << " mm after " << o.iterations
        << " iterations): the printed offset is not reliable\n";
    return kExitNotConverged;
  }
  return kExitOk;
}

int evalPoints(const EvalOptions& options, const config::ModelDocument& doc,
               const model::MachineModel& model, const model::Directions& directions,
               std::ostream& err) {
  const PointsSummary s = evaluatePointsFile(model, directions, evalMode(options), options.points,
                                             options.out, {options.modelPath});
  for (std::size_t t = 0; t < s.toolsMm.size(); ++t) {
    warnFarTool(err, doc, s.toolsMm[t],
                " (first at " + options.points + " line " + std::to_string(s.toolLines[t]) + ")");
  }
  if (s.clampedRows > 0) {
    err << "volcomp eval: warning: " << s.clampedRows << " of " << s.rows
        << " points outside the travel (first at " << options.points << " line "
        << s.firstClampedLine << "): error functions evaluated at the nearest end of the travel\n";
  }
  if (s.notConvergedRows > 0) {
    err << "volcomp eval: the compensation offset did not converge for " << s.notConvergedRows
        << " of " << s.rows << " points (first at " << options.points << " line "
        << s.firstNotConvergedLine << "): those offsets in " << options.out
        << " are not reliable\n";
    return kExitNotConverged;
  }
  return kExitOk;
}

}  // namespace

CLI::App* addEvalVerb(CLI::App& app, EvalOptions& options) {
  CLI::App* verb = app.add_subcommand(
      "eval",
      "Evaluate a model: volumetric error E = p - p0 (mm, workpiece frame), angular error "
      "(rotation vector, rad) and compensation offset o with p(q + o) = p0(q) (mm).");
  verb->add_option("model", options.modelPath, "Model file (volcomp-model/1 JSON)")->required();
  CLI::Option* at = verb->add_option(
      "--at", options.at,
      "Point X,Y,Z in mm; for a D-H chain one value per joint in chain order (mm prismatic, "
      "deg revolute)");
  CLI::Option* points = verb->add_option(
      "--points", options.points,
      "CSV file with columns x,y,z [,tx,ty,tz] [,direction] in any order (mm unless a suffix such "
      "as x_um says; '#' comments): per-point tool offset and direction of travel");
  CLI::Option* outFile = verb->add_option(
      "--out", options.out,
      "CSV output: x,y,z,ex,ey,ez,ea,eb,ec,ox,oy,oz (mm, rad), then tx,ty,tz and direction when "
      "the input has them");
  at->excludes(points);
  points->needs(outFile);
  outFile->needs(points);
  verb->add_option("--tool", options.tool, "Tool offset TX,TY,TZ in mm (overrides the model's)");
  verb->add_option("--direction", options.direction,
                   "Direction of travel per axis, e.g. +,-,+ (0 = unknown: mean of the "
                   "bidirectional curves, the default)");
  verb->add_option("--mode", options.mode, "exact (the reference) or first-order (small angles)")
      ->check(CLI::IsMember({"exact", "first-order"}));
  verb->add_flag("--json", options.json,
                 "Print one JSON object {position, error, angular_error, offset} (D-H chains: "
                 "{position, error, angular_error, T_nominal, T_actual})");
  verb->add_option("--angle-unit", options.angleUnit,
                   "Angles on screen: urad (default) or arcsec (--json and CSV: rad)")
      ->check(CLI::IsMember({"urad", "arcsec"}));
  verb->footer(
      "On screen lengths are in um and angles in urad (or arcsec) to 4 significant digits; "
      "--json and the CSV of --points keep mm and rad at full precision.\n"
      "Exit status: 0 success; 2 bad arguments or bad file (one line on stderr); 3 results "
      "printed but a compensation offset did not converge. Points outside the travel are "
      "evaluated at the nearest end of the travel, with a warning on stderr.");
  return verb;
}

int runEval(const EvalOptions& options, std::ostream& out, std::ostream& err) {
  if (options.at.empty() && options.points.empty()) {
    throw UsageError("eval: give --at X,Y,Z or --points IN.csv --out OUT.csv");
  }
  const config::ModelDocument doc = config::loadModelFile(options.modelPath);
  if (const auto* chain = std::get_if<model::DhChainSpec>(&doc.spec)) {
    return evalChain(options, *chain, out);
  }
  model::MachineModelSpec spec = std::get<model::MachineModelSpec>(doc.spec);
  if (!options.tool.empty()) {
    const std::vector<double> t = parseNumberList(options.tool, "--tool TX,TY,TZ (mm)", 3);
    spec.toolMm = Eigen::Vector3d(t[0], t[1], t[2]);
  }
  const model::Directions directions =
      options.direction.empty() ? model::Directions{} : parseDirections(options.direction);
  const model::MachineModel model(std::move(spec));
  if (!options.points.empty()) return evalPoints(options, doc, model, directions, err);
  warnFarTool(err, doc, model.toolMm(), "");
  return evalPoint(options, model, directions, out, err);
}

}  // namespace volcomp::cli
