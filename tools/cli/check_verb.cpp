#include "check_verb.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <ostream>
#include <variant>

#include "cli_support.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/model/dh_chain.hpp"
#include "volcomp/model/machine_model.hpp"

namespace volcomp::cli {
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;
constexpr int kPolynomialSamples = 1001;

// A summary is read by people: 15 significant digits hide the last-bit noise of unit conversions
// (0.0010835 deg, not 0.0010835000000000003).
std::string formatDouble(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.15g", value + 0.0);
  return buffer;
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
  const double factor = translation ? units.lengthToMm : units.angleToRad;
  const std::string unit = translation ? units.length : units.angle;
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
      line += ", peak |value| unbounded (no travel given for this axis)";
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

void describeMachine(std::ostream& out, const model::MachineModelSpec& spec,
                     const config::ModelDocument& doc) {
  out << "name        " << (spec.name.empty() ? std::string("(unnamed)") : spec.name) << '\n'
      << "topology    " << spec.topology << '\n'
      << "travel      ";
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
      << "error units length " << doc.units.length << ", angle " << doc.units.angle << '\n';
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
        << formatDouble(spec.locationRad[i] / doc.units.angleToRad) << " " << doc.units.angle
        << '\n';
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
    out << " mm, peak |value| " << formatDouble(peakOf(g.valuesMm) / doc.units.lengthToMm) << ' '
        << doc.units.length << '\n';
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
  verb->add_option("model", options.modelPath, "Model file (volcomp-model/1 JSON)")->required();
  verb->add_flag("--template", options.calibrationTemplate,
                 "Accept a calibration template (\"identify\" blocks) and list what it identifies");
  verb->footer(
      "Exit status: 0 valid; 2 invalid (one line on stderr: file, key path, expectation).");
  return verb;
}

int runCheck(const CheckOptions& options, std::ostream& out) {
  config::ParseOptions parse;
  parse.allowIdentify = options.calibrationTemplate;
  const config::ModelDocument doc = config::loadModelFile(options.modelPath, parse);
  out << "file        " << options.modelPath << ": valid volcomp-model/1\n";
  if (const auto* chain = std::get_if<model::DhChainSpec>(&doc.spec)) {
    describeChain(out, *chain);
  } else {
    describeMachine(out, std::get<model::MachineModelSpec>(doc.spec), doc);
  }
  if (options.calibrationTemplate) {
    out << "identify    " << doc.identify.size() << " block(s)\n";
    for (const auto& [path, block] : doc.identify)
      out << "  " << path << ": " << block.dump() << '\n';
  }
  return kExitOk;
}

}  // namespace volcomp::cli
