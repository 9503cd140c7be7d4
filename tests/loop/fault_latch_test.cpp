// The fault latch on its own: what is held, what a cycle gets, and which edges acknowledge.
#include "volcomp/loop/fault_latch.hpp"

#include <gtest/gtest.h>

namespace volcomp::loop {
namespace {

constexpr bool kOn = true;
constexpr bool kOff = false;

TEST(FaultLatch, HoldsALatchableFaultAfterItsCauseIsGone) {
  FaultLatch latch;
  latch.seed(kOn, kOff);
  EXPECT_EQ(latch.apply(FaultCode::OutOfTravel, true), FaultCode::OutOfTravel);
  EXPECT_TRUE(latch.holding());
  for (int i = 0; i < 3; ++i) {
    EXPECT_FALSE(latch.acknowledge(kOn, kOff));
    EXPECT_EQ(latch.apply(FaultCode::None, true), FaultCode::OutOfTravel);
  }
  EXPECT_EQ(latch.held(), FaultCode::OutOfTravel);
}

TEST(FaultLatch, ANewerFaultReplacesTheHeldOne) {
  FaultLatch latch;
  latch.apply(FaultCode::StaleInput, true);
  EXPECT_EQ(latch.apply(FaultCode::ModelInvalid, true), FaultCode::ModelInvalid);
  EXPECT_EQ(latch.apply(FaultCode::None, true), FaultCode::ModelInvalid);
}

TEST(FaultLatch, AFailedTransactionIsNeverHeld) {
  FaultLatch latch;
  EXPECT_EQ(latch.apply(FaultCode::TransactionError, true), FaultCode::TransactionError);
  EXPECT_FALSE(latch.holding());
  EXPECT_EQ(latch.apply(FaultCode::None, true), FaultCode::None);
  // Nor does it replace a held fault: that one comes back once the transactions succeed.
  latch.apply(FaultCode::SustainedLimit, true);
  EXPECT_EQ(latch.apply(FaultCode::TransactionError, true), FaultCode::TransactionError);
  EXPECT_EQ(latch.apply(FaultCode::None, true), FaultCode::SustainedLimit);
}

TEST(FaultLatch, LatchingOffHoldsNothing) {
  FaultLatch latch;
  EXPECT_EQ(latch.apply(FaultCode::OutOfTravel, false), FaultCode::OutOfTravel);
  EXPECT_FALSE(latch.holding());
  EXPECT_EQ(latch.apply(FaultCode::None, false), FaultCode::None);
}

TEST(FaultLatch, ARisingAckAcknowledges) {
  FaultLatch latch;
  latch.seed(kOn, kOff);
  latch.apply(FaultCode::OutOfTravel, true);
  EXPECT_TRUE(latch.acknowledge(kOn, kOn));
  EXPECT_FALSE(latch.holding());
  EXPECT_EQ(latch.apply(FaultCode::None, true), FaultCode::None);
}

// A button stuck high is one edge, not an acknowledge of every later fault.
TEST(FaultLatch, AnAckHeldHighAcknowledgesOnce) {
  FaultLatch latch;
  latch.seed(kOn, kOn);  // high already when the loop began reading
  latch.apply(FaultCode::OutOfTravel, true);
  EXPECT_FALSE(latch.acknowledge(kOn, kOn));
  EXPECT_TRUE(latch.holding());
  EXPECT_FALSE(latch.acknowledge(kOn, kOff));  // released: a falling edge is nothing
  EXPECT_TRUE(latch.acknowledge(kOn, kOn));
  latch.apply(FaultCode::OutOfTravel, true);
  EXPECT_FALSE(latch.acknowledge(kOn, kOn));
  EXPECT_TRUE(latch.holding());
}

TEST(FaultLatch, EnableSwitchedOffAcknowledges) {
  FaultLatch latch;
  latch.seed(kOn, kOff);
  latch.apply(FaultCode::StaleInput, true);
  EXPECT_TRUE(latch.acknowledge(kOff, kOff));
  EXPECT_FALSE(latch.holding());
  // Enable coming back on is no edge that acknowledges.
  latch.apply(FaultCode::StaleInput, true);
  EXPECT_FALSE(latch.acknowledge(kOn, kOff));
  EXPECT_TRUE(latch.holding());
}

// Edges are taken from the reference seed() sets: a toggle before it acknowledges nothing.
TEST(FaultLatch, SeedSetsTheReferenceWithoutActing) {
  FaultLatch latch;
  latch.seed(kOn, kOff);
  latch.apply(FaultCode::OutOfTravel, true);
  latch.seed(kOff, kOn);
  EXPECT_TRUE(latch.holding());
  EXPECT_FALSE(latch.acknowledge(kOff, kOn));
  EXPECT_TRUE(latch.holding());
}

TEST(FaultLatch, AnAcknowledgeWithNothingHeldReportsNothing) {
  FaultLatch latch;
  latch.seed(kOn, kOff);
  EXPECT_FALSE(latch.acknowledge(kOff, kOn));
}

// Acknowledged with the cause still present: held again in the same cycle.
TEST(FaultLatch, ACausePresentAtTheAcknowledgeLatchesAgain) {
  FaultLatch latch;
  latch.seed(kOn, kOff);
  latch.apply(FaultCode::OutOfTravel, true);
  EXPECT_TRUE(latch.acknowledge(kOn, kOn));
  EXPECT_EQ(latch.apply(FaultCode::OutOfTravel, true), FaultCode::OutOfTravel);
  EXPECT_EQ(latch.held(), FaultCode::OutOfTravel);
}

TEST(FaultLatch, ReleaseForgetsTheHeldFault) {
  FaultLatch latch;
  latch.apply(FaultCode::ReadbackOutOfRange, true);
  latch.release();
  EXPECT_FALSE(latch.holding());
  EXPECT_EQ(latch.apply(FaultCode::None, true), FaultCode::None);
}

}  // namespace
}  // namespace volcomp::loop
