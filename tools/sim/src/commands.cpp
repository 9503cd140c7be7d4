#include "volcomp/sim/commands.hpp"

#include <charconv>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace volcomp::sim {
namespace {

std::vector<std::string> words(std::string_view text) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : text) {
    if (c == ' ' || c == '\t' || c == ':' || c == '\r' || c == '\n') {
      if (!cur.empty()) out.push_back(std::move(cur));
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) out.push_back(std::move(cur));
  return out;
}

double parseNumber(const std::string& s, const std::string& what) {
  double v = 0.0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size() || !std::isfinite(v) || v < 0.0) {
    throw std::invalid_argument("expected " + what + ", got \"" + s + "\"");
  }
  return v;
}

int parseCount(const std::string& s) {
  const double v = parseNumber(s, "a positive whole number");
  if (v < 1 || v > 1e9 || v != std::floor(v)) {
    throw std::invalid_argument("expected a positive whole number, got \"" + s + "\"");
  }
  return static_cast<int>(v);
}

bool parseOnOff(const std::string& s) {
  if (s == "on" || s == "1" || s == "true") return true;
  if (s == "off" || s == "0" || s == "false") return false;
  throw std::invalid_argument("expected on or off, got \"" + s + "\"");
}

}  // namespace

Command parseCommand(std::string_view text) {
  const auto w = words(text);
  if (w.empty()) throw std::invalid_argument("empty command");
  Command c;
  const std::string& name = w[0];
  auto optionalDuration = [&](std::size_t index) {
    if (w.size() > index + 1) throw std::invalid_argument("too many arguments to " + name);
    return w.size() > index ? parseNumber(w[index], "a duration in seconds") : 0.0;
  };
  if (name == "stall") {
    c.kind = Command::Kind::Stall;
    c.durationS = optionalDuration(1);
  } else if (name == "drop-link") {
    c.kind = Command::Kind::DropLink;
    c.durationS = optionalDuration(1);
  } else if (name == "exception") {
    c.kind = Command::Kind::Exception;
    if (w.size() < 2) throw std::invalid_argument("exception needs a code (1..11)");
    const double code = parseNumber(w[1], "an exception code 1..11");
    if (code < 1 || code > 11 || code != std::floor(code)) {
      throw std::invalid_argument("expected an exception code 1..11, got \"" + w[1] + "\"");
    }
    c.exceptionCode = static_cast<int>(code);
    c.durationS = optionalDuration(2);
  } else if (name == "freeze") {
    c.kind = Command::Kind::Freeze;
    c.durationS = optionalDuration(1);
  } else if (name == "hold") {
    c.kind = Command::Kind::Hold;
    c.durationS = optionalDuration(1);
  } else if (name == "late-reply") {
    c.kind = Command::Kind::LateReply;
    if (w.size() < 2 || w.size() > 3) throw std::invalid_argument("late-reply needs S [N]");
    c.durationS = parseNumber(w[1], "a delay in seconds");
    if (w.size() == 3) c.count = parseCount(w[2]);
  } else if (name == "no-reply") {
    c.kind = Command::Kind::NoReply;
    if (w.size() > 2) throw std::invalid_argument("too many arguments to no-reply");
    if (w.size() == 2) c.count = parseCount(w[1]);
  } else if (name == "garble-readback") {
    c.kind = Command::Kind::GarbleReadback;
    if (w.size() < 2) throw std::invalid_argument("garble-readback needs MM [S]");
    c.valueMm = parseNumber(w[1], "a read-back value in mm");
    c.durationS = optionalDuration(2);
  } else if (name == "pause-client") {
    c.kind = Command::Kind::PauseClient;
    if (w.size() != 3) throw std::invalid_argument("pause-client needs PID S");
    c.pid = parseCount(w[1]);
    c.durationS = parseNumber(w[2], "a pause in seconds");
  } else if (name == "enable" || name == "homed" || name == "ack") {
    c.kind = name == "enable"  ? Command::Kind::Enable
             : name == "homed" ? Command::Kind::Homed
                               : Command::Kind::Ack;
    if (w.size() != 2) throw std::invalid_argument(name + " needs on or off");
    c.on = parseOnOff(w[1]);
  } else if (name == "resume" || name == "quit" || name == "status") {
    c.kind = name == "resume" ? Command::Kind::Resume
             : name == "quit" ? Command::Kind::Quit
                              : Command::Kind::Status;
    if (w.size() != 1) throw std::invalid_argument(name + " takes no argument");
  } else {
    throw std::invalid_argument(
        "unknown command \"" + name +
        "\"; expected stall, drop-link, exception, freeze, hold, "
        "late-reply, no-reply, pause-client, garble-readback, enable, homed, "
        "ack, resume, "
        "status or quit");
  }
  return c;
}

ScheduledEvent parseEvent(std::string_view spec) {
  const auto colon = spec.find(':');
  if (colon == std::string_view::npos) {
    throw std::invalid_argument("event \"" + std::string(spec) + "\": expected T:COMMAND[:ARG...]");
  }
  ScheduledEvent e;
  try {
    e.atS = parseNumber(std::string(spec.substr(0, colon)), "a time in seconds");
    e.command = parseCommand(spec.substr(colon + 1));
  } catch (const std::invalid_argument& ex) {
    throw std::invalid_argument("event \"" + std::string(spec) + "\": " + ex.what());
  }
  return e;
}

bool applyCommand(Machine& machine, double tS, const Command& c) {
  switch (c.kind) {
    case Command::Kind::Stall:
      machine.stall(tS, c.durationS);
      break;
    case Command::Kind::DropLink:
      machine.dropLink(tS, c.durationS);
      break;
    case Command::Kind::Exception:
      machine.exception(tS, c.exceptionCode, c.durationS);
      break;
    case Command::Kind::Freeze:
      machine.freeze(tS, c.durationS);
      break;
    case Command::Kind::Hold:
      machine.hold(tS, c.durationS);
      break;
    case Command::Kind::LateReply:
      machine.lateReplies(c.durationS, c.count);
      break;
    case Command::Kind::NoReply:
      machine.dropReplies(c.count);
      break;
    case Command::Kind::PauseClient:
      machine.pauseClient(c.pid, c.durationS);
      break;
    case Command::Kind::GarbleReadback:
      machine.garbleReadback(tS, c.valueMm, c.durationS);
      break;
    case Command::Kind::Ack:
      machine.setFaultAck(c.on);
      break;
    case Command::Kind::Enable:
      machine.setEnable(c.on);
      break;
    case Command::Kind::Homed:
      machine.setHomed(c.on);
      break;
    case Command::Kind::Resume:
      machine.resume();
      break;
    case Command::Kind::Status:
      break;
    case Command::Kind::Quit:
      return false;
  }
  return true;
}

}  // namespace volcomp::sim
