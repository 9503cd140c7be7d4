// The Modbus server role end to end: volcompd as a process holding the register bank, driven by
// masters we did not write: libmodbus' client (TCP, and RTU on a pseudo-terminal) and mbpoll.
// Ports are chosen by the daemon (port 0, read from its log line), ptys by the test. Every
// offset a master reads is checked against the limiter (max_offset, max_rate); offsets held at a
// position are checked against the model itself.
#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <termios.h>

#include <atomic>
#include <regex>
#include <thread>

#include "modbus_server_fixture.hpp"

namespace volcomp::e2e {
namespace {

TEST_F(ModbusServerTest, LibmodbusMasterOverTcpGetsTheModelsOffsetsWithinTheLimiter) {
  const int port = startServer(serverConfig());
  ASSERT_GT(port, 0);
  Master master = Master::tcp(port);
  ASSERT_TRUE(master.connect());
  run(master, 0, 250);
  expectOffsetsOfTheModel(master);
  expectReadsWithinLimits(master.reads);
  // Heartbeat: one cycle per complete position set (plus timer cycles when a set is late).
  const auto& r = master.reads;
  EXPECT_GE(static_cast<int>(r.back().heartbeat - r[r.size() - 101].heartbeat), 100);
  stopDaemon();
}

TEST_F(ModbusServerTest, WritesOutsideTheInputBlockAreRefusedWithIllegalDataAddress) {
  const int port = startServer(serverConfig());
  Master master = Master::tcp(port);
  ASSERT_TRUE(master.connect());
  EXPECT_EQ(modbus_write_register(master.ctx(), 14, 1), -1);  // offset X
  EXPECT_EQ(errno, EMBXILADD);
  std::array<std::uint16_t, 4> regs{};
  EXPECT_EQ(modbus_write_registers(master.ctx(), 12, 4, regs.data()), -1);  // into the outputs
  EXPECT_EQ(errno, EMBXILADD);
  EXPECT_EQ(modbus_read_registers(master.ctx(), 20, 4, regs.data()), -1);  // past the bank
  EXPECT_EQ(errno, EMBXILADD);
  EXPECT_EQ(modbus_read_input_registers(master.ctx(), 0, 1, regs.data()), -1);
  EXPECT_EQ(errno, EMBXILFUN);  // the bank has holding registers only
  // The connection survives its refused requests, and none of them landed: no position set has
  // been written, so no cycle has written the outputs either.
  ASSERT_TRUE(master.cycle(kTo, kEnabledHomed, false));
  EXPECT_EQ(master.reads.back().offsetMm, (std::array<double, 3>{}));
  EXPECT_EQ(master.reads.back().status, 0u);
  EXPECT_EQ(master.reads.back().heartbeat, 0u);
  stopDaemon();
}

TEST_F(ModbusServerTest, MasterGoingSilentIsAStaleFaultWithRampOut) {
  const int port = startServer(serverConfig());
  Master master = Master::tcp(port);
  ASSERT_TRUE(master.connect());
  run(master, 0, 200);
  expectOffsetsOfTheModel(master);
  const std::size_t silentFrom = master.reads.size();
  // The master stops writing but keeps reading: within the stale timeout (500 ms) the daemon
  // faults (stale input) and ramps the offsets to zero at max_rate.
  Pacer pacer(10ms);
  const bool zero = testutil::waitUntil(
      [&] {
        pacer.tick();
        master.cycle(kTo, kEnabledHomed, false);
        const MasterRead& r = master.reads.back();
        return (r.status & kFault) != 0 && largestAbs(r.offsetMm) == 0.0;
      },
      5s);
  ASSERT_TRUE(zero) << daemonLog();
  const auto& reads = master.reads;
  const auto faulted =
      std::find_if(reads.begin() + static_cast<std::ptrdiff_t>(silentFrom), reads.end(),
                   [](const MasterRead& r) { return (r.status & kFault) != 0; });
  ASSERT_NE(faulted, reads.end());
  EXPECT_EQ(faultCodeOf(faulted->status), 1u);  // stale-input
  const double silence = faulted->tS - reads[silentFrom - 1].tS;
  EXPECT_GE(silence, 0.45);
  EXPECT_LE(silence, 1.5);
  // A ramp, not a jump: the offsets at the fault were still those of the model.
  EXPECT_GT(largestAbs(faulted->offsetMm), 5 * kQuantumMm);
  expectReadsWithinLimits(reads);
  EXPECT_NE(daemonLog().find("stale-input"), std::string::npos);
  stopDaemon();
}

TEST_F(ModbusServerTest, ExtraConnectionAndDisallowedClientAreRefused) {
  const int port = startServer(serverConfig());
  Master first = Master::tcp(port);
  ASSERT_TRUE(first.connect());
  ASSERT_TRUE(first.cycle(kFrom, kEnabledHomed));
  Master second = Master::tcp(port);
  second.connect();  // accepted by TCP, closed by the server at once
  EXPECT_FALSE(second.cycle(kFrom, kEnabledHomed));
  ASSERT_TRUE(daemon_->waitForStderr("max_connections reached", 5s)) << daemonLog();
  EXPECT_TRUE(first.cycle(kFrom, kEnabledHomed));
  stopDaemon();

  json only = serverConfig();
  only["transport"]["allowed_clients"] = {"192.0.2.1"};
  const int port2 = startServer(only);
  Master stranger = Master::tcp(port2);
  stranger.connect();
  EXPECT_FALSE(stranger.cycle(kFrom, kEnabledHomed));
  ASSERT_TRUE(daemon_->waitForStderr("address not in allowed_clients", 5s)) << daemonLog();
  stopDaemon();
}

TEST_F(ModbusServerTest, MasterReconnectsToARestartedDaemon) {
  json config = serverConfig();
  const int port = startServer(config);
  Master master = Master::tcp(port);
  ASSERT_TRUE(master.connect());
  run(master, 0, 200);
  expectOffsetsOfTheModel(master);
  // SIGTERM: the daemon ramps out; the master reads the ramp while it lasts.
  daemon_->signal(SIGTERM);
  Pacer pacer(10ms);
  while (daemon_->running()) {
    pacer.tick();
    master.cycle(kTo, kEnabledHomed);
  }
  EXPECT_EQ(daemon_->waitExit(10s), 0) << daemonLog();
  // The master saw the ramp-out (the final zero write may come after its last read).
  EXPECT_TRUE(std::any_of(master.reads.begin(), master.reads.end(),
                          [](const MasterRead& r) { return (r.status & kStopping) != 0; }));
  const std::size_t before = master.reads.size();
  // The same port again: the master's next cycles reconnect.
  config["transport"]["port"] = port;
  ASSERT_EQ(startServer(config), port);
  const bool active = testutil::waitUntil(
      [&] {
        pacer.tick();
        return master.cycle(kTo, kEnabledHomed) && (master.reads.back().status & kActive) != 0;
      },
      10s);
  ASSERT_TRUE(active) << daemonLog();
  EXPECT_GT(master.reads.size(), before);
  run(master, 1000, 100);
  expectOffsetsOfTheModel(master, model::Direction::Unknown);  // held at kTo since the restart
  expectReadsWithinLimits(master.reads);
  stopDaemon();
}

/// A pseudo-terminal pair for the RTU tests: the daemon opens `device`; the master uses `fd`.
struct Pty {
  Pty() {
    char name[256] = {};
    if (openpty(&fd, &slave, name, nullptr, nullptr) == 0) device = name;
  }
  ~Pty() {
    if (fd >= 0) ::close(fd);
    if (slave >= 0) ::close(slave);
  }
  int fd = -1;
  int slave = -1;  // kept open, so that the daemon's side never sees a hang-up
  std::string device;
};

json rtuServerConfig(const std::string& device) {
  json d = json::parse(std::ifstream(exampleFile("volcompd-modbus-server-tcp.json")));
  d["model"] = exampleFile("vmc-xyfz-21.json");
  json t = d["transport"];
  d["transport"] = {{"type", "modbus-rtu"},
                    {"role", "server"},
                    {"device", device},
                    {"baud", 115200},
                    {"slave_id", 1},
                    {"cycle_trigger", "write"},
                    {"registers", t["registers"]}};
  return d;
}

TEST_F(ModbusServerTest, LibmodbusMasterOverRtuOnAPseudoTerminal) {
  Pty pty;
  ASSERT_FALSE(pty.device.empty());
  startDaemon(rtuServerConfig(pty.device));
  ASSERT_TRUE(daemon_->waitForStderr("listening on rtu", 10s)) << daemonLog();
  Master master = Master::rtu(pty.fd, 1);
  run(master, 0, 250);
  expectOffsetsOfTheModel(master);
  expectReadsWithinLimits(master.reads);
  EXPECT_EQ(modbus_write_register(master.ctx(), 21, 1), -1);  // the heartbeat
  EXPECT_EQ(errno, EMBXILADD);
  stopDaemon();
}

/// Runs mbpoll with `args`; returns its exit status and output (stdout and stderr).
int mbpoll(const std::vector<std::string>& args, std::string& output) {
  std::vector<std::string> argv{"/usr/bin/mbpoll"};
  argv.insert(argv.end(), args.begin(), args.end());
  Subprocess p(argv, "");
  const int rc = p.waitExit(10s);
  output = p.output();
  return rc;
}

/// The values of mbpoll's "[ref]: value" lines, in order.
std::vector<long> mbpollValues(const std::string& output) {
  std::vector<long> values;
  static const std::regex line("\\[[0-9]+\\]:\\s+(-?[0-9]+)");
  for (auto it = std::sregex_iterator(output.begin(), output.end(), line);
       it != std::sregex_iterator(); ++it) {
    values.push_back(std::stol((*it)[1].str()));
  }
  return values;
}

/// Reads the output block with one mbpoll run (`args` end with the device or host), appends the
/// read to `reads`; true when every offset is within 1.5 counts of `expected` and ACTIVE is set.
bool mbpollReadReaches(const std::vector<std::string>& args, const std::array<double, 3>& expected,
                       std::vector<MasterRead>& reads, std::string& out) {
  if (mbpoll(args, out) != 0) return false;
  const auto v = mbpollValues(out);
  if (v.size() != 8) return false;
  MasterRead r;
  r.tS = steadySeconds();
  std::array<std::uint16_t, 8> regs{};
  for (std::size_t i = 0; i < 8; ++i) regs[i] = static_cast<std::uint16_t>(v[i]);
  for (std::size_t k = 0; k < 3; ++k) r.offsetMm[k] = int32Mm(&regs[2 * k]);
  r.status = regs[6];
  r.heartbeat = regs[7];
  reads.push_back(r);
  for (std::size_t k = 0; k < 3; ++k) {
    if (std::abs(r.offsetMm[k] - expected[k]) > 1.5 * kQuantumMm) return false;
  }
  return (r.status & kActive) != 0;
}

/// The input block as mbpoll arguments: positions in counts (32-bit, big-endian words), then
/// flags (16-bit) in a second call.
std::vector<std::string> positionCounts(const std::array<double, 3>& q) {
  std::vector<std::string> v{"--"};
  for (double mm : q) v.push_back(std::to_string(std::lround(mm * 1e4)));
  return v;
}

// mbpoll polls: one process writes the positions every 10 ms (-l 10) until it is stopped, one
// mbpoll run at a time reads the outputs. No life counter and no read-back in this map (mbpoll
// writes constant values), so every complete position set is fresh.
TEST_F(ModbusServerTest, MbpollDrivesTheServerOverTcp) {
  json config = serverConfig();
  config["transport"]["registers"].erase("sequence");
  config["transport"]["registers"].erase("applied_offset");
  config["transport"]["max_connections"] = 3;
  config["offset_readback"] = false;
  config["plc_zero_after_ms"] = 100;
  const int port = startServer(config);
  ASSERT_GT(port, 0);
  const std::vector<std::string> tcp{"-m", "tcp", "-p", std::to_string(port), "-0", "-a", "1"};
  std::string out;
  auto with = [&](std::vector<std::string> a, const std::vector<std::string>& tail) {
    a.insert(a.begin(), tcp.begin(), tcp.end());
    a.push_back("127.0.0.1");
    a.insert(a.end(), tail.begin(), tail.end());
    return a;
  };
  ASSERT_EQ(mbpoll(with({"-1", "-r", "6", "-t", "4"}, {"3"}), out), 0) << out;
  std::vector<std::string> writer{"/usr/bin/mbpoll"};
  for (const auto& a : with({"-l", "10", "-r", "0", "-t", "4:int", "-B"}, positionCounts(kTo))) {
    writer.push_back(a);
  }
  Subprocess positions(writer, path("mbpoll-writer.out"));
  const auto expected = modelOffset(kTo, model::Direction::Unknown);  // mbpoll never moves
  std::vector<MasterRead> reads;
  // Read the offsets until they have ramped to the model's (a few hundred ms at max_rate).
  const bool reached = testutil::waitUntil(
      [&] {
        return mbpollReadReaches(with({"-1", "-r", "14", "-c", "8", "-t", "4"}, {}), expected,
                                 reads, out);
      },
      15s);
  ASSERT_TRUE(reached) << out << "\n" << daemonLog();
  expectReadsWithinLimits(reads);
  // A write outside the input block: mbpoll reports the exception and fails.
  EXPECT_NE(mbpoll(with({"-1", "-r", "14", "-t", "4"}, {"5"}), out), 0);
  EXPECT_NE(out.find("Illegal data address"), std::string::npos) << out;
  positions.signal(SIGINT);
  positions.waitExit(5s);
  stopDaemon();
}

/// Copies bytes both ways between the master sides of two ptys, so that mbpoll (which opens a
/// device path) and the daemon (which opens another) talk as over a null-modem cable.
class PtyRelay {
 public:
  PtyRelay() : thread_([this] { relay(); }) {}
  ~PtyRelay() {
    stop_ = true;
    thread_.join();
  }
  Pty daemonSide;
  Pty masterSide;

 private:
  void relay() {
    std::array<char, 512> buf{};
    while (!stop_) {
      pollfd fds[2] = {{daemonSide.fd, POLLIN, 0}, {masterSide.fd, POLLIN, 0}};
      if (::poll(fds, 2, 20) <= 0) continue;
      for (int i = 0; i < 2; ++i) {
        if ((fds[i].revents & POLLIN) == 0) continue;
        const ssize_t n = ::read(fds[i].fd, buf.data(), buf.size());
        if (n > 0) {
          [[maybe_unused]] const auto w =
              ::write(fds[1 - i].fd, buf.data(), static_cast<std::size_t>(n));
        }
      }
    }
  }
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

TEST_F(ModbusServerTest, MbpollOverRtuThroughAPtyPair) {
  PtyRelay relay;
  ASSERT_FALSE(relay.daemonSide.device.empty());
  json config = rtuServerConfig(relay.daemonSide.device);
  config["transport"]["registers"].erase("sequence");
  config["transport"]["registers"].erase("applied_offset");
  config["transport"]["parity"] = "E";  // mbpoll's default parity
  config["offset_readback"] = false;
  config["plc_zero_after_ms"] = 100;
  startDaemon(config);
  ASSERT_TRUE(daemon_->waitForStderr("listening on rtu", 10s)) << daemonLog();
  // The master side's terminal settings are mbpoll's; the relay passes bytes unchanged.
  termios tio{};
  tcgetattr(relay.masterSide.slave, &tio);
  cfmakeraw(&tio);
  tcsetattr(relay.masterSide.slave, TCSANOW, &tio);
  const std::vector<std::string> rtu{"-m", "rtu", "-b", "115200", "-P", "even",
                                     "-0", "-a",  "1",  "-o",     "0.5"};
  std::string out;
  auto with = [&](std::vector<std::string> a, const std::vector<std::string>& tail) {
    a.insert(a.begin(), rtu.begin(), rtu.end());
    a.push_back(relay.masterSide.device);
    a.insert(a.end(), tail.begin(), tail.end());
    return a;
  };
  ASSERT_EQ(mbpoll(with({"-1", "-r", "6", "-t", "4"}, {"3"}), out), 0) << out;
  // Positions and reads alternate (one serial master at a time); each write is one cycle.
  const auto expected = modelOffset(kTo, model::Direction::Unknown);  // mbpoll never moves
  std::vector<MasterRead> reads;
  const bool reached = testutil::waitUntil(
      [&] {
        if (mbpoll(with({"-1", "-r", "0", "-t", "4:int", "-B"}, positionCounts(kTo)), out) != 0) {
          return false;
        }
        return mbpollReadReaches(with({"-1", "-r", "14", "-c", "8", "-t", "4"}, {}), expected,
                                 reads, out);
      },
      20s);
  ASSERT_TRUE(reached) << out << "\n" << daemonLog();
  expectReadsWithinLimits(reads);
  EXPECT_NE(mbpoll(with({"-1", "-r", "20", "-t", "4"}, {"1"}), out), 0);
  EXPECT_NE(out.find("Illegal data address"), std::string::npos) << out;
  stopDaemon();
}

}  // namespace
}  // namespace volcomp::e2e
