#include "check_verb.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <ostream>
#include <variant>

#include "cli_support.hpp"
#include "model_schema.hpp"
#include "volcomp/config/daemon_config.hpp"
#include "volcomp/config/display_units.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/config/model_plausibility.hpp"
#include "volcomp/format/numbers.hpp"
#include "volcomp/model/dh_chain.hpp"
#include "volcomp/model/machine_model.hpp"

namespace volcomp::cli {
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;
constexpr int kPolynomialSamples = 1001;

// A summary is read by people: 15 significant digits hide the last-bit noise of unit conversions
// (0.0010835 deg, not 0.0010835000000000003).
std::string formatDouble(double value) {
  return format::general(value + 0.0, 15);
}

std::string range(double lo, double hi) {
  return "[" + formatDouble(lo) + ", " + formatDouble(hi) + "]";
}

double peakOf(const std::vector<double>& values) {
  double peak = 0.0;
  for (double v : values) peak = std::max(peak, std::abs(v));
  return peak;
}

double polynomialAt(const std::vector<double>& c, double q) {
  double value = 0.0;
  for (auto it = c.rbegin(); it != c.rend(); ++it) value = value * q + *it;
  return value;
}

// One line per component: kind, range, peak |value| in the file's units, direction dependence.
void describeMotion(std::ostream& out, const model::MachineModelSpec& spec, int index,
                    const config::ErrorUnits& units) {
  const model::ErrorFunctionSpec& f = spec.motion[index];
  const bool translation = index % 6 < 3;
  const double factor = translation ? units.lengthToMm() : units.angleToRad();
  const std::string unit =
      translation ? config::unitName(units.length) : config::unitName(units.angle);
  const auto& travel = spec.travelMm[index / 6];
  std::string line = "  " + model::motionName(index) + "  ";
  if (const double* c = std::get_if<double>(&f)) {
    line += "constant, value " + formatDouble(*c / factor) + " " + unit;
  } else if (const auto* p = std::get_if<model::PolynomialSpec>(&f)) {
    line += "polynomial of degree " + std::to_string(p->coefficients.size() - 1);
    if (travel) {
      double peak = 0.0;
      for (int i = 0; i < kPolynomialSamples; ++i) {
        const double q =
            (*travel)[0] + ((*travel)[1] - (*travel)[0]) * i / (kPolynomialSamples - 1);
        peak = std::max(peak, std::abs(polynomialAt(p->coefficients, q)));
      }
      line += " over the travel " + range((*travel)[0], (*travel)[1]) + " mm, peak |value| " +
              formatDouble(peak / factor) + " " + unit + " (sampled at " +
              std::to_string(kPolynomialSamples) + " points)";
    } else {
      // The file reader refuses a polynomial of degree >= 1 without the travel.
      line += ", a constant";
    }
  } else {
    const auto& t = std::get<model::TableSpec>(f);
    const double lo = t.positionsMm.front();
    const double hi = t.positionsMm.back();
    line += std::string("table, ") + config::interpolationName(t.interpolation) + ", " +
            std::to_string(t.positionsMm.size()) + " nodes over " + range(lo, hi) +
            " mm, peak |value| " +
            formatDouble(std::max(peakOf(t.values), peakOf(t.valuesNegative)) / factor) + " " +
            unit + (t.valuesNegative.empty() ? ", one direction" : ", bidirectional");
    if (travel && (lo > (*travel)[0] || hi < (*travel)[1])) {
      line += "; note: the travel " + range((*travel)[0], (*travel)[1]) +
              " mm reaches beyond the table, end values are held there";
    }
  }
  out << line << '\n';
}

// Which side of the frame each axis is on decides the sign of what a user types in: an
// instrument reads the tool relative to the workpiece, a motion error moves the axis' carriage.
void describeSides(std::ostream& out, const model::MachineModelSpec& spec) {
  const model::Topology topology = model::Topology::parse(spec.topology);
  for (int axis = 0; axis < 3; ++axis) {
    const bool workpiece = topology.isWorkpieceSide(static_cast<model::Axis>(axis));
    out << (axis == 0 ? "sides       " : "            ") << "XYZ"[axis]
        << (workpiece ? " workpiece side (moves the workpiece): its motion errors = -(reading of "
                        "the tool relative to the workpiece)\n"
                      : " tool side (moves the tool): its motion errors = +(reading of the tool "
                        "relative to the workpiece)\n");
  }
  out << "            squareness and grids = +reading on either side (laser, straightedge, "
         "ball-bar: docs/model-file.md, \"Entering measured data\")\n";
}

void describeAssessment(std::ostream& out, const config::ModelAssessment& a,
                        const config::ModelDocument& doc,
                        const std::optional<config::OffsetBound>& bound,
                        config::AngleDisplay angles) {
  out << "plausible   over " << a.gridPoints[0] << " x " << a.gridPoints[1] << " x "
      << a.gridPoints[2] << " points of";
  for (int axis = 0; axis < 3; ++axis) {
    out << ' ' << "XYZ"[axis] << ' ' << range(a.rangeMm[axis][0], a.rangeMm[axis][1])
        << (a.rangeIsTravel[axis] ? "" : " (no travel: the span of its tables and grids)");
  }
  out << " mm, both directions\n"
      << "  peak |E|      " << config::micrometres(a.peakErrorMm) << " at ("
      << config::significant(a.peakErrorAtMm.x()) << ", "
      << config::significant(a.peakErrorAtMm.y()) << ", "
      << config::significant(a.peakErrorAtMm.z()) << ") mm\n"
      << "  peak angle    " << config::angle(a.peakAngleRad, angles) << '\n'
      << "  peak offset   X " << config::micrometres(a.peakOffsetMm[0]) << ", Y "
      << config::micrometres(a.peakOffsetMm[1]) << ", Z " << config::micrometres(a.peakOffsetMm[2])
      << '\n'
      << "  limits        values and |E| <= " << config::micrometres(doc.plausibility.maxLengthMm)
      << ", angles <= " << config::angle(doc.plausibility.maxAngleRad, angles)
      << (doc.plausibility.stated ? " (the file's)" : " (defaults)");
  if (bound) {
    out << "; offsets <= " << config::micrometres(bound->maxOffsetMm[0]) << " (" << bound->source
        << ")";
  }
  out << '\n';
}

void describeMachine(std::ostream& out, const model::MachineModelSpec& spec,
                     const config::ModelDocument& doc) {
  out << "name        " << (spec.name.empty() ? std::string("(unnamed)") : spec.name) << '\n'
      << "topology    " << spec.topology << '\n';
  describeSides(out, spec);
  out << "travel      ";
  for (int axis = 0; axis < 3; ++axis) {
    out << "XYZ"[axis] << ' '
        << (spec.travelMm[axis] ? range((*spec.travelMm[axis])[0], (*spec.travelMm[axis])[1])
                                : std::string("unbounded"))
        << (axis < 2 ? "  " : " mm\n");
  }
  const auto vec = [](const Eigen::Vector3d& v) {
    return "[" + formatDouble(v.x()) + ", " + formatDouble(v.y()) + ", " + formatDouble(v.z()) +
           "]";
  };
  out << "tool        " << vec(spec.toolMm) << " mm\n"
      << "workpiece   " << vec(spec.workpieceMm) << " mm\n"
      << "error units length " << config::unitName(doc.units.length) << ", angle "
      << config::unitName(doc.units.angle) << '\n';
  int motionCount = 0;
  for (int i = 0; i < 18; ++i) {
    const double* c = std::get_if<double>(&spec.motion[i]);
    motionCount += (c == nullptr || *c != 0.0) ? 1 : 0;
  }
  out << "components  " << motionCount << " motion error(s)\n";
  for (int i = 0; i < 18; ++i) {
    const double* c = std::get_if<double>(&spec.motion[i]);
    if (c == nullptr || *c != 0.0) describeMotion(out, spec, i, doc.units);
  }
  int locationCount = 0;
  for (double v : spec.locationRad) locationCount += v != 0.0 ? 1 : 0;
  out << "location    " << locationCount << " location error(s)\n";
  for (int i = 0; i < 9; ++i) {
    if (spec.locationRad[i] == 0.0) continue;
    out << "  " << model::locationName(i) << " constant, value "
        << formatDouble(spec.locationRad[i] / doc.units.angleToRad()) << " "
        << config::unitName(doc.units.angle) << '\n';
  }
  out << "grids       " << spec.grids.size() << '\n';
  for (const model::GridSpec& g : spec.grids) {
    out << "  E"
        << "XYZ"[g.component] << " over ";
    std::string shape;
    for (std::size_t l = 0; l < g.over.size(); ++l) {
      const char name = "XYZ"[static_cast<int>(g.over[l])];
      out << (l > 0 ? "," : "") << name;
      shape += (l > 0 ? " x " : "") + std::to_string(g.axesMm[l].size());
    }
    out << ": " << shape << " nodes";
    for (std::size_t l = 0; l < g.over.size(); ++l) {
      out << ", "
          << "XYZ"[static_cast<int>(g.over[l])] << ' '
          << range(g.axesMm[l].front(), g.axesMm[l].back());
    }
    out << " mm, peak |value| " << formatDouble(peakOf(g.valuesMm) / doc.units.lengthToMm()) << ' '
        << config::unitName(doc.units.length) << '\n';
  }
}

void describeChain(std::ostream& out, const model::DhChainSpec& spec) {
  const model::DhChain chain(spec);
  out << "name        " << (spec.name.empty() ? std::string("(unnamed)") : spec.name) << '\n'
      << "chain       "
      << (spec.convention == model::DhConvention::Modified ? "modified D-H (mdh)"
                                                           : "standard D-H (dh)")
      << ", " << spec.links.size() << " links, " << chain.jointCount()
      << " joint value(s) for --at\n";
  const auto deg = [](double rad) { return formatDouble(rad * kRadToDeg); };
  const auto vecDeg = [&](const Eigen::Vector3d& v) {
    return "[" + deg(v.x()) + ", " + deg(v.y()) + ", " + deg(v.z()) + "]";
  };
  const auto vecMm = [](const Eigen::Vector3d& v) {
    return "[" + formatDouble(v.x()) + ", " + formatDouble(v.y()) + ", " + formatDouble(v.z()) +
           "]";
  };
  for (std::size_t i = 0; i < spec.links.size(); ++i) {
    const model::DhLinkSpec& l = spec.links[i];
    const char* joint = l.joint == model::JointType::Prismatic  ? "prismatic"
                        : l.joint == model::JointType::Revolute ? "revolute "
                                                                : "fixed    ";
    out << "  link " << i + 1 << "  " << joint << "  ";
    if (l.isTransform) {
      out << "transform rotation " << vecDeg(l.rotationRad) << " deg, translation "
          << vecMm(l.translationMm) << " mm; deviations rotation " << vecDeg(l.dRotationRad)
          << " deg, translation " << vecMm(l.dTranslationMm) << " mm\n";
    } else {
      out << "theta " << deg(l.thetaRad) << " deg, d " << formatDouble(l.dMm) << " mm, a "
          << formatDouble(l.aMm) << " mm, alpha " << deg(l.alphaRad) << " deg; deviations dtheta "
          << deg(l.dThetaRad) << " deg, dd " << formatDouble(l.dDMm) << " mm, da "
          << formatDouble(l.dAMm) << " mm, dalpha " << deg(l.dAlphaRad) << " deg\n";
    }
  }
}

}  // namespace

CLI::App* addCheckVerb(CLI::App& app, CheckOptions& options) {
  CLI::App* verb = app.add_subcommand(
      "check",
      "Validate a model file and summarise it: topology or D-H chain, travel, tool, "
      "units, each component with its kind, range and peak |value| (in the file's "
      "units), grids with shape and peak.");
  CLI::Option* schema = verb->add_flag(
      "--schema", options.printSchema,
      "Print the JSON Schema of the model format (config/schema/volcomp-model-1.schema.json, "
      "for editors; volcomp's reader is the authority) and exit");
  verb->add_option("model", options.modelPath, "Model file (volcomp-model/1 JSON)")
      ->excludes(schema);
  verb->add_flag("--template", options.calibrationTemplate,
                 "Accept a calibration template (\"identify\" blocks) and list what it identifies");
  CLI::Option* config = verb->add_option("--config", options.daemonConfig,
                                         "volcompd configuration: the model's offsets must fit its "
                                         "limiter.max_offset_mm");
  verb->add_option("--max-offset", options.maxOffsetMm,
                   "The model's offsets must fit this limit (mm), as the daemon's limiter")
      ->check(CLI::PositiveNumber)
      ->excludes(config);
  verb->add_option("--angle-unit", options.angleUnit, "Angles on screen: urad (default) or arcsec")
      ->check(CLI::IsMember({"urad", "arcsec"}));
  verb->footer(
      "A 3-axis model is evaluated over a grid of its travel and refused when it has no "
      "error_units, when a value or the volumetric error is implausible for a machine tool "
      "(|value| > 1 mm, angles > 0.01 rad unless the file's \"plausibility\" says otherwise), "
      "when it is NaN or infinite anywhere, or when an offset exceeds --max-offset or the "
      "limiter of --config.\n"
      "Exit status: 0 valid; 2 invalid (one line on stderr: file, key path, expectation).");
  return verb;
}

int runCheck(const CheckOptions& options, std::ostream& out) {
  if (options.printSchema) {
    out << kModelSchema;
    return kExitOk;
  }
  if (options.modelPath.empty()) throw UsageError("check: a model file is required (or --schema)");
  config::ParseOptions parse;
  parse.allowIdentify = options.calibrationTemplate;
  const config::ModelDocument doc = config::loadModelFile(options.modelPath, parse);
  std::optional<config::OffsetBound> bound;
  if (!options.daemonConfig.empty()) {
    bound = config::offsetBoundOf(config::loadDaemonConfig(options.daemonConfig));
  } else if (options.maxOffsetMm > 0.0) {
    bound = config::OffsetBound{};
    bound->maxOffsetMm.fill(options.maxOffsetMm);
    bound->source = "--max-offset";
  }
  // Templates hold start values, not a machine: they are not assessed.
  std::optional<config::ModelAssessment> assessment;
  if (!options.calibrationTemplate) assessment = config::checkPlausible(doc, bound);
  out << "file        " << options.modelPath << ": valid volcomp-model/1\n";
  if (const auto* chain = std::get_if<model::DhChainSpec>(&doc.spec)) {
    describeChain(out, *chain);
  } else {
    describeMachine(out, std::get<model::MachineModelSpec>(doc.spec), doc);
    if (assessment) {
      describeAssessment(out, *assessment, doc, bound,
                         config::angleDisplayFromName(options.angleUnit));
    }
  }
  if (options.calibrationTemplate) {
    out << "identify    " << doc.identify.size() << " block(s)\n";
    for (const auto& [path, block] : doc.identify)
      out << "  " << path << ": " << block.dump() << '\n';
  }
  return kExitOk;
}

}  // namespace volcomp::cli
