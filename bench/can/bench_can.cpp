// Processing time per CAN frame: decoding the signals of an input frame and encoding those of an
// output frame, as the driver does for each frame (no socket). Compare with the bus: a classical
// 8-byte frame at 1 Mbit/s takes ~114 µs on the wire (135 µs worst case with stuffing).
#include <array>
#include <cstdint>
#include <vector>

#include <benchmark/benchmark.h>

#include "volcomp/can/signal.hpp"

namespace {

using volcomp::can::ByteOrder;
using volcomp::can::SignalSpec;
using volcomp::can::ValueType;

SignalSpec make(unsigned start, unsigned length, ByteOrder order, ValueType type, double scale) {
  SignalSpec s;
  s.startBit = start;
  s.length = length;
  s.byteOrder = order;
  s.valueType = type;
  s.scale = scale;
  return s;
}

/// An input frame as in the test layout: two 24-bit positions and an 8-bit sequence counter
/// (Intel), or the same big-endian (Motorola start bits 7, 31, 63).
std::vector<SignalSpec> inputSignals(ByteOrder order) {
  const bool intel = order == ByteOrder::Intel;
  return {make(intel ? 0 : 7, 24, order, ValueType::Signed, 0.0001),
          make(intel ? 24 : 31, 24, order, ValueType::Signed, 0.0001),
          make(intel ? 56 : 63, 8, order, ValueType::Unsigned, 1.0)};
}

/// An output frame: three int16 offsets (µm) and a 16-bit status word.
std::vector<SignalSpec> outputSignals(ByteOrder order) {
  const bool intel = order == ByteOrder::Intel;
  return {make(intel ? 0 : 7, 16, order, ValueType::Signed, 0.001),
          make(intel ? 16 : 23, 16, order, ValueType::Signed, 0.001),
          make(intel ? 32 : 39, 16, order, ValueType::Signed, 0.001),
          make(intel ? 48 : 55, 16, order, ValueType::Unsigned, 1.0)};
}

void decodeFrame(benchmark::State& state, ByteOrder order) {
  const auto signals = inputSignals(order);
  std::array<std::uint8_t, 8> payload{0x87, 0xD6, 0x12, 0xFF, 0xFF, 0xFF, 0x00, 0x05};
  std::array<double, 3> values{};
  for (auto _ : state) {
    benchmark::DoNotOptimize(payload);
    for (std::size_t i = 0; i < signals.size(); ++i)
      benchmark::DoNotOptimize(volcomp::can::decode(signals[i], payload, values[i]));
    benchmark::DoNotOptimize(values);
  }
  state.counters["frames/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void encodeFrame(benchmark::State& state, ByteOrder order) {
  const auto signals = outputSignals(order);
  std::array<std::uint8_t, 8> payload{};
  const std::array<double, 4> values{0.012, -0.002, 0.25, 4105.0};
  for (auto _ : state) {
    payload.fill(0);
    for (std::size_t i = 0; i < signals.size(); ++i)
      benchmark::DoNotOptimize(volcomp::can::encode(signals[i], values[i], payload));
    benchmark::DoNotOptimize(payload);
  }
  state.counters["frames/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

/// One input frame decoded and one output frame encoded: the codec work per frame pair.
void decodeEncodePair(benchmark::State& state, ByteOrder order) {
  const auto in = inputSignals(order);
  const auto out = outputSignals(order);
  std::array<std::uint8_t, 8> rx{0x87, 0xD6, 0x12, 0xFF, 0xFF, 0xFF, 0x00, 0x05};
  std::array<std::uint8_t, 8> tx{};
  std::array<double, 4> values{};
  for (auto _ : state) {
    benchmark::DoNotOptimize(rx);
    for (std::size_t i = 0; i < in.size(); ++i) volcomp::can::decode(in[i], rx, values[i]);
    values[3] = 4105.0;
    tx.fill(0);
    for (std::size_t i = 0; i < out.size(); ++i)
      benchmark::DoNotOptimize(volcomp::can::encode(out[i], values[i] * 1e-4, tx));
    benchmark::DoNotOptimize(tx);
  }
}

/// A 64-byte CAN FD frame full of 64-bit values, the most bits one frame can carry.
void decodeFdFrame(benchmark::State& state) {
  std::vector<SignalSpec> signals;
  for (unsigned i = 0; i < 8; ++i)
    signals.push_back(make(64 * i, 64, ByteOrder::Intel, ValueType::Float64, 1.0));
  std::array<std::uint8_t, 64> payload{};
  std::array<double, 8> values{};
  for (std::size_t i = 0; i < 8; ++i) volcomp::can::encode(signals[i], 1.5 * double(i), payload);
  for (auto _ : state) {
    benchmark::DoNotOptimize(payload);
    for (std::size_t i = 0; i < 8; ++i) volcomp::can::decode(signals[i], payload, values[i]);
    benchmark::DoNotOptimize(values);
  }
}

BENCHMARK_CAPTURE(decodeFrame, intel, ByteOrder::Intel);
BENCHMARK_CAPTURE(decodeFrame, motorola, ByteOrder::Motorola);
BENCHMARK_CAPTURE(encodeFrame, intel, ByteOrder::Intel);
BENCHMARK_CAPTURE(encodeFrame, motorola, ByteOrder::Motorola);
BENCHMARK_CAPTURE(decodeEncodePair, intel, ByteOrder::Intel);
BENCHMARK_CAPTURE(decodeEncodePair, motorola, ByteOrder::Motorola);
BENCHMARK(decodeFdFrame);

}  // namespace

BENCHMARK_MAIN();
