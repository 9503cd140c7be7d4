// The settings of a calibration and of a plan check themselves: isValid names the setting that
// cannot be used and what it must be, before any work.

#include <gtest/gtest.h>

#include <string>

#include "volcomp/calibration/calibrate.hpp"
#include "volcomp/calibration/planning.hpp"

namespace volcomp::calibration {
namespace {

using Field = CalibrationSettings::Field;

// The first setting isValid refuses, as "field: expected" text ("" when valid).
std::string refusal(const CalibrationSettings& settings) {
  std::string error;
  Field field{};
  if (settings.isValid(&error, &field)) return "";
  return std::to_string(static_cast<int>(field)) + ": " + error;
}

std::string expected(Field field, const std::string& text) {
  return std::to_string(static_cast<int>(field)) + ": " + text;
}

TEST(CalibrationSettings, DefaultsAreValidAndEachBadValueIsNamed) {
  EXPECT_EQ(refusal(CalibrationSettings{}), "");
  EXPECT_TRUE(CalibrationSettings{}.isValid(nullptr));

  CalibrationSettings s;
  s.lossScaleMm = 0.0;
  EXPECT_EQ(refusal(s), expected(Field::LossScale, "expected > 0"));
  s = {};
  s.rankTolerance = 1.0;
  EXPECT_EQ(refusal(s), expected(Field::RankTolerance, "expected a value in (0, 1)"));
  s = {};
  s.method = MethodChoice::Linear;
  s.loss = RobustLoss::Huber;
  EXPECT_EQ(refusal(s), expected(Field::Loss,
                                 "a robust loss needs the Levenberg-Marquardt "
                                 "method (or auto)"));
  s.method = MethodChoice::Auto;
  EXPECT_EQ(refusal(s), "");
  s = {};
  s.maxIterations = 0;
  EXPECT_EQ(refusal(s), expected(Field::MaxIterations, "expected >= 1"));
  s = {};
  s.identification.angleScaleMm = -1.0;
  EXPECT_EQ(refusal(s), expected(Field::AngleScale, "expected > 0"));
  for (int folds : {1, -2}) {
    s = {};
    s.folds = folds;
    EXPECT_EQ(refusal(s), expected(Field::Folds, "expected k >= 2")) << folds;
  }
  s.folds = 2;
  EXPECT_EQ(refusal(s), "");
}

TEST(PlanOptions, EachBadValueIsNamed) {
  PlanOptions options;
  std::string error;
  PlanOptions::Field field{};
  EXPECT_FALSE(options.isValid(&error, &field));  // no points asked for
  EXPECT_EQ(field, PlanOptions::Field::Points);
  EXPECT_EQ(error, "expected N >= 1");
  options.points = 4;
  EXPECT_TRUE(options.isValid(&error, &field));
  options.noiseMm = 0.0;
  EXPECT_FALSE(options.isValid(&error, &field));
  EXPECT_EQ(field, PlanOptions::Field::Noise);
  EXPECT_EQ(error, "expected > 0 (mm)");
  options.noiseMm = 1e-3;
  options.rankTolerance = 0.0;
  EXPECT_FALSE(options.isValid(&error, &field));
  EXPECT_EQ(field, PlanOptions::Field::RankTolerance);
}

}  // namespace
}  // namespace volcomp::calibration
