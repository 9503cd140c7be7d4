// volcomp-bench-pacing: how late an EMPTY periodic cycle wakes up on this machine, for several
// ways of waiting for an absolute deadline, so that volcompd's overruns can be split into what
// the cycle costs and what the platform's pacing costs.
//
// Modes (each runs --seconds at --period-us, deadlines t0 + k * period, the next one chosen by
// volcompd's own nextDeadline(), so "overruns" means what it means in the daemon):
//   asio        asio::steady_timer::async_wait on an io_context, as PeriodicScheduler does
//   nanosleep   clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME) to the deadline
//   sleep-spin  clock_nanosleep to deadline - margin, then spin on the clock to the deadline
//   spin        never sleep: spin on the clock to the deadline
// Beside the lateness of each wake-up it records, across each mode's run, the steal time of
// /proc/stat (the hypervisor running something else on this vCPU: nothing in the guest can
// change that), the system's context switches, this thread's voluntary and involuntary
// context switches, and for the spinning modes the largest gap between two consecutive clock
// reads while spinning (the vCPU or the thread taken away while it had work to do).
// Pin it and run it under SCHED_FIFO (taskset, chrt) like volcompd; see run_latency.sh.

#include <fcntl.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <asio/io_context.hpp>
#include <asio/steady_timer.hpp>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "volcomp/daemon/scheduler.hpp"

namespace {

using Clock = std::chrono::steady_clock;

struct ProcStat {
  std::uint64_t stealAllTicks = 0;
  std::uint64_t stealCpuTicks = 0;
  std::uint64_t contextSwitches = 0;
};

// /proc/stat: "cpu  user nice system idle iowait irq softirq steal ...", "cpuN ...", "ctxt N".
ProcStat readProcStat(int cpu) {
  ProcStat s;
  std::ifstream in("/proc/stat");
  std::string line;
  const std::string cpuTag = "cpu" + std::to_string(cpu);
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string tag;
    fields >> tag;
    if (tag == "cpu" || tag == cpuTag) {
      std::uint64_t v[8] = {};
      for (auto& x : v) fields >> x;
      (tag == "cpu" ? s.stealAllTicks : s.stealCpuTicks) = v[7];
    } else if (tag == "ctxt") {
      fields >> s.contextSwitches;
    }
  }
  return s;
}

struct ThreadSwitches {
  long voluntary = 0;
  long involuntary = 0;
};

ThreadSwitches threadSwitches() {
  rusage u{};
  getrusage(RUSAGE_THREAD, &u);
  return {u.ru_nvcsw, u.ru_nivcsw};
}

double microseconds(Clock::duration d) {
  return std::chrono::duration<double, std::micro>(d).count();
}

timespec toTimespec(Clock::time_point t) {
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch());
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(ns.count() / 1000000000);
  ts.tv_nsec = static_cast<long>(ns.count() % 1000000000);
  return ts;
}

// steady_clock is CLOCK_MONOTONIC on Linux (libstdc++), so its time points are valid
// clock_nanosleep deadlines.
void sleepUntil(Clock::time_point t) {
  const timespec ts = toTimespec(t);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

/// One mode's run: per-cycle lateness and the deadline bookkeeping of the daemon.
class Run {
 public:
  Run(Clock::duration period, Clock::duration cycle, std::size_t expected)
      : period_(period), cycle_(cycle) {
    lateUs_.reserve(expected + 16);
  }

  /// Records a wake-up for `deadline`, burns the simulated cycle and returns the next deadline.
  Clock::time_point cycle(Clock::time_point deadline) {
    const auto wake = Clock::now();
    lateUs_.push_back(microseconds(wake - deadline));
    auto end = wake;
    if (cycle_.count() > 0) {
      while ((end = Clock::now()) < wake + cycle_) {
      }
    }
    const auto next = volcomp::daemon::nextDeadline(deadline, end, period_);
    if (next.missed > 0) {
      ++overruns_;
      missed_ += next.missed;
    }
    return next.deadline;
  }

  /// Spins until `t`, keeping the largest gap between two clock reads.
  void spinUntil(Clock::time_point t) {
    auto prev = Clock::now();
    while (prev < t) {
      const auto now = Clock::now();
      maxGap_ = std::max(maxGap_, now - prev);
      prev = now;
    }
  }

  std::vector<double>& lateUs() { return lateUs_; }
  std::uint64_t overruns() const { return overruns_; }
  std::uint64_t missed() const { return missed_; }
  Clock::duration maxSpinGap() const { return maxGap_; }

 private:
  Clock::duration period_;
  Clock::duration cycle_;
  std::vector<double> lateUs_;
  std::uint64_t overruns_ = 0;
  std::uint64_t missed_ = 0;
  Clock::duration maxGap_{};
};

void runAsio(Run& run, Clock::time_point start, Clock::time_point stop) {
  asio::io_context io;
  asio::steady_timer timer(io);
  Clock::time_point deadline = start;
  std::function<void(const std::error_code&)> onTimer = [&](const std::error_code& ec) {
    if (ec) return;
    deadline = run.cycle(deadline);
    if (deadline >= stop) return;
    timer.expires_at(deadline);
    timer.async_wait(onTimer);
  };
  timer.expires_at(deadline);
  timer.async_wait(onTimer);
  io.run();
}

void runSleeping(Run& run, Clock::time_point start, Clock::time_point stop, Clock::duration margin,
                 bool sleep) {
  for (Clock::time_point deadline = start; deadline < stop;) {
    if (sleep) sleepUntil(deadline - margin);
    if (margin.count() > 0 || !sleep) run.spinUntil(deadline);
    deadline = run.cycle(deadline);
  }
}

double percentile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return 0.0;
  const auto i = static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1) + 0.5);
  return sorted[std::min(i, sorted.size() - 1)];
}

std::string policyName() {
  const int policy = sched_getscheduler(0);
  sched_param p{};
  sched_getparam(0, &p);
  switch (policy) {
    case SCHED_FIFO:
      return "SCHED_FIFO " + std::to_string(p.sched_priority);
    case SCHED_RR:
      return "SCHED_RR " + std::to_string(p.sched_priority);
    default:
      return "SCHED_OTHER";
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"volcomp-bench-pacing: wake-up lateness of an empty periodic cycle per wait mode"};
  double seconds = 10;
  int periodUs = 1000;
  int marginUs = 900;
  int cycleUs = 0;
  std::vector<std::string> modes{"asio", "nanosleep", "sleep-spin", "spin"};
  bool lockMemory = false;
  long timerSlackNs = 0;
  bool dmaLatency = false;
  bool json = false;
  app.add_option("--seconds", seconds, "duration of each mode's run")->check(CLI::PositiveNumber);
  app.add_option("--period-us", periodUs, "period (absolute deadlines)")
      ->check(CLI::PositiveNumber);
  app.add_option("--modes", modes, "asio, nanosleep, sleep-spin, spin (in this order by default)")
      ->check(CLI::IsMember({"asio", "nanosleep", "sleep-spin", "spin"}))
      ->delimiter(',');
  app.add_option("--margin-us", marginUs, "sleep-spin: wake this long before the deadline")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--cycle-us", cycleUs, "simulated cycle (busy), 0 = an empty cycle")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--mlock", lockMemory, "mlockall(MCL_CURRENT | MCL_FUTURE) first");
  app.add_option("--timer-slack-ns", timerSlackNs, "prctl(PR_SET_TIMERSLACK, N) first; 0 = leave")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--cpu-dma-latency", dmaLatency,
               "hold /dev/cpu_dma_latency at 0 us during the runs (keeps every CPU out of idle "
               "states; system-wide)");
  app.add_flag("--json", json, "one JSON object instead of a table");
  CLI11_PARSE(app, argc, argv);

  if (lockMemory && mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
    std::fprintf(stderr, "volcomp-bench-pacing: mlockall: %s\n", std::strerror(errno));
    return 1;
  }
  if (timerSlackNs > 0 && prctl(PR_SET_TIMERSLACK, static_cast<unsigned long>(timerSlackNs)) != 0) {
    std::fprintf(stderr, "volcomp-bench-pacing: PR_SET_TIMERSLACK: %s\n", std::strerror(errno));
    return 1;
  }
  int dmaFd = -1;
  if (dmaLatency) {
    dmaFd = open("/dev/cpu_dma_latency", O_WRONLY | O_CLOEXEC);
    const std::int32_t zero = 0;
    if (dmaFd < 0 || write(dmaFd, &zero, sizeof zero) != static_cast<ssize_t>(sizeof zero)) {
      std::fprintf(stderr, "volcomp-bench-pacing: /dev/cpu_dma_latency: %s\n",
                   std::strerror(errno));
      return 1;
    }
  }

  const Clock::duration period = std::chrono::microseconds(periodUs);
  const auto runFor =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
  const auto expected = static_cast<std::size_t>(runFor / period);
  const int cpu = sched_getcpu();
  const double tickMs = 1000.0 / static_cast<double>(sysconf(_SC_CLK_TCK));

  nlohmann::json result{{"period_us", periodUs},
                        {"seconds", seconds},
                        {"cpu", cpu},
                        {"policy", policyName()},
                        {"mlock", lockMemory},
                        {"timer_slack_ns", prctl(PR_GET_TIMERSLACK)},
                        {"cpu_dma_latency_0", dmaLatency},
                        {"cycle_us", cycleUs},
                        {"margin_us", marginUs},
                        {"modes", nlohmann::json::array()}};
  for (const std::string& mode : modes) {
    Run run(period, std::chrono::microseconds(cycleUs), expected);
    const ProcStat before = readProcStat(cpu);
    const ThreadSwitches switchesBefore = threadSwitches();
    // Start a few periods ahead so that the first deadline is not already late.
    const auto start = Clock::now() + 5 * period;
    const auto stop = start + runFor;
    if (mode == "asio") {
      runAsio(run, start, stop);
    } else if (mode == "nanosleep") {
      runSleeping(run, start, stop, Clock::duration::zero(), true);
    } else if (mode == "sleep-spin") {
      runSleeping(run, start, stop, std::chrono::microseconds(marginUs), true);
    } else {
      runSleeping(run, start, stop, Clock::duration::zero(), false);
    }
    const ThreadSwitches switchesAfter = threadSwitches();
    const ProcStat after = readProcStat(cpu);
    std::vector<double>& late = run.lateUs();
    std::sort(late.begin(), late.end());
    const auto over = [&](double us) {
      return late.end() - std::upper_bound(late.begin(), late.end(), us);
    };
    nlohmann::json m{
        {"mode", mode},
        {"cycles", late.size()},
        {"expected", expected},
        {"late_median_us", percentile(late, 0.5)},
        {"late_p99_us", percentile(late, 0.99)},
        {"late_p99_9_us", percentile(late, 0.999)},
        {"late_max_us", late.empty() ? 0.0 : late.back()},
        {"late_over_100us", over(100.0)},
        {"late_over_500us", over(500.0)},
        {"overruns", run.overruns()},
        {"missed", run.missed()},
        {"steal_cpu_ms", static_cast<double>(after.stealCpuTicks - before.stealCpuTicks) * tickMs},
        {"steal_all_ms", static_cast<double>(after.stealAllTicks - before.stealAllTicks) * tickMs},
        {"ctxt", after.contextSwitches - before.contextSwitches},
        {"thread_nvcsw", switchesAfter.voluntary - switchesBefore.voluntary},
        {"thread_nivcsw", switchesAfter.involuntary - switchesBefore.involuntary},
        {"max_spin_gap_us", microseconds(run.maxSpinGap())}};
    result["modes"].push_back(m);
  }
  if (dmaFd >= 0) close(dmaFd);

  if (json) {
    std::printf("%s\n", result.dump().c_str());
    return 0;
  }
  std::printf(
      "pacing %d us for %g s per mode on CPU %d, %s%s%s%s, cycle %d us\n", periodUs, seconds, cpu,
      result["policy"].get<std::string>().c_str(), lockMemory ? ", mlockall" : "",
      timerSlackNs > 0 ? (", timer slack " + std::to_string(timerSlackNs) + " ns").c_str() : "",
      dmaLatency ? ", cpu_dma_latency 0" : "", cycleUs);
  std::printf("%-11s %7s %8s %8s %8s %8s %6s %6s %8s %8s %8s %7s %7s %8s\n", "mode", "cycles",
              "med us", "p99 us", "p99.9 us", "max us", ">500us", "overr", "missed", "steal ms",
              "ctxt", "nvcsw", "nivcsw", "gap us");
  for (const auto& m : result["modes"]) {
    std::printf("%-11s %7zu %8.1f %8.1f %8.1f %8.1f %6ld %6llu %8llu %8.0f %8llu %7ld %7ld %8.1f\n",
                m["mode"].get<std::string>().c_str(), m["cycles"].get<std::size_t>(),
                m["late_median_us"].get<double>(), m["late_p99_us"].get<double>(),
                m["late_p99_9_us"].get<double>(), m["late_max_us"].get<double>(),
                m["late_over_500us"].get<long>(),
                static_cast<unsigned long long>(m["overruns"].get<std::uint64_t>()),
                static_cast<unsigned long long>(m["missed"].get<std::uint64_t>()),
                m["steal_cpu_ms"].get<double>(),
                static_cast<unsigned long long>(m["ctxt"].get<std::uint64_t>()),
                m["thread_nvcsw"].get<long>(), m["thread_nivcsw"].get<long>(),
                m["max_spin_gap_us"].get<double>());
  }
  return 0;
}
