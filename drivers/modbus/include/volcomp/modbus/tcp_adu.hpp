#pragma once
/// Modbus/TCP application data units as the server role receives and refuses them, as pure
/// functions (Modbus Messaging on TCP/IP Implementation Guide v1.0b, 3.1.3). An ADU is the MBAP
/// header (transaction id, protocol id 0, length of what follows, unit id: 7 bytes) and the PDU
/// (function code and data, at most 253 bytes). The header's length field says where an ADU ends,
/// so the server collects a connection's bytes without ever waiting on one connection.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace volcomp::modbus {

inline constexpr std::size_t kMbapBytes = 7;
inline constexpr std::size_t kMaxTcpAduBytes = 260;

/// What the bytes received so far on a connection begin with.
struct TcpAduStatus {
  enum class Kind { Incomplete, Complete, OutOfStep };
  Kind kind = Kind::Incomplete;
  /// Complete: the bytes of the first ADU (header and PDU).
  std::size_t bytes = 0;
};

/// Complete when `received` holds a whole ADU at its front; Incomplete while the header or the
/// PDU it announces is still arriving; OutOfStep when the header is no Modbus/TCP header (protocol
/// id other than 0, or a length field outside 2..254: no unit id and function code, or more than
/// the largest PDU). Judged as soon as 6 bytes are in.
TcpAduStatus tcpAdu(std::span<const std::uint8_t> received) noexcept;

/// The exception reply to the request ADU `request` (at least header and function code): the
/// request's transaction and unit id, function code | 0x80 (a function code that already has
/// the high bit keeps it: 0x83 is answered as 0x83, never wrapped to 0x03), `code`.
std::array<std::uint8_t, 9> tcpExceptionReply(std::span<const std::uint8_t> request,
                                              std::uint8_t code) noexcept;

}  // namespace volcomp::modbus
