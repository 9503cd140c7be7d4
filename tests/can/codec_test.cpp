#include "volcomp/can/signal.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "volcomp/can/errors.hpp"
#include "volcomp/can/frame.hpp"

namespace volcomp::can {
namespace {

SignalSpec spec(unsigned start, unsigned length, ByteOrder order,
                ValueType type = ValueType::Unsigned, double scale = 1.0, double offset = 0.0) {
  SignalSpec s;
  s.name = "s";
  s.startBit = start;
  s.length = length;
  s.byteOrder = order;
  s.valueType = type;
  s.scale = scale;
  s.offset = offset;
  return s;
}

// Reference model written straight from the DBC definition, bit by bit: payload bit b is bit
// b % 8 of byte b / 8. Intel: raw bit i sits at payload bit start + i. Motorola: the raw MSB
// sits at payload bit `start`; each following bit is the next lower bit of the byte, and after
// bit 0 of a byte comes bit 7 of the next byte (b -> b + 15).
std::vector<unsigned> referenceBits(const SignalSpec& s) {
  std::vector<unsigned> bits(s.length);  // bits[i] = payload bit of raw bit i
  if (s.byteOrder == ByteOrder::Intel) {
    for (unsigned i = 0; i < s.length; ++i) bits[i] = s.startBit + i;
  } else {
    unsigned b = s.startBit;
    for (unsigned k = 0; k < s.length; ++k) {
      bits[s.length - 1 - k] = b;
      b = (b % 8 == 0) ? b + 15 : b - 1;
    }
  }
  return bits;
}

std::uint64_t referenceDecode(const SignalSpec& s, const std::vector<std::uint8_t>& payload) {
  std::uint64_t raw = 0;
  const auto bits = referenceBits(s);
  for (unsigned i = 0; i < s.length; ++i)
    if ((payload[bits[i] / 8] >> (bits[i] % 8)) & 1u) raw |= std::uint64_t{1} << i;
  return raw;
}

TEST(FrameLengths, ClassicAndFdDlcLengths) {
  EXPECT_TRUE(isValidLength(8, false));
  EXPECT_FALSE(isValidLength(9, false));
  EXPECT_FALSE(isValidLength(12, false));
  for (std::size_t n : {0u, 1u, 8u, 12u, 16u, 20u, 24u, 32u, 48u, 64u})
    EXPECT_TRUE(isValidLength(n, true)) << n;
  for (std::size_t n : {9u, 10u, 13u, 33u, 63u, 65u}) EXPECT_FALSE(isValidLength(n, true)) << n;
  EXPECT_EQ(validLengthAtLeast(9, true), 12u);
  EXPECT_EQ(validLengthAtLeast(25, true), 32u);
  EXPECT_EQ(validLengthAtLeast(49, true), 64u);
  EXPECT_EQ(validLengthAtLeast(65, true), 0u);
  EXPECT_EQ(validLengthAtLeast(9, false), 0u);
  EXPECT_EQ(validLengthAtLeast(5, false), 5u);
  EXPECT_TRUE(isValidId(0x7FF, false));
  EXPECT_FALSE(isValidId(0x800, false));
  EXPECT_TRUE(isValidId(0x1FFFFFFF, true));
  EXPECT_FALSE(isValidId(0x20000000, true));
}

struct Vector {
  SignalSpec spec;
  std::uint64_t raw;
  std::array<std::uint8_t, 8> bytes;
};

// Known vectors, derived by hand from the DBC convention:
// - Intel 0|16, 0x1234: LSB first -> 34 12.
// - Intel 4|12, 0xABC: bits 4..15; low nibble C in byte 0 bits 4..7 -> C0, then AB in byte 1.
// - Motorola 7|16, 0x1234: MSB at byte 0 bit 7, big-endian -> 12 34.
// - Motorola 3|12, 0xABC: MSB at byte 0 bit 3; byte 0 bits 3..0 = A, byte 1 = BC -> 0A BC.
// - Motorola 12|8, 0xB5 = 1011'0101: MSB at byte 1 bit 4; byte 1 bits 4..0 = 10110 (0x16), then
//   byte 2 bits 7..5 = 101 -> byte 1 = 16, byte 2 = A0.
// - Intel 62|2, 0x3: payload bits 62 and 63 are bits 6 and 7 of byte 7 -> C0 in byte 7.
// - Motorola 7|64, 0x0102030405060708: plain big-endian 01 02 .. 08.
// - Intel 0|64, same value: little-endian 08 07 .. 01.
const std::vector<Vector>& knownVectors() {
  static const std::vector<Vector> v{
      {spec(0, 16, ByteOrder::Intel), 0x1234, {0x34, 0x12}},
      {spec(4, 12, ByteOrder::Intel), 0xABC, {0xC0, 0xAB}},
      {spec(7, 16, ByteOrder::Motorola), 0x1234, {0x12, 0x34}},
      {spec(3, 12, ByteOrder::Motorola), 0xABC, {0x0A, 0xBC}},
      {spec(12, 8, ByteOrder::Motorola), 0xB5, {0x00, 0x16, 0xA0}},
      {spec(62, 2, ByteOrder::Intel), 0x3, {0, 0, 0, 0, 0, 0, 0, 0xC0}},
      {spec(7, 64, ByteOrder::Motorola),
       0x0102030405060708,
       {0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08}},
      {spec(0, 64, ByteOrder::Intel),
       0x0102030405060708,
       {0x08, 0x07, 0x06, 0x05, 0x04, 0x03, 0x02, 0x01}},
  };
  return v;
}

TEST(SignalCodec, KnownVectorsEncode) {
  for (const Vector& v : knownVectors()) {
    std::array<std::uint8_t, 8> payload{};
    ASSERT_FALSE(encodeRaw(v.spec, v.raw, payload)) << v.spec.startBit;
    EXPECT_EQ(payload, v.bytes) << "start " << v.spec.startBit << " length " << v.spec.length;
  }
}

TEST(SignalCodec, KnownVectorsDecode) {
  for (const Vector& v : knownVectors()) {
    std::uint64_t raw = 0;
    ASSERT_FALSE(decodeRaw(v.spec, v.bytes, raw));
    EXPECT_EQ(raw, v.raw) << "start " << v.spec.startBit << " length " << v.spec.length;
  }
}

TEST(SignalCodec, SignedScaledAndFloatVectors) {
  std::array<std::uint8_t, 8> p{};
  // Signed Intel 0|16 scale 0.01 offset -10: 2.5 -> raw (2.5 + 10) / 0.01 = 1250 = 0x04E2.
  const SignalSpec scaled = spec(0, 16, ByteOrder::Intel, ValueType::Signed, 0.01, -10.0);
  ASSERT_FALSE(encode(scaled, 2.5, p));
  EXPECT_EQ(p[0], 0xE2);
  EXPECT_EQ(p[1], 0x04);
  double value = 0;
  ASSERT_FALSE(decode(scaled, p, value));
  EXPECT_NEAR(value, 2.5, 1e-12);

  // Signed 8 bits: 0x80 is -128, 0xFF is -1.
  const SignalSpec s8 = spec(8, 8, ByteOrder::Intel, ValueType::Signed);
  p = {0, 0x80};
  ASSERT_FALSE(decode(s8, p, value));
  EXPECT_EQ(value, -128.0);
  ASSERT_FALSE(encode(s8, -1.0, p));
  EXPECT_EQ(p[1], 0xFF);

  // float32 1.5 = 0x3FC00000: Intel little-endian 00 00 C0 3F, Motorola 7|32 3F C0 00 00.
  p = {};
  ASSERT_FALSE(encode(spec(0, 32, ByteOrder::Intel, ValueType::Float32), 1.5, p));
  EXPECT_EQ((std::array<std::uint8_t, 4>{p[0], p[1], p[2], p[3]}),
            (std::array<std::uint8_t, 4>{0x00, 0x00, 0xC0, 0x3F}));
  p = {};
  ASSERT_FALSE(encode(spec(7, 32, ByteOrder::Motorola, ValueType::Float32), 1.5, p));
  EXPECT_EQ((std::array<std::uint8_t, 4>{p[0], p[1], p[2], p[3]}),
            (std::array<std::uint8_t, 4>{0x3F, 0xC0, 0x00, 0x00}));
  // float64 -2.0 = 0xC000000000000000, Intel: only the last byte is non-zero (C0).
  p = {};
  const SignalSpec f64 = spec(0, 64, ByteOrder::Intel, ValueType::Float64);
  ASSERT_FALSE(encode(f64, -2.0, p));
  EXPECT_EQ(p[7], 0xC0);
  ASSERT_FALSE(decode(f64, p, value));
  EXPECT_EQ(value, -2.0);
}

TEST(SignalCodec, RangeChecksNeverWrap) {
  std::array<std::uint8_t, 8> p{};
  const SignalSpec u8 = spec(0, 8, ByteOrder::Intel);
  EXPECT_FALSE(encode(u8, 255.0, p));
  EXPECT_FALSE(encode(u8, 255.4, p));                 // rounds to 255
  EXPECT_EQ(encode(u8, 255.5, p), Errc::OutOfRange);  // rounds to 256
  EXPECT_EQ(encode(u8, 256.0, p), Errc::OutOfRange);
  EXPECT_EQ(encode(u8, -1.0, p), Errc::OutOfRange);
  const SignalSpec s8 = spec(0, 8, ByteOrder::Motorola, ValueType::Signed);
  EXPECT_FALSE(encode(s8, 127.0, p));
  EXPECT_FALSE(encode(s8, -128.0, p));
  EXPECT_EQ(encode(s8, 128.0, p), Errc::OutOfRange);
  EXPECT_EQ(encode(s8, -129.0, p), Errc::OutOfRange);
  EXPECT_EQ(encode(s8, std::nan(""), p), Errc::NotFinite);
  EXPECT_EQ(encode(s8, INFINITY, p), Errc::NotFinite);
  const SignalSpec u64 = spec(0, 64, ByteOrder::Intel);
  EXPECT_EQ(encode(u64, 18446744073709551616.0, p), Errc::OutOfRange);  // 2^64
  EXPECT_EQ(encode(spec(0, 32, ByteOrder::Intel, ValueType::Float32), 1e39, p), Errc::OutOfRange);
  // encodeRaw refuses bits above the signal's length.
  EXPECT_EQ(encodeRaw(spec(0, 4, ByteOrder::Intel), 0x10, p), Errc::OutOfRange);

  // DBC [min|max] is enforced on both sides.
  SignalSpec ranged = spec(0, 16, ByteOrder::Intel, ValueType::Signed, 0.01, 0.0);
  ranged.minimum = -10.0;
  ranged.maximum = 10.0;
  EXPECT_FALSE(encode(ranged, 10.0, p));
  EXPECT_EQ(encode(ranged, 10.01, p), Errc::OutOfRange);
  ASSERT_FALSE(encodeRaw(ranged, 1001, p));  // 10.01 mm on the wire
  double value = 0;
  EXPECT_EQ(decode(ranged, p, value), Errc::OutOfRange);

  // A NaN float on the wire is refused.
  p = {0x00, 0x00, 0xC0, 0x7F};  // float32 quiet NaN, little-endian
  EXPECT_EQ(decode(spec(0, 32, ByteOrder::Intel, ValueType::Float32), p, value), Errc::NotFinite);
}

TEST(SignalCodec, OutsideFrameIsRefused) {
  std::array<std::uint8_t, 8> classic{};
  std::array<std::uint8_t, 12> fd{};
  std::uint64_t raw = 0;
  EXPECT_EQ(encodeRaw(spec(60, 8, ByteOrder::Intel), 1, classic), Errc::OutsideFrame);
  EXPECT_EQ(decodeRaw(spec(60, 8, ByteOrder::Intel), classic, raw), Errc::OutsideFrame);
  // Motorola 63|8 is all of byte 7; 63|9 continues into byte 8.
  EXPECT_FALSE(encodeRaw(spec(63, 8, ByteOrder::Motorola), 1, classic));
  EXPECT_EQ(encodeRaw(spec(63, 9, ByteOrder::Motorola), 1, classic), Errc::OutsideFrame);
  EXPECT_FALSE(encodeRaw(spec(63, 9, ByteOrder::Motorola), 1, fd));
  EXPECT_EQ(bytesNeeded(spec(63, 9, ByteOrder::Motorola)), 9u);
  EXPECT_EQ(bytesNeeded(spec(4, 12, ByteOrder::Intel)), 2u);
  EXPECT_EQ(
      decodeRaw(spec(0, 16, ByteOrder::Intel), std::span<const std::uint8_t>(fd.data(), 1), raw),
      Errc::OutsideFrame);
}

TEST(SignalCodec, EncodingLeavesOtherBitsAlone) {
  // Intel 2|4 zero into an all-ones byte clears bits 2..5: 1100'0011 = C3.
  std::array<std::uint8_t, 8> p;
  p.fill(0xFF);
  ASSERT_FALSE(encodeRaw(spec(2, 4, ByteOrder::Intel), 0, p));
  EXPECT_EQ(p[0], 0xC3);
  EXPECT_EQ(p[1], 0xFF);
}

TEST(SignalCodec, LayoutProblems) {
  EXPECT_TRUE(layoutProblem(spec(0, 16, ByteOrder::Intel)).empty());
  EXPECT_FALSE(layoutProblem(spec(0, 0, ByteOrder::Intel)).empty());
  EXPECT_FALSE(layoutProblem(spec(0, 65, ByteOrder::Intel)).empty());
  EXPECT_FALSE(layoutProblem(spec(0, 16, ByteOrder::Intel, ValueType::Float32)).empty());
  EXPECT_FALSE(layoutProblem(spec(0, 32, ByteOrder::Intel, ValueType::Float64)).empty());
  EXPECT_FALSE(layoutProblem(spec(0, 8, ByteOrder::Intel, ValueType::Unsigned, 0.0)).empty());
  EXPECT_FALSE(layoutProblem(spec(505, 8, ByteOrder::Intel)).empty());  // beyond 64 bytes
  SignalSpec big = spec(0, 8, ByteOrder::Intel);
  big.frameId = 0x800;
  EXPECT_FALSE(layoutProblem(big).empty());
  big.extended = true;
  EXPECT_TRUE(layoutProblem(big).empty());
}

// Every layout option against the bit-by-bit reference: both byte orders x signedness x lengths
// crossing byte boundaries x start bits across the payload, random raw values and random
// background bits, which must survive encoding.
TEST(SignalCodec, RoundTripMatchesReferenceForEveryLayout) {
  std::mt19937_64 rng(12345);
  const std::vector<unsigned> lengths{1,  2,  3,  7,  8,  9,  12, 15, 16, 17, 23, 24,
                                      25, 31, 32, 33, 40, 47, 48, 52, 57, 63, 64};
  int cases = 0;
  for (ByteOrder order : {ByteOrder::Intel, ByteOrder::Motorola}) {
    for (ValueType type : {ValueType::Unsigned, ValueType::Signed}) {
      for (unsigned length : lengths) {
        for (unsigned start = 0; start < 8 * 16; start += 5) {
          const SignalSpec s = spec(start, length, order, type);
          const std::size_t need = bytesNeeded(s);
          if (need > 16) continue;
          std::vector<std::uint8_t> payload(16);
          for (auto& b : payload) b = static_cast<std::uint8_t>(rng());
          const std::vector<std::uint8_t> before = payload;
          const std::uint64_t mask = length == 64 ? ~0ull : (1ull << length) - 1;
          const std::uint64_t raw = rng() & mask;
          ASSERT_FALSE(encodeRaw(s, raw, payload));
          EXPECT_EQ(referenceDecode(s, payload), raw) << start << "|" << length;
          std::uint64_t back = 0;
          ASSERT_FALSE(decodeRaw(s, payload, back));
          EXPECT_EQ(back, raw);
          // Bits outside the signal are untouched.
          std::vector<std::uint8_t> occupied(16);
          for (unsigned b : referenceBits(s))
            occupied[b / 8] = static_cast<std::uint8_t>(occupied[b / 8] | (1u << (b % 8)));
          for (std::size_t i = 0; i < 16; ++i)
            EXPECT_EQ(payload[i] & ~occupied[i], before[i] & ~occupied[i])
                << start << "|" << length;
          const std::vector<unsigned> bits = referenceBits(s);
          EXPECT_EQ(need, *std::max_element(bits.begin(), bits.end()) / 8 + 1);
          ++cases;
        }
      }
    }
  }
  EXPECT_GT(cases, 1000);
}

// Physical round trip with scale and offset: raw r -> physical r * scale + offset -> encode ->
// the same raw, for raw values at both ends of the range (lengths up to 52 bits, where a double
// still holds every integer of the range exactly).
TEST(SignalCodec, PhysicalRoundTripWithScaleAndOffset) {
  const std::vector<std::pair<double, double>> scalings{
      {1.0, 0.0}, {0.001, 0.0}, {0.0001, -250.0}, {-0.5, 10.0}, {2.0, 1000.0}};
  for (ByteOrder order : {ByteOrder::Intel, ByteOrder::Motorola}) {
    for (ValueType type : {ValueType::Unsigned, ValueType::Signed}) {
      for (unsigned length : {1u, 8u, 11u, 16u, 21u, 32u, 40u}) {
        for (auto [scale, offset] : scalings) {
          const SignalSpec s =
              spec(order == ByteOrder::Intel ? 3 : 12, length, order, type, scale, offset);
          const bool isSigned = type == ValueType::Signed;
          const double lo = isSigned ? -std::ldexp(1.0, static_cast<int>(length) - 1) : 0.0;
          const double hi = isSigned ? std::ldexp(1.0, static_cast<int>(length) - 1) - 1
                                     : std::ldexp(1.0, static_cast<int>(length)) - 1;
          for (double r : {lo, hi, std::round((lo + hi) / 3), 0.0}) {
            if (r < lo || r > hi) continue;
            std::array<std::uint8_t, 16> p{};
            const double physical = r * scale + offset;
            ASSERT_FALSE(encode(s, physical, p)) << length << " " << r;
            double back = 0;
            ASSERT_FALSE(decode(s, p, back));
            EXPECT_NEAR(back, physical, std::fabs(scale) * 1e-6 + std::fabs(physical) * 1e-12);
          }
          // One count beyond either end is refused.
          std::array<std::uint8_t, 16> p{};
          EXPECT_EQ(encode(s, (hi + 1) * scale + offset, p), Errc::OutOfRange);
          EXPECT_EQ(encode(s, (lo - 1) * scale + offset, p), Errc::OutOfRange);
        }
      }
    }
  }
}

TEST(SignalCodec, FloatRoundTripBothOrders) {
  for (ByteOrder order : {ByteOrder::Intel, ByteOrder::Motorola}) {
    const unsigned start = order == ByteOrder::Intel ? 8 : 15;
    const SignalSpec f32 = spec(start, 32, order, ValueType::Float32, 0.5, 1.0);
    const SignalSpec f64 = spec(start, 64, order, ValueType::Float64);
    for (double v : {0.0, -1.25, 123.456, 1e-3, -98765.4321}) {
      std::array<std::uint8_t, 16> p{};
      double back = 0;
      ASSERT_FALSE(encode(f32, v, p));
      ASSERT_FALSE(decode(f32, p, back));
      // float32 keeps 24 significant bits: relative error <= 2^-24 of (v - 1) / 0.5.
      EXPECT_NEAR(back, v, std::fabs((v - 1.0) / 0.5) * 0.5 * 6e-8 + 1e-12);
      ASSERT_FALSE(encode(f64, v, p));
      ASSERT_FALSE(decode(f64, p, back));
      EXPECT_EQ(back, v);
    }
  }
}

}  // namespace
}  // namespace volcomp::can
