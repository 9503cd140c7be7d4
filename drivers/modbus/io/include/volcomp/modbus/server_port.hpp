#pragma once
/// The server role: volcompd holds the register bank (the same typed register map as the client
/// role, laid out by server_bank.hpp) and a controller acting as Modbus master writes positions,
/// enable, homed, fault ack, life counter and applied offsets, and reads offsets, status and
/// heartbeat. Implements the loop's ControllerPort over libmodbus' server side.
///
/// TCP: one service thread serves every connection without ever waiting on one. It collects each
/// connection's bytes as they come (non-blocking; the MBAP header says where a request ends,
/// tcp_adu.hpp), answers one whole request per connection in turn, refuses what the bank does not
/// serve with the exception at once (server_bank.hpp's refuseRequest; libmodbus' own exception
/// path waits out a response timeout), and passes only requests it serves to modbus_reply. A
/// request that takes longer than response_timeout_ms from its first byte to its last, a header
/// that is no Modbus/TCP header, a master that does not read its replies, and a connection silent
/// for idle_timeout_s are closed; TCP keepalive finds a peer that vanished. When max_connections
/// are open, a new connection from an allowed client replaces the one silent longest if it has
/// been silent for takeover_after_ms (a master that polls is never displaced), otherwise it is
/// closed. RTU: the serial device as slave (one master: modbus_receive, then the same refusals).
///
/// Threads: the loop's read() and write() copy the inputs out of and the outputs into the bank
/// under a mutex held for a copy only (never during I/O), so a slow or hostile master cannot
/// stall a cycle. read() and write() never allocate.
///
/// Freshness: read() reports hasSequence with a count of fresh position sets in place of the
/// master's life counter. It advances when a master completes a position set (every position
/// register written over one connection since that connection's previous set) and, if a life
/// counter is mapped, that counter has changed since the previous advance. The loop's stale
/// timeout therefore applies exactly as in the client role: a master that stops writing (or whose
/// life counter freezes) is StaleInput. Until the first complete set read() fails with
/// Errc::no_master_write (the loop stays in Starting).
///
/// Link: connect() opens the listening socket (TCP) or the device (RTU) and starts the service
/// thread; a master coming and going is not a link event (its silence is stale input). An RTU
/// device that fails (hang-up, unplugged adapter) makes connected() false; the loop reconnects.

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <system_error>
#include <thread>
#include <vector>

#include "volcomp/loop/ports.hpp"
#include "volcomp/modbus/register_plan.hpp"
#include "volcomp/modbus/server_bank.hpp"
#include "volcomp/modbus/settings.hpp"
#include "volcomp/modbus/tcp_adu.hpp"

struct _modbus;            // libmodbus' modbus_t
struct _modbus_mapping_t;  // libmodbus' modbus_mapping_t

namespace volcomp::modbus {

/// Counters of the service thread (any thread may read them).
struct ServerCounters {
  std::atomic<std::uint64_t> requests{0};
  std::atomic<std::uint64_t> refused{0};  ///< answered with an exception (refuseRequest)
  std::atomic<std::uint64_t> positionSets{0};
  std::atomic<std::uint64_t> connections{0};         ///< accepted
  std::atomic<std::uint64_t> refusedConnections{0};  ///< disallowed address or over the limit
  std::atomic<std::uint64_t> replacedConnections{
      0};                                            ///< silent ones that gave a new one their slot
  std::atomic<std::uint64_t> droppedConnections{0};  ///< closed for slowness, silence or garbage
};

class ModbusServerPort final : public loop::ControllerPort {
 public:
  /// Lines for the log (connections accepted, refused and closed; the listening endpoint); called
  /// from the service thread and from connect().
  using Notice = std::function<void(bool warning, std::string_view line)>;

  /// `settings.role` must be Server and every input a holding register (the configuration
  /// checks both). Throws std::system_error when libmodbus refuses the parameters.
  ModbusServerPort(ModbusSettings settings, Notice notice = {});
  ~ModbusServerPort() override;
  ModbusServerPort(const ModbusServerPort&) = delete;
  ModbusServerPort& operator=(const ModbusServerPort&) = delete;

  /// With cycle_trigger `write`: called from the service thread when a complete position set has
  /// been written and no earlier call is still unanswered by a read() (so calls do not pile up).
  /// Set before connect().
  void setCycleTrigger(std::function<void()> trigger) { trigger_ = std::move(trigger); }

  std::error_code connect() noexcept override;
  void disconnect() noexcept override;
  bool connected() const noexcept override { return serving_ && !failed_; }
  std::error_code read(loop::AxisSample& out) noexcept override;
  std::error_code write(const loop::OffsetCommand& command) noexcept override;

  const ModbusSettings& settings() const noexcept { return settings_; }
  const ServerLayout& layout() const noexcept { return layout_; }
  /// TCP: the port listened on (the chosen one when configured 0); 0 before connect().
  std::uint16_t boundPort() const noexcept { return boundPort_; }
  const ServerCounters& counters() const noexcept { return counters_; }

 private:
  using SteadyClock = std::chrono::steady_clock;
  struct Client {
    Client(int socket, std::string name, const RegisterMap& map, SteadyClock::time_point now)
        : fd(socket), peer(std::move(name)), tracker(map), lastRequest(now) {}
    int fd = -1;
    std::string peer;
    PositionWriteTracker tracker;  // a set is complete over one connection
    std::array<std::uint8_t, kMaxTcpAduBytes> received{};
    std::size_t filled = 0;
    SteadyClock::time_point partialSince;  // first byte of the request still arriving
    SteadyClock::time_point lastRequest;   // accepted, or the last whole request
  };
  void serveTcp() noexcept;
  void serveRtu() noexcept;
  /// Milliseconds until the next connection deadline (-1: none); closes those already past.
  int expireClients(SteadyClock::time_point now) noexcept;
  void acceptClient(SteadyClock::time_point now) noexcept;
  void closeClient(std::size_t index, const std::string& why) noexcept;
  /// Reads what has arrived on a connection; false when it is closed, broken or out of step.
  bool receive(Client& client, SteadyClock::time_point now, std::string& why) noexcept;
  /// Answers the whole request at the front of the connection's bytes; false when the reply
  /// could not be sent.
  bool answerTcp(Client& client, SteadyClock::time_point now) noexcept;
  /// Receives and answers one request on the serial device; false when the device failed.
  bool answerRtu() noexcept;
  /// Serves an accepted request (libmodbus' reply; the master's writes into the inputs).
  int reply(const std::uint8_t* adu, int length, std::span<const std::uint8_t> pdu,
            PositionWriteTracker& tracker) noexcept;
  void notice(bool warning, const std::string& line) const;

  ModbusSettings settings_;
  Notice notice_;
  std::function<void()> trigger_;
  ServerLayout layout_;
  PositionWriteTracker rtuTracker_;  // service thread only
  _modbus* ctx_ = nullptr;
  _modbus_mapping_t* mapping_ = nullptr;  // service thread only while serving
  std::thread thread_;
  int listenFd_ = -1;
  int wakeFd_ = -1;  // eventfd: stops the service thread
  std::vector<Client> clients_;
  std::uint16_t boundPort_ = 0;
  bool serving_ = false;
  std::atomic<bool> failed_{false};
  std::atomic<bool> triggerPending_{false};
  ServerCounters counters_;
  std::array<std::uint8_t, 260> query_{};  // RTU: MODBUS_RTU_MAX_ADU_LENGTH is 256

  // Shared between the service thread and the loop, under mutex_.
  std::mutex mutex_;
  std::array<std::uint16_t, 125> inputs_{};   // the input block as the master wrote it
  std::array<std::uint16_t, 123> outputs_{};  // the output block as the loop wrote it
  bool haveSet_ = false;
  std::uint16_t freshness_ = 0;
  std::uint16_t lastLife_ = 0;

  // The loop's own buffers (read/write thread only).
  std::array<std::uint16_t, 125> readBuffer_{};
  std::array<std::uint16_t, 123> writeBuffer_{};
};

}  // namespace volcomp::modbus
