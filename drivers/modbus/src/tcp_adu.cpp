#include "volcomp/modbus/tcp_adu.hpp"

namespace volcomp::modbus {

TcpAduStatus tcpAdu(std::span<const std::uint8_t> received) noexcept {
  if (received.size() < 6) return {};
  const unsigned protocol = (received[2] << 8) | received[3];
  const unsigned length = (received[4] << 8) | received[5];
  if (protocol != 0 || length < 2 || length > kMaxTcpAduBytes - 6) {
    return {TcpAduStatus::Kind::OutOfStep, 0};
  }
  const std::size_t bytes = 6 + length;
  if (received.size() < bytes) return {};
  return {TcpAduStatus::Kind::Complete, bytes};
}

std::array<std::uint8_t, 9> tcpExceptionReply(std::span<const std::uint8_t> request,
                                              std::uint8_t code) noexcept {
  return {request[0], request[1], 0,          0,
          0,          3,          request[6], static_cast<std::uint8_t>(request[7] | 0x80),
          code};
}

}  // namespace volcomp::modbus
