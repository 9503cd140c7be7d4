// Latency compensation: the velocity estimator on its own (constant velocity, timing jitter, a
// reversal, a stop, stale samples) and the loop using it (where the model is evaluated, with a
// fake clock and a moving fake controller).
#include "volcomp/loop/latency_compensation.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include "loop_fixture.hpp"

namespace volcomp::loop::testing {
namespace {

using namespace std::chrono_literals;
using model::Direction;
using time_point = VelocityEstimator::time_point;

constexpr auto kGap = 50ms;
const time_point kT0 = time_point(std::chrono::hours(10));

time_point at(double seconds) {
  return kT0 + std::chrono::duration_cast<std::chrono::nanoseconds>(
                   std::chrono::duration<double>(seconds));
}

// --- the estimator ---------------------------------------------------------------------------

TEST(VelocityEstimator, ConstantVelocityIsExactOnEveryAxis) {
  VelocityEstimator e;
  for (int i = 0; i < 6; ++i) {
    const double t = 0.01 * i;
    e.add(at(t), {100.0 + 400.0 * t, 50.0 - 100.0 * t, -20.0}, kGap);
  }
  EXPECT_EQ(e.size(), kHistorySamples);
  EXPECT_TRUE(e.velocity(0).sure);
  EXPECT_NEAR(e.velocity(0).mmS, 400.0, 1e-6);
  EXPECT_TRUE(e.velocity(1).sure);
  EXPECT_NEAR(e.velocity(1).mmS, -100.0, 1e-6);
  EXPECT_FALSE(e.velocity(2).sure) << "an axis at rest has nothing to extrapolate";
}

TEST(VelocityEstimator, UnsureUntilThreeSamples) {
  VelocityEstimator e;
  e.add(at(0.0), {0.0, 0.0, 0.0}, kGap);
  e.add(at(0.01), {4.0, 0.0, 0.0}, kGap);
  EXPECT_FALSE(e.velocity(0).sure);
  e.add(at(0.02), {8.0, 0.0, 0.0}, kGap);
  EXPECT_TRUE(e.velocity(0).sure);
}

TEST(VelocityEstimator, MeasuredTimesAbsorbReadJitter) {
  // Reads 10 ms apart +- 3 ms, positions sampled at the measured times: the estimate is the true
  // 400 mm/s (one assuming the nominal period would be off by up to 50 %).
  VelocityEstimator e;
  const double jitter[] = {0.0, 0.003, -0.002, 0.0025, -0.003, 0.001, 0.002, -0.0015};
  for (int i = 0; i < 8; ++i) {
    const double t = 0.01 * i + jitter[i];
    e.add(at(t), {400.0 * t, 0.0, 0.0}, kGap);
    if (i >= 2) {
      ASSERT_TRUE(e.velocity(0).sure) << i;
      EXPECT_NEAR(e.velocity(0).mmS, 400.0, 1e-6) << i;
    }
  }
}

TEST(VelocityEstimator, TimestampNoiseMovesTheEstimateLittle) {
  // The controller samples up to 0.5 ms away from the measured time (its answer inside the read).
  VelocityEstimator e;
  const double offset[] = {0.0004, -0.0005, 0.0003, -0.0002, 0.0005, -0.0004, 0.0001, -0.0003};
  for (int i = 0; i < 8; ++i) {
    const double t = 0.01 * i;
    e.add(at(t), {400.0 * (t + offset[i]), 0.0, 0.0}, kGap);
    if (i >= 2) {
      ASSERT_TRUE(e.velocity(0).sure) << i;
      EXPECT_NEAR(e.velocity(0).mmS, 400.0, 0.12 * 400.0) << i;
    }
  }
}

TEST(VelocityEstimator, ReversalInTheWindowIsUnsureUntilTheWindowIsMonotonicAgain) {
  VelocityEstimator e;
  const double q[] = {0.0, 4.0, 8.0, 10.0, 6.0, 2.0, -2.0, -6.0};  // turns at 10 mm
  for (int i = 0; i < 8; ++i) {
    e.add(at(0.01 * i), {q[i], 0.0, 0.0}, kGap);
    const AxisVelocity v = e.velocity(0);
    if (i >= 2 && i <= 3) {
      EXPECT_TRUE(v.sure) << i;
      EXPECT_GT(v.mmS, 0.0) << i;
    } else if (i >= 4 && i <= 5) {
      EXPECT_FALSE(v.sure) << "the window still holds the turn at sample " << i;
    } else if (i >= 6) {
      EXPECT_TRUE(v.sure) << "the turn is the oldest sample: every step is negative";
    }
  }
  ASSERT_TRUE(e.velocity(0).sure);
  EXPECT_NEAR(e.velocity(0).mmS, -400.0, 1e-6);
}

TEST(VelocityEstimator, DecelerationTakesTheSmallerSlopeAndAStopIsUnsure) {
  VelocityEstimator e;
  const double q[] = {0.0, 4.0, 8.0, 10.0};  // 400, 400, then 200 mm/s
  for (int i = 0; i < 4; ++i) e.add(at(0.01 * i), {q[i], 0.0, 0.0}, kGap);
  ASSERT_TRUE(e.velocity(0).sure);
  EXPECT_NEAR(e.velocity(0).mmS, 200.0, 1e-6) << "the newest pair, smaller than the fit";
  e.add(at(0.04), {10.0, 0.0, 0.0}, kGap);  // stopped
  EXPECT_FALSE(e.velocity(0).sure);
}

TEST(VelocityEstimator, StaleSamplesStartANewWindowAndARepeatedTimeReplaces) {
  VelocityEstimator e;
  for (int i = 0; i < 4; ++i) e.add(at(0.01 * i), {4.0 * i, 0.0, 0.0}, kGap);
  ASSERT_TRUE(e.velocity(0).sure);
  e.add(at(0.03 + 0.2), {12.5, 0.0, 0.0}, kGap);  // 200 ms later: a pause, a link loss
  EXPECT_EQ(e.size(), 1U);
  EXPECT_FALSE(e.velocity(0).sure);
  e.add(at(0.23), {12.6, 0.0, 0.0}, kGap);  // the same instant read again
  EXPECT_EQ(e.size(), 1U);
  e.reset();
  EXPECT_EQ(e.size(), 0U);
}

TEST(PredictPositions, ExtrapolatesSureAxesWithinTheCapAndTakesTheirDirection) {
  VelocityEstimator e;
  for (int i = 0; i < 4; ++i) e.add(at(0.01 * i), {-400.0 * 0.01 * i, 7.0, 0.0}, kGap);
  std::array<double, 3> q{-12.0, 7.0, 0.0};
  model::Directions d{Direction::Positive, Direction::Unknown, Direction::Negative};
  EXPECT_EQ(predictPositions(e, q, d, 5ms, 20ms, 0.002), 1);
  EXPECT_NEAR(q[0], -12.0 - 400.0 * 0.005, 1e-9);
  EXPECT_EQ(q[1], 7.0);
  EXPECT_EQ(d[0], Direction::Negative) << "the estimate's direction";
  EXPECT_EQ(d[1], Direction::Unknown) << "unsure axes keep the tracker's";
  EXPECT_EQ(d[2], Direction::Negative);
  q = {-12.0, 7.0, 0.0};
  predictPositions(e, q, d, 500ms, 20ms, 0.002);
  EXPECT_NEAR(q[0], -12.0 - 400.0 * 0.020, 1e-9) << "the horizon is capped";
}

TEST(PredictPositions, NoiseAtRestBelowTheHysteresisIsNeitherExtrapolatedNorADirection) {
  // Four reads creeping up by 0.5 um each (encoder noise on actual positions): monotonic, so the
  // estimate is sure, but 1.5 um over the window is within the tracker's 2 um hysteresis.
  VelocityEstimator e;
  for (int i = 0; i < 4; ++i) e.add(at(0.01 * i), {10.0 + 0.0005 * i, 0.0, 0.0}, kGap);
  ASSERT_TRUE(e.velocity(0).sure);
  std::array<double, 3> q{10.0015, 0.0, 0.0};
  model::Directions d{Direction::Unknown, Direction::Unknown, Direction::Unknown};
  EXPECT_EQ(predictPositions(e, q, d, 5ms, 20ms, 0.002), 0);
  EXPECT_EQ(q[0], 10.0015);
  EXPECT_EQ(d[0], Direction::Unknown);
  EXPECT_EQ(predictPositions(e, q, d, 5ms, 20ms, 0.001), 1) << "beyond a smaller hysteresis";
}

// --- smooth turns ----------------------------------------------------------------------------

// X braking at 5 m/s^2 from 400 mm/s: q = 100 + 400 t - 2500 t^2, at rest at t = 0.08 s (116 mm),
// then back the same way (a reversal through zero velocity, as a CNC brakes it).
double braking(double t) {
  return 100.0 + 400.0 * t - 2500.0 * t * t;
}

TEST(Parabola, ABrakingAxisIsFittedExactly) {
  VelocityEstimator e;
  for (int i = 0; i <= 5; ++i) e.add(at(0.01 * i), {braking(0.01 * i), 0.0, 0.0}, kGap);
  const AxisParabola p = e.parabola(0, 0.002);
  ASSERT_TRUE(p.smooth);
  EXPECT_NEAR(p.c0, braking(0.05), 1e-9);
  EXPECT_NEAR(p.c1, 400.0 - 5000.0 * 0.05, 1e-6) << "velocity at the newest sample";
  EXPECT_NEAR(p.c2, -2500.0, 1e-4);
  EXPECT_NEAR(p.oldestS, -0.05, 1e-12);
  const AxisParabola older = e.parabola(0, 0.002, 5);  // without the newest read
  ASSERT_TRUE(older.smooth);
  EXPECT_NEAR(older.c1, p.c1, 1e-6) << "times stay relative to the newest read";
  EXPECT_NEAR(older.oldestS, -0.05, 1e-12);
  EXPECT_EQ(e.parabola(1, 0.002).rangeMm, 0.0) << "an axis at rest: no range, nothing to predict";
}

TEST(Parabola, AnUnbrakedReversalIsNotSmooth) {
  // 400 mm/s straight into a turn at 10 mm and straight back: a velocity jump, no parabola.
  VelocityEstimator e;
  const double q[] = {-6.0, -2.0, 2.0, 6.0, 10.0, 6.0};
  for (int i = 0; i < 6; ++i) e.add(at(0.01 * i), {q[i], 0.0, 0.0}, kGap);
  EXPECT_FALSE(e.parabola(0, 0.002).smooth);
}

HoldPrediction holdAt(double newestS, std::chrono::nanoseconds horizon,
                      Direction tracked = Direction::Positive) {
  VelocityEstimator e;
  for (int i = 5; i >= 0; --i) {
    const double t = newestS - 0.01 * i;
    e.add(at(t), {braking(t), 50.0, -20.0}, kGap);
  }
  return predictHold(e, {braking(newestS), 50.0, -20.0},
                     {tracked, Direction::Unknown, Direction::Unknown}, horizon, 10ms, 30ms, 0.002);
}

TEST(PredictHold, ATurnInsideTheHoldIsListedWithTheFractionBeforeIt) {
  // Newest sample at 0.07 s, hold from 0.072 to 0.082 s (horizon 7 ms to its middle): the turn at
  // 0.08 s leaves 80 % of the hold on the way out.
  const HoldPrediction h = holdAt(0.07, 7ms);
  ASSERT_EQ(h.turns, 1U);
  EXPECT_EQ(h.turnAxis[0], 0U);
  EXPECT_NEAR(h.turnFraction[0], 0.8, 1e-6);
  EXPECT_EQ(h.directions[0], Direction::Positive) << "directions at the hold's start";
  EXPECT_NEAR(h.qMm[0], braking(0.077), 1e-6) << "on the parabola at the hold's middle";
  EXPECT_EQ(h.qMm[1], 50.0);
}

TEST(PredictHold, ATurnBeforeTheHoldStartsTakesTheNewDirection) {
  const HoldPrediction h = holdAt(0.07, 17ms);  // hold 0.082 .. 0.092 s
  EXPECT_EQ(h.turns, 0U);
  EXPECT_EQ(h.directions[0], Direction::Negative);
  EXPECT_NEAR(h.qMm[0], braking(0.087), 1e-6);
}

TEST(PredictHold, ATurnAfterTheHoldChangesNothingButThePosition) {
  const HoldPrediction h = holdAt(0.05, 7ms);  // hold 0.052 .. 0.062 s, turn at 0.08 s
  EXPECT_EQ(h.turns, 0U);
  EXPECT_EQ(h.directions[0], Direction::Positive);
}

TEST(PredictHold, JustAfterTheTurnTheNewDirectionHoldsBeforeTheTrackerSeesIt) {
  // Newest sample 1 ms after the turn: 2.5 nm back (2500 x 0.001^2), far inside the tracker's
  // 2 um hysteresis, and the newest step still went up. The tracker says positive; the parabola
  // says negative.
  const HoldPrediction h = holdAt(0.081, 7ms, Direction::Positive);
  EXPECT_EQ(h.turns, 0U);
  EXPECT_EQ(h.directions[0], Direction::Negative);
}

// Braked to a stop at 116 mm at 0.08 s and on in the same direction at once (exact stop mode).
double stopAndOn(double t) {
  const double u = t - 0.08;
  return u < 0.0 ? 116.0 - 2500.0 * u * u : 116.0 + 2500.0 * u * u;
}

TEST(PredictHold, AnAsymmetricTurnIsATurn) {
  // Braked at 3125 mm/s^2 into the turn at t = 0 (x = 340) and back at 781 mm/s^2 (a corner of a
  // zig-zag: the next move is longer and X only a small part of it). The newest read 0.9 ms
  // after the turn.
  const auto x = [](double t) {
    return t < 0.0 ? 340.0 - 0.5 * 3125.0 * t * t : 340.0 - 0.5 * 781.0 * t * t;
  };
  for (const double newest : {0.0003, 0.0009, 0.003, 0.006, 0.0095}) {
    VelocityEstimator e;
    for (int i = 5; i >= 0; --i) e.add(at(newest - 0.01 * i), {x(newest - 0.01 * i), 0, 0}, kGap);
    const HoldPrediction h = predictHold(
        e, {x(newest), 0.0, 0.0}, {Direction::Positive, Direction::Unknown, Direction::Unknown},
        7ms, 10ms, 30ms, 0.002);
    EXPECT_EQ(h.directions[0], Direction::Negative) << newest;
  }
}

TEST(PredictHold, AStopAndOnIsNoTurnOnceAReadShowsIt) {
  // Before the stop the reads are those of a braked reversal: the hold with the stop in it is
  // taken as turning (nothing can tell them apart yet). After it, whichever read comes first,
  // the direction stays and no turn is predicted.
  for (const double newest : {0.081, 0.085, 0.089, 0.091, 0.095, 0.099, 0.105}) {
    VelocityEstimator e;
    for (int i = 5; i >= 0; --i)
      e.add(at(newest - 0.01 * i), {stopAndOn(newest - 0.01 * i), 0, 0}, kGap);
    const HoldPrediction h = predictHold(
        e, {stopAndOn(newest), 0.0, 0.0},
        {Direction::Positive, Direction::Unknown, Direction::Unknown}, 7ms, 10ms, 30ms, 0.002);
    EXPECT_EQ(h.turns, 0U) << newest;
    EXPECT_EQ(h.directions[0], Direction::Positive) << newest;
  }
}

TEST(PredictHold, AStopIsNotTakenForATurnOnceTheAxisRests) {
  // Braked to rest at 116 mm and resting there: the newest step is zero, no new direction.
  VelocityEstimator e;
  const double times[] = {0.05, 0.06, 0.07, 0.08, 0.09, 0.10};
  for (double t : times) e.add(at(t), {braking(std::min(t, 0.08)), 0.0, 0.0}, kGap);
  const HoldPrediction h = predictHold(
      e, {116.0, 0.0, 0.0}, {Direction::Positive, Direction::Unknown, Direction::Unknown}, 7ms,
      10ms, 30ms, 0.002);
  EXPECT_EQ(h.turns, 0U);
  EXPECT_EQ(h.directions[0], Direction::Positive);
}

// --- in the loop -----------------------------------------------------------------------------

class LatencyLoopTest : public LoopTest {
 protected:
  void SetUp() override {
    settings.latencyCompensation = true;
    settings.controllerLatency = 2ms;
    port.autoSequence = true;
    port.sample.positionMm = {100.0, 50.0, -20.0};
  }
  /// One cycle with X moving at vx mm/s (the controller samples at the cycle's clock).
  CycleReport move(double vxMmS) {
    clock.advance(settings.period);
    port.sample.positionMm[0] += vxMmS * std::chrono::duration<double>(settings.period).count();
    return loop->step();
  }
};

TEST_F(LatencyLoopTest, EvaluatesTheModelWhereTheAxisWillBeWhenTheOffsetActs) {
  make();
  for (int i = 0; i < 10; ++i) move(400.0);
  // Reads and writes take no time on the fake clock: h = controller latency 2 ms + half the
  // 10 ms period over which the offset holds.
  EXPECT_NEAR(model->lastQ[0], port.sample.positionMm[0] + 400.0 * 0.007, 1e-6);
  EXPECT_EQ(model->lastQ[1], 50.0);
  EXPECT_EQ(model->lastDirections[0], Direction::Positive);
  EXPECT_GT(loop->counters().extrapolatedCycles, 0U);
  EXPECT_EQ(loop->state(), LoopState::Active);
}

TEST_F(LatencyLoopTest, TheMeasuredTransactionTimesLengthenTheHorizon) {
  make();
  // Each read takes 2 ms (the controller answers after 1 ms, mid-read).
  port.afterRead = [this] { clock.advance(2ms); };
  for (int i = 0; i < 10; ++i) move(100.0);
  // Cycles are now 12 ms apart: 1 mm per 12 ms. h = 1 ms (the rest of the read) + 0 (the
  // write) + 2 ms + 5 ms.
  EXPECT_NEAR(model->lastQ[0], port.sample.positionMm[0] + 1.0 / 0.012 * 0.008, 1e-6);
}

// The controller latches the positions every 4 ms (a PLC scan) and serves them until the next:
// read every 10 ms, they are 0 or 2 ms old. Its timestamp (10 us ticks) gives them their age;
// without it the loop takes them as sampled mid-read and evaluates up to 2 ms short.
TEST_F(LatencyLoopTest, AControllerTimestampGivesTheLatchedPositionsTheirAge) {
  const double x0 = port.sample.positionMm[0];
  auto worstErrorMm = [&](bool stamped) {
    make();
    port.sample.positionMm[0] = x0;
    port.sample.hasTimestamp = stamped;
    port.sample.timestampTickS = 10e-6;
    const auto start = clock.now();
    double worst = 0.0;
    for (int i = 1; i <= 40; ++i) {
      clock.advance(settings.period);
      const double tS = std::chrono::duration<double>(clock.now() - start).count();
      const double latchS = std::floor(tS / 0.004 + 1e-9) * 0.004;
      port.sample.positionMm[0] = x0 + 400.0 * latchS;
      port.sample.timestampTicks =
          static_cast<std::uint16_t>(std::llround((latchS + 3.0) / 10e-6) & 0xFFFF);
      loop->step();
      // Where the axis is when the offset acts: 2 ms controller latency + half the period on.
      if (i > 10) worst = std::max(worst, std::abs(model->lastQ[0] - (x0 + 400.0 * (tS + 0.007))));
    }
    EXPECT_EQ(loop->state(), LoopState::Active);
    return worst;
  };
  EXPECT_LT(worstErrorMm(true), 1e-6);
  // Without: at least the 2 ms age (more: the ages' jitter reaches the velocity estimate too).
  EXPECT_GT(worstErrorMm(false), 400.0 * 0.002 - 1e-6);
}

TEST_F(LatencyLoopTest, OffEvaluatesAtThePositionsRead) {
  settings.latencyCompensation = false;
  make();
  for (int i = 0; i < 10; ++i) move(400.0);
  EXPECT_EQ(model->lastQ[0], port.sample.positionMm[0]);
  EXPECT_EQ(loop->counters().extrapolatedCycles, 0U);
}

TEST_F(LatencyLoopTest, AReversalFallsBackToThePositionRead) {
  make();
  for (int i = 0; i < 10; ++i) move(400.0);
  move(-400.0);
  EXPECT_EQ(model->lastQ[0], port.sample.positionMm[0]);
  EXPECT_EQ(model->lastDirections[0], Direction::Negative) << "the tracker saw the turn";
  move(-400.0);
  EXPECT_EQ(model->lastQ[0], port.sample.positionMm[0]) << "the turn is still in the window";
  move(-400.0);
  EXPECT_NEAR(model->lastQ[0], port.sample.positionMm[0] - 400.0 * 0.007, 1e-6);
}

TEST_F(LatencyLoopTest, AStopNeverTurnsTheDirection) {
  make();
  for (int i = 0; i < 10; ++i) move(400.0);
  for (int i = 0; i < 5; ++i) {
    move(0.0);
    EXPECT_EQ(model->lastQ[0], port.sample.positionMm[0]) << i;
    EXPECT_EQ(model->lastDirections[0], Direction::Positive) << i;
  }
}

TEST_F(LatencyLoopTest, FrozenRegistersAddNoSampleAndAPauseForgetsTheHistory) {
  make();
  for (int i = 0; i < 10; ++i) move(400.0);
  // The life counter stops: the same positions again are not a stop of the axis.
  port.autoSequence = false;
  port.sample.hasSequence = true;
  port.sample.sequence = port.sequence;
  clock.advance(settings.period);
  loop->step();
  EXPECT_NEAR(model->lastQ[0], port.sample.positionMm[0] + 400.0 * 0.007, 1e-6);
  port.autoSequence = true;
  // Disabled for a while: the estimate starts again from the positions read after it.
  port.sample.enable = false;
  for (int i = 0; i < 5; ++i) move(400.0);
  port.sample.enable = true;
  move(400.0);
  EXPECT_EQ(model->lastQ[0], port.sample.positionMm[0]);
}

TEST_F(LatencyLoopTest, ATurnInTheHoldWritesTheMeanOfBothDirections) {
  // X brakes through a turn at 0.08 s (see braking()); reads 10 ms apart, h = 2 + 5 ms. The model
  // gives X 0.004 mm more offset while X moves negative (a 4 um reversal step).
  model->negativeXShiftMm = 0.004;
  make();
  std::array<double, 8> writtenX{};
  for (int i = 0; i < 8; ++i) {
    if (i > 0) clock.advance(settings.period);
    port.sample.positionMm[0] = braking(0.01 * i);
    loop->step();
    writtenX[static_cast<std::size_t>(i)] = port.last.offsetMm[0];
  }
  // The cycle reading t = 0.07 s writes for the hold 0.072 .. 0.082 s: 80 % positive, 20 %
  // negative. The base offset is 0.01 mm (the fake model's), reached by the limiter long before.
  EXPECT_NEAR(writtenX[7], 0.01 + 0.2 * 0.004, 1e-9);
  EXPECT_EQ(loop->counters().turnCycles, 1U);
  clock.advance(settings.period + 500us);  // the next read comes a hair past the turn
  port.sample.positionMm[0] = braking(0.08 + 0.0005);
  loop->step();
  EXPECT_NEAR(port.last.offsetMm[0], 0.014, 1e-9) << "the whole next hold is on the way back";
}

TEST_F(LatencyLoopTest, EveryHoldAfterATurnIsOnTheWayBackWhereverTheTurnFallsInTheCycle) {
  // The asymmetric turn of a zig-zag corner (braked at 3125 mm/s^2 into x = 340, back at
  // 781 mm/s^2), read every 10 ms at every phase of the cycle in 0.5 ms steps: the first write
  // whose hold starts after the turn has the negative direction's offset.
  model->negativeXShiftMm = 0.004;
  const auto x = [](double t) {
    return t < 0.0 ? 340.0 - 0.5 * 3125.0 * t * t : 340.0 - 0.5 * 781.0 * t * t;
  };
  // Y turns with X (braked at 3906, back at 4883 mm/s^2), Z starts from rest at the corner.
  const auto y = [](double t) {
    return t < 0.0 ? 350.0 - 0.5 * 3906.0 * t * t : 350.0 - 0.5 * 4883.0 * t * t;
  };
  const auto z = [](double t) { return t < 0.0 ? -160.0 : -160.0 - 0.5 * 781.0 * t * t; };
  for (int phase = 0; phase < 20; ++phase) {
    SCOPED_TRACE(phase);
    port.sample.positionMm = {x(-0.2), y(-0.2), z(-0.2)};
    make();
    const double t0 = -0.2 + 0.0005 * phase;
    bool checked = false;
    for (int i = 0; i < 40 && !checked; ++i) {
      if (i > 0) clock.advance(settings.period);
      const double t = t0 + 0.01 * i;
      port.sample.positionMm = {x(t), y(t), z(t)};
      loop->step();
      // Holds from t + 2 ms (controller latency) to t + 12 ms.
      if (t + 0.002 >= 0.0 && i > 10) {
        EXPECT_NEAR(port.last.offsetMm[0], 0.014, 1e-9) << "read at t = " << t;
        checked = true;
      }
    }
  }
}

TEST_F(LatencyLoopTest, ExtrapolationStaysInsideTheTravel) {
  port.sample.positionMm[0] = 496.0;  // travel X [0, 500]
  make();
  for (int i = 0; i < 2; ++i) move(100.0);
  EXPECT_NEAR(model->lastQ[0], 498.0, 1e-9) << "unsure: as read";
  move(100.0);
  move(100.0);
  EXPECT_EQ(model->lastQ[0], 500.0);
  EXPECT_EQ(port.last.status & status::kOutOfTravel, 0);
}

}  // namespace
}  // namespace volcomp::loop::testing
