// The plausibility check of config/model_plausibility.hpp: what `volcomp check`, `volcompd
// --check-config` and every reload refuse before a model may compensate a machine. One test per
// refusal, with the message's key path and hint, and the example models passing.

#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "volcomp/config/config_error.hpp"
#include "volcomp/config/daemon_config.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/config/model_plausibility.hpp"

namespace volcomp::config {
namespace {

ModelDocument docOf(const std::string& text) {
  return parseModel(nlohmann::json::parse(text), "m.json");
}

// The VMC's positioning error as a laser gives it (um), and the same numbers typed under mm.
constexpr const char* kLaserInUm = R"({"format": "volcomp-model/1", "topology": "XYFZ",
  "travel": {"X": [0, 850], "Y": [0, 500], "Z": [-500, 0]}, "tool": [0, 0, 120],
  "error_units": {"length": "um", "angle": "urad"},
  "components": {"EXX": {"positions": [0, 425, 850], "values": [0, 8.7, 15.6]}, "EC0Y": 18.5}})";
constexpr const char* kLaserTypedAsMm = R"({"format": "volcomp-model/1", "topology": "XYFZ",
  "travel": {"X": [0, 850], "Y": [0, 500], "Z": [-500, 0]}, "tool": [0, 0, 120],
  "error_units": {"length": "mm", "angle": "urad"},
  "components": {"EXX": {"positions": [0, 425, 850], "values": [0, 8.7, 15.6]}, "EC0Y": 18.5}})";

std::string refusal(const ModelDocument& doc, const std::optional<OffsetBound>& bound = {}) {
  try {
    checkPlausible(doc, bound);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

void expectContains(const std::string& text, const std::string& fragment) {
  EXPECT_NE(text.find(fragment), std::string::npos) << text << "\nlacks: " << fragment;
}

TEST(ModelPlausibility, AcceptsARealisticModelAndReportsItsPeaks) {
  const auto assessment = checkPlausible(docOf(kLaserInUm), std::nullopt);
  ASSERT_TRUE(assessment);
  EXPECT_NEAR(assessment->motionPeak[0], 15.6e-3, 1e-12);  // EXX at X = 850
  EXPECT_EQ(assessment->motionPeakAtMm[0], 850.0);
  EXPECT_EQ(assessment->gridPoints[0], kPlausibilityGridPoints);
  // XYFZ: X is the table, EXX = +15.6 um moves the workpiece: E_x = -15.6 um; EC0Y = 18.5 urad
  // adds -y * 18.5 urad: o_x ~ +15.6 + 9.25 um at (850, 500).
  EXPECT_NEAR(assessment->peakOffsetMm[0], 24.85e-3, 1e-5);
  EXPECT_LT(assessment->peakErrorMm, 0.03);
}

TEST(ModelPlausibility, RefusesMicrometresTypedAsMillimetresAndSaysSo) {
  const std::string message = refusal(docOf(kLaserTypedAsMm));
  expectContains(message, "m.json");
  expectContains(message, "components.EXX");
  expectContains(message, "implausible for a machine tool");
  expectContains(message, "15.6 mm");
  expectContains(message, "Were values in um entered as mm?");
  expectContains(message, "\"plausibility\"");
}

TEST(ModelPlausibility, RefusesAFileWithoutErrorUnits) {
  const std::string message = refusal(docOf(R"({"format": "volcomp-model/1", "topology": "FXYZ",
    "components": {"EXX": 0.002}})"));
  expectContains(message, "m.json: error_units");
  expectContains(message, "missing");
}

TEST(ModelPlausibility, RefusesImplausibleAnglesAndLocationErrors) {
  expectContains(refusal(docOf(R"({"format": "volcomp-model/1", "topology": "FXYZ",
    "error_units": {"length": "um", "angle": "mrad"}, "components": {"EBX": 12}})")),
                 "components.EBX");
  const std::string location = refusal(docOf(R"({"format": "volcomp-model/1", "topology": "FXYZ",
    "error_units": {"length": "um", "angle": "rad"}, "components": {"EC0Y": 18.5}})"));
  expectContains(location, "components.EC0Y");
  expectContains(location, "Were values in urad entered as rad?");
}

TEST(ModelPlausibility, RefusesAnImplausibleGrid) {
  expectContains(refusal(docOf(R"({"format": "volcomp-model/1", "topology": "FXYZ",
    "error_units": {"length": "mm", "angle": "urad"},
    "grids": [{"component": "EZ", "over": ["X", "Y"], "axes": {"X": [0, 100], "Y": [0, 100]},
               "values": [[0, -13], [-4.7, -46.7]]}]})")),
                 "grids[0].values");
}

TEST(ModelPlausibility, TheFileMayRaiseTheLimitsExplicitly) {
  const std::string text = R"({"format": "volcomp-model/1", "topology": "FXYZ",
    "travel": {"X": [0, 4000]}, "error_units": {"length": "um", "angle": "urad"},
    "plausibility": {"max_length_mm": 2.5},
    "components": {"EXX": {"positions": [0, 4000], "values": [0, 1800]}}})";
  EXPECT_EQ(refusal(docOf(text)), "");
  ModelDocument defaults = docOf(text);
  defaults.plausibility = PlausibilityLimits{};
  expectContains(refusal(defaults), "the default plausibility limit");
}

TEST(ModelPlausibility, RefusesAVolumetricErrorBeyondTheLimitFromAngleTimesArm) {
  // 5 mrad of pitch is plausible alone; on a 300 mm tool it moves the tip by 1.5 mm.
  const std::string message = refusal(docOf(R"({"format": "volcomp-model/1", "topology": "FXYZ",
    "travel": {"X": [0, 100], "Y": [0, 100], "Z": [0, 100]}, "tool": [0, 0, 300],
    "error_units": {"length": "um", "angle": "mrad"}, "components": {"EBX": 5}})"));
  expectContains(message, "the volumetric error reaches");
  expectContains(message, "tool length");
}

// Every refusal is one line that names the file and stays under 300 characters, even with an
// installed path and the longest hints (a unit typed wrongly, the override, the limiter's file).
TEST(ModelPlausibility, EveryRefusalIsOneShortLineNamingTheFile) {
  const std::string file = "/etc/volcomp/vmc-850.json";
  const auto refusalOf = [&](const std::string& text, const std::optional<OffsetBound>& bound) {
    return refusal(parseModel(nlohmann::json::parse(text), file), bound);
  };
  OffsetBound bound;
  bound.maxOffsetMm = {0.01, 0.01, 0.01};
  bound.source = "limiter.max_offset_mm of /etc/volcomp/volcompd.json";
  const std::vector<std::string> refusals = {
      refusalOf(kLaserTypedAsMm, std::nullopt),
      refusalOf(kLaserInUm, bound),
      refusalOf(R"({"format": "volcomp-model/1", "topology": "FXYZ",
        "error_units": {"length": "um", "angle": "mrad"}, "components": {"EBX": 12}})",
                std::nullopt),
      refusalOf(R"({"format": "volcomp-model/1", "topology": "FXYZ",
        "error_units": {"length": "um", "angle": "rad"}, "components": {"EC0Y": 18.5}})",
                std::nullopt),
      refusalOf(R"({"format": "volcomp-model/1", "topology": "FXYZ",
        "travel": {"X": [0, 100], "Y": [0, 100], "Z": [0, 100]}, "tool": [0, 0, 300],
        "error_units": {"length": "um", "angle": "mrad"}, "components": {"EBX": 5}})",
                std::nullopt),
      refusalOf(R"({"format": "volcomp-model/1", "topology": "FXYZ",
        "error_units": {"length": "mm", "angle": "urad"},
        "grids": [{"component": "EZ", "over": ["X", "Y"], "axes": {"X": [0, 100], "Y": [0, 100]},
                   "values": [[0, -13], [-4.7, -46.7]]}]})",
                std::nullopt),
  };
  for (const std::string& message : refusals) {
    EXPECT_EQ(message.rfind(file + ": ", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_LE(message.size(), 300u) << message;
  }
}

TEST(ModelPlausibility, RefusesAModelThatEvaluatesToInfinity) {
  // Each coefficient is a finite number; the polynomial overflows over the travel. The reader
  // refuses such a model before any plausibility check sees it (config/model_finite.hpp), so
  // the refusal is the reader's, naming where the error stops being finite.
  try {
    docOf(R"({"format": "volcomp-model/1", "topology": "FXYZ",
    "travel": {"X": [0, 1000]}, "error_units": {"length": "mm", "angle": "urad"},
    "plausibility": {"max_length_mm": 1000, "max_angle_rad": 1},
    "components": {"EXX": {"polynomial": [0, 0, 1e306]}}})");
    ADD_FAILURE() << "a model that evaluates to infinity was read";
  } catch (const ConfigError& e) {
    expectContains(e.what(), "components.EXX");
    expectContains(e.what(), "not finite");
  }
}

TEST(ModelPlausibility, RefusesOffsetsBeyondTheLimiter) {
  OffsetBound bound;
  bound.maxOffsetMm.fill(0.01);
  bound.source = "limiter.max_offset_mm of volcompd.json";
  const std::string message = refusal(docOf(kLaserInUm), bound);
  expectContains(message, "the model asks for an offset of 24.85 um on X at (850, 500");
  expectContains(message, "beyond 10 um (limiter.max_offset_mm of volcompd.json)");
  bound.maxOffsetMm.fill(0.1);
  EXPECT_EQ(refusal(docOf(kLaserInUm), bound), "");
}

TEST(ModelPlausibility, TheDaemonConfigurationGivesTheBoundUnlessItAcceptsBeyond) {
  DaemonConfig config;
  config.file = "volcompd.json";
  for (loop::AxisLimits& a : config.limiter.axes) a.maxOffsetMm = 0.05;
  const auto bound = offsetBoundOf(config);
  ASSERT_TRUE(bound);
  EXPECT_EQ(bound->maxOffsetMm[2], 0.05);
  expectContains(bound->source, "volcompd.json");
  config.acceptModelBeyondMaxOffset = true;
  EXPECT_FALSE(offsetBoundOf(config));
}

TEST(ModelPlausibility, APolynomialWithoutTravelIsRefusedWhenRead) {
  try {
    docOf(R"({"format": "volcomp-model/1", "topology": "FXYZ",
      "error_units": {"length": "um", "angle": "urad"},
      "components": {"EYX": {"polynomial": [0, 0.01, 2e-5]}}})");
    FAIL() << "accepted a polynomial without travel";
  } catch (const ConfigError& e) {
    expectContains(e.what(), "components.EYX");
    expectContains(e.what(), "needs the travel of axis X");
  }
  // A constant polynomial is bounded; with the travel a polynomial is held at its ends.
  EXPECT_NO_THROW(docOf(R"({"format": "volcomp-model/1", "topology": "FXYZ",
    "error_units": {"length": "um", "angle": "urad"}, "components": {"EYX": {"polynomial": [3]}}})"));
}

TEST(ModelPlausibility, EveryExampleModelPasses) {
  for (const char* name : {"vmc-xyfz-21.json", "vmc-xyfz-21-true.json", "gantry-fxyz-grid.json",
                           "cartesian-table-dh.json"}) {
    const ModelDocument doc = loadModelFile(std::string(VOLCOMP_EXAMPLES_DIR) + "/" + name);
    OffsetBound bound;
    bound.maxOffsetMm.fill(0.1);  // the example daemon configurations' limiter
    bound.source = "the examples' limiter";
    EXPECT_NO_THROW(checkPlausible(doc, bound)) << name;
  }
}

}  // namespace
}  // namespace volcomp::config
