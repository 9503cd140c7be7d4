#pragma once
// An independent Modbus master for the server-role tests: libmodbus' own client (TCP, or RTU on a
// pseudo-terminal's master side), paced by a timerfd like a PLC cycle (the test waits on the
// timer, it does not sleep). Each cycle writes the input block of the example register map
// (positions, flags, life counter, applied offsets = the offsets it read last, as a controller
// that applies them) and reads the output block; every read is recorded with its time.

#include <modbus/modbus.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace volcomp::e2e {

/// One read of the output block as the master saw it.
struct MasterRead {
  double tS = 0.0;  ///< steady clock, s
  std::array<double, 3> offsetMm{};
  unsigned status = 0;
  unsigned heartbeat = 0;
};

/// Waits for the next tick of a periodic timer (a PLC's cycle).
class Pacer {
 public:
  explicit Pacer(std::chrono::milliseconds period)
      : fd_(::timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC)) {
    itimerspec spec{};
    spec.it_interval.tv_nsec = std::chrono::nanoseconds(period).count();
    spec.it_value = spec.it_interval;
    ::timerfd_settime(fd_, 0, &spec, nullptr);
  }
  ~Pacer() { ::close(fd_); }
  Pacer(const Pacer&) = delete;
  Pacer& operator=(const Pacer&) = delete;
  void tick() const {
    std::uint64_t expirations = 0;
    [[maybe_unused]] const auto n = ::read(fd_, &expirations, sizeof expirations);
  }

 private:
  int fd_;
};

inline double steadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

inline void putInt32(std::uint16_t* r, double mm) {
  const auto counts = static_cast<std::uint32_t>(static_cast<std::int32_t>(std::lround(mm * 1e4)));
  r[0] = static_cast<std::uint16_t>(counts >> 16);
  r[1] = static_cast<std::uint16_t>(counts & 0xFFFFu);
}

inline double int32Mm(const std::uint16_t* r) {
  return static_cast<std::int32_t>((static_cast<std::uint32_t>(r[0]) << 16) | r[1]) / 1e4;
}

class Master {
 public:
  /// TCP to 127.0.0.1:port.
  static Master tcp(int port) { return Master(modbus_new_tcp("127.0.0.1", port), -1); }
  /// RTU through the master side `ptyFd` of a pseudo-terminal (no device path to open).
  static Master rtu(int ptyFd, int slaveId) {
    Master m(modbus_new_rtu("/dev/null", 115200, 'N', 8, 1), ptyFd);
    modbus_set_slave(m.ctx_, slaveId);
    return m;
  }
  Master(Master&& o) noexcept : ctx_(o.ctx_), ptyFd_(o.ptyFd_), up_(o.up_) { o.ctx_ = nullptr; }
  ~Master() {
    if (ctx_ == nullptr) return;
    if (ptyFd_ >= 0) modbus_set_socket(ctx_, -1);
    modbus_close(ctx_);
    modbus_free(ctx_);
  }

  modbus_t* ctx() const { return ctx_; }
  bool connect() {
    if (up_) return true;
    if (ptyFd_ >= 0) {
      modbus_set_socket(ctx_, ptyFd_);
      up_ = true;
    } else {
      up_ = modbus_connect(ctx_) == 0;
      if (!up_) modbus_close(ctx_);
    }
    return up_;
  }

  /// One PLC cycle: writes the inputs (or only reads, when `writeInputs` is false) and reads the
  /// outputs. A failed transaction closes a TCP connection (reopened by the next connect()).
  bool cycle(const std::array<double, 3>& qMm, std::uint16_t flags, bool writeInputs = true) {
    if (!connect()) return false;
    if (writeInputs) {
      std::array<std::uint16_t, 14> in{};
      for (std::size_t k = 0; k < 3; ++k) putInt32(&in[2 * k], qMm[k]);
      in[6] = flags;
      in[7] = ++life_;
      for (std::size_t k = 0; k < 3; ++k) putInt32(&in[8 + 2 * k], applied_[k]);
      if (modbus_write_registers(ctx_, 0, 14, in.data()) != 14) return fail();
    }
    std::array<std::uint16_t, 8> out{};
    if (modbus_read_registers(ctx_, 14, 8, out.data()) != 8) return fail();
    MasterRead r;
    r.tS = steadySeconds();
    for (std::size_t k = 0; k < 3; ++k) r.offsetMm[k] = int32Mm(&out[2 * k]);
    r.status = out[6];
    r.heartbeat = out[7];
    applied_ = r.offsetMm;
    reads.push_back(r);
    return true;
  }

  std::vector<MasterRead> reads;

 private:
  Master(modbus_t* ctx, int ptyFd) : ctx_(ctx), ptyFd_(ptyFd) {
    modbus_set_response_timeout(ctx_, 1, 0);
  }
  bool fail() {
    if (ptyFd_ < 0) {
      modbus_close(ctx_);
      up_ = false;
    }
    return false;
  }

  modbus_t* ctx_;
  int ptyFd_;
  bool up_ = false;
  std::uint16_t life_ = 0;
  std::array<double, 3> applied_{};
};

}  // namespace volcomp::e2e
