// The compensation of programs against models built here: exact vertices, pieces only where the
// offset is not affine, the deviation bound checked independently and densely, reversal moves,
// G91 without accumulation, streaming (nc/compensator.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>

#include "volcomp/nc/compensator.hpp"
#include "volcomp/nc/ngc_reader.hpp"

namespace volcomp::nc {
namespace {

struct Result {
  std::string text;
  NcReport report;
};

Result compensate(const model::MachineModelSpec& spec, const std::string& program,
                  CompensateOptions options = {}, std::optional<Vec3> start = Vec3(0, 0, 0),
                  const WorkOffsets& offsets = {}, const ToolTable& tools = {}) {
  auto model = std::make_shared<const model::MachineModel>(spec);
  OffsetField field(model, model::EvalMode::Exact);
  NgcReader reader("test.ngc", offsets, tools, start, decimalsForTolerance(options.toleranceMm));
  Compensator c(field, options, start);
  StringSource source(program);
  StringSink sink;
  Result r;
  r.report = c.run(reader, source, sink);
  r.text = sink.text();
  return r;
}

// Machine positions after each motion line of a program (read back with the same interpreter).
std::vector<Vec3> endPoints(const std::string& program, const WorkOffsets& offsets = {}) {
  NgcInterpreter in(offsets, {}, Vec3(0, 0, 0), {});
  std::vector<Vec3> points;
  std::istringstream lines(program);
  std::string line;
  while (std::getline(lines, line)) {
    Block b;
    LineError e;
    NgcLine l;
    EXPECT_TRUE(tokenize(line, b, e) && in.execute(b, l, e)) << line << ": " << e.message;
    if (l.motion) points.push_back(l.move.endMm);
  }
  return points;
}

model::MachineModelSpec emptySpec() {
  model::MachineModelSpec s;
  s.topology = "FXYZ";
  s.travelMm = {std::array<double, 2>{-1000, 1000}, std::array<double, 2>{-1000, 1000},
                std::array<double, 2>{-1000, 1000}};
  return s;
}

TEST(Compensator, ZeroModelKeepsTheProgram) {
  const std::string program =
      "%\n(part)\nN10 G21 G90 G17\nN20 G0 X0 Y0 Z5 M3 S1000\nN30 G1 Z-1 F200\n"
      "N40 G1 X100.5 Y-20 (cut)\nN50 G0 Z5\nM30\n%\n";
  const Result r = compensate(emptySpec(), program);
  EXPECT_EQ(r.text,
            "%\n(part)\nN10 G21 G90 G17\nN20 G0 X0 Y0 Z5 M3 S1000\nN30 G1 X0 Y0 Z-1 F200\n"
            "N40 G1 X100.5 Y-20 Z-1 (cut)\nN50 G0 X100.5 Y-20 Z5\nM30\n%\n");
  EXPECT_EQ(r.report.piecesAdded, 0);
  EXPECT_EQ(r.report.rapidMoves, 2);
  EXPECT_EQ(r.report.feedMoves, 2);
  EXPECT_EQ(r.report.linesIn, 9);
  EXPECT_EQ(r.report.linesOut, 9);
}

TEST(Compensator, ConstantErrorShiftsEveryPoint) {
  model::MachineModelSpec s = emptySpec();
  s.motion[motionIndex(model::Axis::X, model::MotionKind::EX)] = 0.01;  // EXX = 10 um
  const Result r = compensate(s, "G0 X10 Y0 Z0\nG1 X500 Y300 Z-50 F100\n");
  const std::vector<Vec3> p = endPoints(r.text);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_NEAR(p[0].x(), 9.99, 1e-9);
  EXPECT_NEAR(p[1].x(), 499.99, 1e-9);
  EXPECT_NEAR(p[1].y(), 300.0, 1e-9);
  EXPECT_EQ(r.report.piecesAdded, 0);
  EXPECT_NEAR(r.report.peakOffsetMm, 0.01, 1e-12);
}

TEST(Compensator, AffineOffsetStaysOneMove) {
  // Squareness and constant angles with a tool: the error is affine in q, so is the offset.
  model::MachineModelSpec s = emptySpec();
  s.locationRad[model::locationIndex(model::Axis::Y, 2)] = 50e-6;
  s.locationRad[model::locationIndex(model::Axis::Z, 1)] = -30e-6;
  s.toolMm = Vec3(0, 0, 100);
  const Result r = compensate(s, "G0 X0 Y0 Z0\nG1 X800 Y-600 Z-400 F100\nG1 X-800 Y600 Z400\n");
  EXPECT_EQ(r.report.piecesAdded, 0) << r.text;
  EXPECT_LT(r.report.maxDeviationMm, 1e-5);
}

double pointSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

// Distance between the written polyline and the ideal compensated curve of the straight move
// from -> to, both ways, sampled every 0.02 mm, with the model evaluated here (not by the
// compensation). Both run forward, so each point is looked up near the previous match.
double denseDeviation(const model::MachineModelSpec& spec, const Vec3& from, const Vec3& to,
                      const std::vector<Vec3>& written) {
  const model::MachineModel m(spec);
  model::Workspace ws;
  const int n = static_cast<int>(std::ceil((to - from).norm() / 0.02));
  std::vector<Vec3> ideal;
  for (int i = 0; i <= n; ++i) {
    const Vec3 q = from + (static_cast<double>(i) / n) * (to - from);
    ideal.push_back(q + model::solveOffset(m, ws, q).offsetMm);
  }
  const auto distance = [](const Vec3& p, const std::vector<Vec3>& line, std::size_t& cursor) {
    double best = 1e300;
    const std::size_t lo = cursor > 50 ? cursor - 50 : 0;
    for (std::size_t k = lo; k + 1 < line.size() && k < cursor + 300; ++k) {
      const double d = pointSegment(p, line[k], line[k + 1]);
      if (d < best) {
        best = d;
        cursor = k;
      }
    }
    return best;
  };
  double worst = 0.0;
  std::size_t cursor = 0;
  for (const Vec3& p : ideal) worst = std::max(worst, distance(p, written, cursor));
  cursor = 0;
  for (std::size_t k = 0; k + 1 < written.size(); ++k) {
    const int steps =
        std::max(1, static_cast<int>(std::ceil((written[k + 1] - written[k]).norm() / 0.02)));
    for (int i = 0; i <= steps; ++i) {
      const Vec3 p = written[k] + (static_cast<double>(i) / steps) * (written[k + 1] - written[k]);
      worst = std::max(worst, distance(p, ideal, cursor));
    }
  }
  return worst;
}

TEST(Compensator, NonlinearOffsetIsSplitWithinTheTolerance) {
  // A bent X axis (straightness in Z, 0.2 mm over the travel) and a wavy positioning error.
  model::MachineModelSpec s = emptySpec();
  s.motion[motionIndex(model::Axis::X, model::MotionKind::EZ)] =
      model::PolynomialSpec{{0.0, 0.0, -2e-7}};
  model::TableSpec table;
  for (int i = 0; i <= 20; ++i) {
    table.positionsMm.push_back(-1000 + 100 * i);
    table.values.push_back(0.02 * std::sin(i));
  }
  table.interpolation = model::Interpolation::Cubic;
  s.motion[motionIndex(model::Axis::X, model::MotionKind::EX)] = table;
  CompensateOptions options;
  options.toleranceMm = 0.001;
  const Result r = compensate(s, "G0 X-900 Y0 Z0\nG1 X900 Y100 Z-10 F100\n", options);
  const std::vector<Vec3> p = endPoints(r.text);
  ASSERT_GT(p.size(), 3u) << r.text;
  EXPECT_GT(r.report.piecesAdded, 5);
  EXPECT_LE(r.report.maxBoundMm, 0.001);
  std::vector<Vec3> written(p.begin(), p.end());
  const double dense = denseDeviation(s, Vec3(-900, 0, 0), Vec3(900, 100, -10), written);
  EXPECT_LE(dense, 0.001 + 1e-7);
  EXPECT_GT(dense, 0.0003) << "pieces should be about as long as the tolerance allows";
}

TEST(Compensator, ArcsBecomePolylinesWithinTheTolerance) {
  const Result r = compensate(emptySpec(), "G0 X10 Y0 Z0\nG3 X-10 Y0 I-10 J0 F100\n");
  const std::vector<Vec3> p = endPoints(r.text);
  // Half a circle of radius 10 mm at 1 um: a chord of 2 sqrt(8 r tol) = 0.25 mm at most.
  EXPECT_GT(p.size(), 100u);
  for (std::size_t i = 1; i < p.size(); ++i) {
    const Vec3 mid = 0.5 * (p[i - 1] + p[i]);
    EXPECT_LE(10.0 - std::hypot(mid.x(), mid.y()), 0.001 + 1e-6);
    EXPECT_NEAR(std::hypot(p[i].x(), p[i].y()), 10.0, 1e-5);
  }
  EXPECT_NE(r.text.find("G1 X-10 Y0 Z0"), std::string::npos);
}

TEST(Compensator, ReversalMovesForBidirectionalTables) {
  model::MachineModelSpec s = emptySpec();
  model::TableSpec t;
  t.positionsMm = {-1000, 1000};
  t.values = {0.0, 0.0};
  t.valuesNegative = {0.004, 0.004};  // 4 um reversal error
  s.motion[motionIndex(model::Axis::X, model::MotionKind::EX)] = t;
  const Result r = compensate(s, "G0 X-10 Y0 Z0\nG1 X100 F100\nG1 Y10\nG1 X0\nG1 Y20\nG1 X100\n");
  EXPECT_EQ(r.report.reversalMoves, 3) << r.text;
  EXPECT_NE(r.text.find("(volcomp: reversal)"), std::string::npos);
  const std::vector<Vec3> p = endPoints(r.text);
  // Moving +X the error is 0; moving -X it is +4 um, compensated by -4 um.
  EXPECT_NEAR(p[0].x(), -10.004, 1e-9);
  EXPECT_NEAR(p.back().x(), 100.0, 1e-9);
  bool sawMinus = false;
  for (const Vec3& v : p) sawMinus = sawMinus || std::abs(v.x() - (0.0 - 0.004)) < 1e-9;
  EXPECT_TRUE(sawMinus) << r.text;
}

TEST(Compensator, IncrementsAreDifferencesOfCompensatedPoints) {
  model::MachineModelSpec s = emptySpec();
  s.motion[motionIndex(model::Axis::Y, model::MotionKind::EY)] =
      model::PolynomialSpec{{0.0, 1.23456e-5}};  // 12.3 um per metre
  std::string program = "G90 G0 X0 Y0 Z0\nG91\n";
  for (int i = 0; i < 500; ++i) program += "G1 Y1.001 F100\n";
  const Result r = compensate(s, program);
  const std::vector<Vec3> p = endPoints(r.text);
  const double y = 500 * 1.001;
  EXPECT_NEAR(p.back().y(), y - 1.23456e-5 * y, 0.5e-5) << "no accumulated rounding";
}

TEST(Compensator, StreamingDoesNotChangeTheOutput) {
  model::MachineModelSpec s = emptySpec();
  s.motion[motionIndex(model::Axis::X, model::MotionKind::EZ)] =
      model::PolynomialSpec{{0, 0, -2e-7}};
  std::string program = "G0 X0 Y0 Z0\n";
  for (int i = 0; i < 40; ++i) {
    program += "G1 X" + std::to_string(20 * i) + " Y" + std::to_string(i % 3) + " F500\n";
    program += "G2 X" + std::to_string(20 * i + 10) + " Y" + std::to_string(i % 3) + " R5\n";
  }
  CompensateOptions small;
  small.chunkLines = 1;
  EXPECT_EQ(compensate(s, program, small).text, compensate(s, program).text);
}

TEST(Compensator, StopCodesRunAfterTheWholeMove) {
  model::MachineModelSpec s = emptySpec();
  s.motion[motionIndex(model::Axis::X, model::MotionKind::EZ)] =
      model::PolynomialSpec{{0, 0, -2e-7}};
  const Result r = compensate(s, "G0 X-900 Y0 Z0\nN5 G1 X900 F100 M0 (stop)\nM2\n");
  const std::size_t m0 = r.text.find("\nM0\n");
  ASSERT_NE(m0, std::string::npos) << r.text;
  EXPECT_EQ(r.text.find("G1", m0), std::string::npos) << "M0 after the last piece";
  EXPECT_NE(r.text.find("N5 G1 X"), std::string::npos);
  EXPECT_NE(r.text.find(" F100 (stop)"), std::string::npos);
}

TEST(Compensator, UnknownStartAndOutsideTravel) {
  model::MachineModelSpec s = emptySpec();
  s.travelMm[0] = std::array<double, 2>{0, 100};
  s.motion[motionIndex(model::Axis::X, model::MotionKind::EX)] = 0.01;
  const Result r = compensate(s, "G0 Z5\nG0 X50 Y0\nG1 X150 F100\n", {}, std::nullopt);
  EXPECT_EQ(r.report.uncompensatedMoves, 1);
  ASSERT_EQ(r.report.uncompensatedLines.size(), 1u);
  EXPECT_EQ(r.report.uncompensatedLines[0].line, 1);
  EXPECT_TRUE(r.text.rfind("G0 Z5\n", 0) == 0);
  EXPECT_GT(r.report.outsideTravel, 0);
  ASSERT_FALSE(r.report.outsideTravelLines.empty());
  EXPECT_EQ(r.report.outsideTravelLines[0].line, 3);
  EXPECT_EQ(r.report.outsideTravelLines[0].axes, 1);
}

TEST(Compensator, InchProgramsStayInch) {
  model::MachineModelSpec s = emptySpec();
  s.motion[motionIndex(model::Axis::X, model::MotionKind::EX)] = 0.0254;  // 0.001 in
  const Result r = compensate(s, "G20 G0 X1 Y0 Z0\n");
  EXPECT_NE(r.text.find("G20 G0 X0.999 Y0 Z0"), std::string::npos) << r.text;
}

TEST(Compensator, DecimalsFollowTheTolerance) {
  EXPECT_EQ(decimalsForTolerance(0.001).mm, 5);
  EXPECT_EQ(decimalsForTolerance(0.001).inch, 7);
  EXPECT_EQ(decimalsForTolerance(0.01).mm, 4);
  EXPECT_EQ(decimalsForTolerance(1e-5).mm, 7);
}

}  // namespace
}  // namespace volcomp::nc
