// Modbus/TCP framing as the server role collects a connection's bytes: where an ADU ends, when
// a stream is out of step, and the exception reply (function byte never wrapped).
#include "volcomp/modbus/tcp_adu.hpp"

#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

namespace volcomp::modbus {
namespace {

using Kind = TcpAduStatus::Kind;

// FC03, 8 registers from 14: transaction 0x1234, unit 1.
const std::vector<std::uint8_t> kRead = {0x12, 0x34, 0, 0, 0, 6, 1, 0x03, 0, 14, 0, 8};

TEST(TcpAdu, CompleteOnlyWhenTheLengthFieldIsSatisfied) {
  for (std::size_t n = 0; n < kRead.size(); ++n) {
    EXPECT_EQ(tcpAdu({kRead.data(), n}).kind, Kind::Incomplete) << n;
  }
  const TcpAduStatus whole = tcpAdu(kRead);
  EXPECT_EQ(whole.kind, Kind::Complete);
  EXPECT_EQ(whole.bytes, kRead.size());
  // The next request already behind it: the first ends where its header says.
  std::vector<std::uint8_t> two = kRead;
  two.insert(two.end(), kRead.begin(), kRead.begin() + 5);
  EXPECT_EQ(tcpAdu(two).bytes, kRead.size());
}

TEST(TcpAdu, AHeaderThatIsNoModbusTcpHeaderIsOutOfStep) {
  std::vector<std::uint8_t> adu = kRead;
  adu[3] = 1;  // protocol id 1
  EXPECT_EQ(tcpAdu({adu.data(), 6}).kind, Kind::OutOfStep);
  adu = kRead;
  adu[5] = 1;  // a unit id and no function code
  EXPECT_EQ(tcpAdu(adu).kind, Kind::OutOfStep);
  adu[4] = 1;  // 256 + 1: more than the largest PDU
  EXPECT_EQ(tcpAdu(adu).kind, Kind::OutOfStep);
  // The largest ADU: unit id and a PDU of 253 bytes.
  std::vector<std::uint8_t> largest(kMaxTcpAduBytes, 0);
  largest[5] = 254;
  EXPECT_EQ(tcpAdu({largest.data(), largest.size() - 1}).kind, Kind::Incomplete);
  EXPECT_EQ(tcpAdu(largest).bytes, kMaxTcpAduBytes);
}

TEST(TcpAdu, ExceptionReplyEchoesTransactionAndUnitAndNeverWrapsTheFunction) {
  std::vector<std::uint8_t> adu = kRead;
  adu[6] = 17;
  const auto reply = tcpExceptionReply(adu, 2);
  const std::array<std::uint8_t, 9> expected = {0x12, 0x34, 0, 0, 0, 3, 17, 0x83, 2};
  EXPECT_EQ(reply, expected);
  adu[7] = 0x83;  // a request with an exception's function code: answered as 0x83, not 0x03
  EXPECT_EQ(tcpExceptionReply(adu, 1)[7], 0x83);
  adu[7] = 0x2B;
  EXPECT_EQ(tcpExceptionReply(adu, 1)[7], 0xAB);
}

}  // namespace
}  // namespace volcomp::modbus
