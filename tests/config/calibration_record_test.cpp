// The optional "calibration" block of model files: read, written back, rejected with key paths,
// and the distance of a tool from the calibrated tools.

#include <gtest/gtest.h>

#include <cmath>

#include "volcomp/config/model_file.hpp"

namespace volcomp::config {
namespace {

nlohmann::json modelWith(const nlohmann::json& calibration) {
  return {{"format", "volcomp-model/1"},
          {"topology", "XYFZ"},
          {"components", {{"EXX", 1.0}}},
          {"calibration", calibration}};
}

TEST(CalibrationRecord, ReadFromAModelFileAndWrittenBack) {
  const nlohmann::json block = nlohmann::json::parse(R"({
    "volcomp_version": "0.1.0", "date": "2026-12-01T19:40:00Z",
    "template": "t.json", "measurements": ["a.csv", "b.csv"], "validation": "v.csv",
    "points": 8316, "parameter_count": 125, "rank": 122,
    "residual_rms_mm": {"before": 0.0158, "after": 0.00086, "validation": 0.0009},
    "s0_mm": 0.0005, "not_identifiable": ["EAX[0]", "EAY[0]"],
    "tools_mm": [[0, 0, 120], [0, 0, 220]]})");
  const ModelDocument doc = parseModel(modelWith(block), "m.json");
  ASSERT_TRUE(doc.calibration.has_value());
  const CalibrationRecord& r = *doc.calibration;
  EXPECT_EQ(r.volcompVersion, "0.1.0");
  EXPECT_EQ(r.measurementFiles, (std::vector<std::string>{"a.csv", "b.csv"}));
  EXPECT_EQ(r.rank, 122);
  EXPECT_EQ(r.residualRmsValidationMm, 0.0009);
  EXPECT_EQ(r.notIdentifiable.size(), 2u);
  ASSERT_EQ(r.toolsMm.size(), 2u);
  EXPECT_EQ(r.toolsMm[1], Eigen::Vector3d(0, 0, 220));
  EXPECT_EQ(writeCalibrationRecord(r), block);
  // Without the block there is no record, and the numbers of the model do not depend on it.
  nlohmann::json plain = modelWith(block);
  plain.erase("calibration");
  EXPECT_FALSE(parseModel(plain, "m.json").calibration.has_value());
}

TEST(CalibrationRecord, BadBlocksNameTheKeyPath) {
  const auto error = [](const nlohmann::json& block) {
    try {
      parseModel(modelWith(block), "m.json");
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error({{"tools_mm", {{0, 0}}}}).find("m.json: calibration.tools_mm[0]"),
            std::string::npos);
  EXPECT_NE(error({{"rank", -1}}).find("calibration.rank"), std::string::npos);
  EXPECT_NE(error({{"residual_rms_mm", {{"during", 1}}}}).find("calibration.residual_rms_mm.during"),
            std::string::npos);
  EXPECT_NE(error({{"operator", "me"}}).find("calibration.operator: unknown key"),
            std::string::npos);
}

TEST(CalibrationRecord, ToolDistanceIsToTheHullOfTheCalibratedTools) {
  CalibrationRecord r;
  EXPECT_FALSE(toolDistanceMm(r, Eigen::Vector3d(0, 0, 100)).has_value());
  r.toolsMm = {Eigen::Vector3d(0, 0, 120)};
  EXPECT_DOUBLE_EQ(*toolDistanceMm(r, Eigen::Vector3d(0, 0, 120)), 0.0);
  EXPECT_DOUBLE_EQ(*toolDistanceMm(r, Eigen::Vector3d(3, 0, 124)), 5.0);
  // Two lengths: everything between them is interpolated (distance 0), beyond is not.
  r.toolsMm.push_back(Eigen::Vector3d(0, 0, 220));
  r.toolsMm.push_back(Eigen::Vector3d(0, 0, 220));  // repeated tools count once
  EXPECT_NEAR(*toolDistanceMm(r, Eigen::Vector3d(0, 0, 170)), 0.0, 1e-12);
  EXPECT_NEAR(*toolDistanceMm(r, Eigen::Vector3d(0, 0, 250)), 30.0, 1e-12);
  EXPECT_NEAR(*toolDistanceMm(r, Eigen::Vector3d(4, 0, 170)), 4.0, 1e-12);
  // The cross of the end-to-end test: the convex hull is a tetrahedron.
  r.toolsMm = {Eigen::Vector3d(0, 0, 120), Eigen::Vector3d(0, 0, 220),
               Eigen::Vector3d(100, 0, 120), Eigen::Vector3d(0, 100, 120)};
  EXPECT_NEAR(*toolDistanceMm(r, Eigen::Vector3d(20, 20, 140)), 0.0, 1e-12);
  EXPECT_NEAR(*toolDistanceMm(r, Eigen::Vector3d(20, 20, 100)), 20.0, 1e-12);  // below the base
  // Beyond the slanted face x/100 + y/100 + (z - 120)/100 = 1: distance along its normal.
  const Eigen::Vector3d outside(60, 60, 140);
  const double expected = (0.6 + 0.6 + 0.2 - 1.0) * 100.0 / std::sqrt(3.0);
  EXPECT_NEAR(*toolDistanceMm(r, outside), expected, 1e-9);
  EXPECT_GT(kCalibratedToolToleranceMm, 0.0);
}

}  // namespace
}  // namespace volcomp::config
