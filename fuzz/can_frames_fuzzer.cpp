// CAN frames as the daemon receives them: each datagram a raw socket returns (its size and its
// struct canfd_frame bytes, so also error frames, remote requests, bad DLCs and oversized
// lengths) goes through deliverDatagram, what the channel does with every receive, into the
// daemon's CanControllerPort with the example configuration's layout (its DBC), classical and
// CAN FD. Every datagram is counted exactly once (accepted, malformed, unknown or error frame);
// a complete set's frames decode to finite values within their signals' ranges.
// Input: datagrams back to back, each one byte choosing the size and then the frame's bytes.

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <variant>

#include "fuzz_support.hpp"
#include "volcomp/can/controller_port.hpp"
#include "volcomp/can/signal.hpp"
#include "volcomp/config/json_reader.hpp"
#include "volcomp/config/transport_config.hpp"

namespace {

using namespace volcomp;

const can::CanLayout& exampleLayout(bool fd) {
  static const std::array<can::CanLayout, 2> layouts = [] {
    const std::string file = VOLCOMP_EXAMPLES_DIR + "/volcompd-can.json";
    nlohmann::json section = config::readJsonFile(file).at("transport");
    std::array<can::CanLayout, 2> out;
    for (const bool withFd : {false, true}) {
      section["fd"] = withFd;
      out[withFd ? 1 : 0] =
          std::get<can::CanLayout>(config::parseTransportSettings(section, file, "transport"));
    }
    return out;
  }();
  return layouts[fd ? 1 : 0];
}

/// Sizes a receive can return: the two MTUs, and what a broken or foreign socket might give.
constexpr std::array<std::size_t, 6> kSizes{CAN_MTU, CANFD_MTU, CAN_MTU, CANFD_MTU, 0, CAN_MTU - 1};

void checkSet(const can::CanControllerPort& port) {
  const can::CanLayout& layout = port.layout();
  const auto& frames = port.lastInputFrames();
  fuzz::require(frames.size() == layout.inputFrames.size(), "input frames not one per layout");
  for (std::size_t i = 0; i < frames.size(); ++i) {
    for (const can::FieldSignal& s : layout.inputFrames[i].signals) {
      double value = 0.0;
      fuzz::require(!can::decode(s.spec, can::payloadOf(frames[i]), value),
                    "a frame of a complete set does not decode");
      fuzz::require(std::isfinite(value), "a value of a complete set is not finite");
      if (s.spec.minimum < s.spec.maximum) {
        fuzz::require(value >= s.spec.minimum && value <= s.spec.maximum,
                      "a value of a complete set is outside its range");
      }
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::ByteReader in(data, size);
  const bool fd = (in.take<std::uint8_t>() & 1) != 0;
  can::CanControllerPort port(exampleLayout(fd));
  std::uint64_t datagrams = 0;
  while (in.remaining() > 0) {
    const std::size_t bytes = kSizes[in.take<std::uint8_t>() % kSizes.size()];
    canfd_frame datagram{};
    datagram.can_id = in.take<std::uint32_t>();
    datagram.len = in.take<std::uint8_t>();
    datagram.flags = in.take<std::uint8_t>();
    const std::size_t payload = bytes == CANFD_MTU ? CANFD_MAX_DLEN : CAN_MAX_DLEN;
    for (std::size_t k = 0; k < payload; ++k) datagram.data[k] = in.take<std::uint8_t>();
    const std::uint64_t setsBefore = port.stats().completeSets;
    port.receive(datagram, bytes);
    ++datagrams;
    if (port.stats().completeSets != setsBefore) checkSet(port);
  }
  const can::CanStats& s = port.stats();
  fuzz::require(s.framesReceived + s.malformedFrames + s.unknownFrames + s.errorFrames == datagrams,
                "a datagram was not counted exactly once");
  fuzz::require(s.completeSets <= s.framesReceived, "more complete sets than frames");
  return 0;
}
