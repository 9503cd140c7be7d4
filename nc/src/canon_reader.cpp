#include "volcomp/nc/canon_reader.hpp"

#include <charconv>
#include <cmath>

#include "volcomp/config/printable.hpp"
#include "volcomp/nc/nc_error.hpp"
#include "volcomp/nc/numbers.hpp"

namespace volcomp::nc {

struct CanonReader::Arguments {
  static constexpr int kMax = 16;
  std::array<std::string_view, kMax> items{};
  std::array<std::size_t, kMax> offsets{};
  int count = 0;
  std::string_view raw;  // between the parentheses
  std::size_t rawOffset = 0;
};

namespace {

bool isBlank(char c) noexcept {
  return c == ' ' || c == '\t' || c == '\r';
}

// Parses "  12 N..... NAME(args)"; returns false when the line is not in that shape.
bool splitCanonical(std::string_view line, std::string_view& name, std::size_t& nameOffset,
                    std::string_view& raw, std::size_t& rawOffset) {
  std::size_t i = 0;
  while (i < line.size() && isBlank(line[i])) ++i;
  const std::size_t digits = i;
  while (i < line.size() && line[i] >= '0' && line[i] <= '9') ++i;
  if (i == digits) return false;
  while (i < line.size() && isBlank(line[i])) ++i;
  if (i >= line.size() || line[i] != 'N') return false;
  ++i;
  while (i < line.size() && ((line[i] >= '0' && line[i] <= '9') || line[i] == '.')) ++i;
  while (i < line.size() && isBlank(line[i])) ++i;
  nameOffset = i;
  while (i < line.size() &&
         ((line[i] >= 'A' && line[i] <= 'Z') || (line[i] >= '0' && line[i] <= '9') ||
          line[i] == '_' || line[i] == '.')) {
    ++i;
  }
  if (i == nameOffset || i >= line.size() || line[i] != '(') return false;
  name = line.substr(nameOffset, i - nameOffset);
  std::size_t close = line.size();
  while (close > i && (isBlank(line[close - 1]))) --close;
  if (close == i + 1 || line[close - 1] != ')') return false;
  rawOffset = i + 1;
  raw = line.substr(rawOffset, close - 1 - rawOffset);
  return true;
}

bool toNumber(std::string_view text, double& value) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  return ec == std::errc() && end == text.data() + text.size() && std::isfinite(value);
}

// The text of a quoted argument (COMMENT("..."), MESSAGE("...")).
std::string_view quotedText(std::string_view raw) {
  const std::size_t open = raw.find('"');
  const std::size_t close = raw.rfind('"');
  if (open == std::string_view::npos || close <= open) return raw;
  return raw.substr(open + 1, close - open - 1);
}

std::string commentSafe(std::string_view text) {
  std::string s(text);
  for (char& c : s) {
    if (c == '(') c = '[';
    if (c == ')') c = ']';
  }
  return s;
}

}  // namespace

CanonReader::CanonReader(std::string file, std::optional<Vec3> startMm, Decimals decimals)
    : file_(std::move(file)), decimals_(decimals) {
  if (startMm) {
    position_.machineMm = *startMm;
    position_.known = 7;
  }
}

bool CanonReader::looksCanonical(std::string_view line) {
  std::string_view name, raw;
  std::size_t a = 0, b = 0;
  return splitCanonical(line, name, a, raw, b);
}

void CanonReader::fail(long number, std::size_t offset, const std::string& message) const {
  throw NcError(file_, number, static_cast<int>(offset) + 1, message);
}

PrintMode CanonReader::printMode() const noexcept {
  PrintMode m;
  m.frame.unitMm = mmPerUnit(units_);
  m.frame.shiftMm = g5xMm_ + g92StartMm_.value_or(Vec3::Zero()) + toolMm_;
  m.decimals = units_ == LengthUnit::Inch ? decimals_.inch : decimals_.mm;
  return m;
}

void CanonReader::appendLength(std::string& out, double valueMm) const {
  const PrintMode m = printMode();
  appendFixed(out, valueMm / m.frame.unitMm, m.decimals);
}

void CanonReader::header(std::string& out) {
  out += "(volcomp nc: flat program from the LinuxCNC canonical commands of ";
  out += commentSafe(file_);
  out += ")\nG90 G94 G40 G49\n";
}

void CanonReader::trailer(std::string& out) {
  if (!programEnd_) out += "M2\n";
}

void CanonReader::read(std::string_view line, std::string_view eol, long number, Chunk& chunk) {
  LineWork work;
  work.input = line;
  work.eol = eol;
  work.action = LineAction::Drop;
  std::string_view trimmed = line;
  while (!trimmed.empty() && isBlank(trimmed.back())) trimmed.remove_suffix(1);
  if (trimmed.find_first_not_of(" \t") == std::string_view::npos || programEnd_) {
    chunk.lines.push_back(work);
    return;
  }
  std::string_view name;
  std::size_t nameOffset = 0;
  Arguments args;
  if (!splitCanonical(line, name, nameOffset, args.raw, args.rawOffset)) {
    fail(number, 0,
         "not a canonical command line (expected the output of rs274 -g, such as \"  12 N..... "
         "STRAIGHT_FEED(1.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)\")");
  }
  if (name != "COMMENT" && name != "MESSAGE" && name.rfind("LOG", 0) != 0 && name != "SYSTEM") {
    std::size_t i = 0;
    while (i < args.raw.size()) {
      while (i < args.raw.size() && (isBlank(args.raw[i]) || args.raw[i] == ',')) ++i;
      const std::size_t start = i;
      while (i < args.raw.size() && !isBlank(args.raw[i]) && args.raw[i] != ',') ++i;
      if (i == start) break;
      if (args.count == Arguments::kMax) fail(number, args.rawOffset + start, "too many arguments");
      args.items[static_cast<std::size_t>(args.count)] = args.raw.substr(start, i - start);
      args.offsets[static_cast<std::size_t>(args.count++)] = args.rawOffset + start;
    }
  }
  const auto number_ = [&](int index) { return argument(args, name, number, index); };
  const auto toolNumber = [&](int index) {
    const double tool = number_(index);
    if (!isToolNumber(tool)) {
      fail(number, args.offsets[static_cast<std::size_t>(index)],
           std::string(name) + ": tool number must be a whole number in 0..2147483647");
    }
    return std::to_string(static_cast<long>(tool));
  };
  std::string text;
  const auto emit = [&](const std::string& t) {
    work.action = LineAction::Text;
    work.text = chunk.store(t);
  };
  const double unit = mmPerUnit(units_);

  if (name == "STRAIGHT_TRAVERSE" || name == "STRAIGHT_FEED" || name == "ARC_FEED") {
    motion(args, name, number, line, eol, chunk);
    return;
  }
  if (name == "USE_LENGTH_UNITS") {
    const std::string_view u = args.count > 0 ? args.items[0] : std::string_view();
    if (u != "CANON_UNITS_MM" && u != "CANON_UNITS_INCHES") {
      fail(number, args.rawOffset,
           "USE_LENGTH_UNITS: expected CANON_UNITS_MM or CANON_UNITS_INCHES");
    }
    const LengthUnit next = u == "CANON_UNITS_MM" ? LengthUnit::Mm : LengthUnit::Inch;
    if (!unitsWritten_ || next != units_) emit(next == LengthUnit::Mm ? "G21" : "G20");
    units_ = next;
    unitsWritten_ = true;
  } else if (name == "SET_G5X_OFFSET") {
    const double index = number_(0);
    if (index < 1 || index > 9 || index != std::floor(index)) {
      fail(number, args.offsets[0], "SET_G5X_OFFSET: coordinate system must be 1 .. 9");
    }
    const auto k = static_cast<std::size_t>(index) - 1;
    const Vec3 v(number_(1) * unit, number_(2) * unit, number_(3) * unit);
    if (!systemsMm_[k]) {
      systemsMm_[k] = v;
    } else if ((*systemsMm_[k] - v).cwiseAbs().maxCoeff() > 1e-9) {
      // The program changed this coordinate system (G10 L2/L20): the controller must too.
      text += "G10 L2 P" + std::to_string(k + 1) + " X";
      appendFixed(text, v.x() / unit, 6);
      text += " Y";
      appendFixed(text, v.y() / unit, 6);
      text += " Z";
      appendFixed(text, v.z() / unit, 6);
      systemsMm_[k] = v;
    }
    if (system_ != static_cast<int>(k)) {
      if (!text.empty()) text += '\n';
      text += coordinateSystemName(static_cast<int>(k));
      system_ = static_cast<int>(k);
    }
    g5xMm_ = v;
    if (!text.empty()) emit(text);
  } else if (name == "SET_G92_OFFSET") {
    g92Mm_ = Vec3(number_(0) * unit, number_(1) * unit, number_(2) * unit);
    if (!g92StartMm_) g92StartMm_ = g92Mm_;
  } else if (name == "SET_XY_ROTATION") {
    rotationDeg_ = number_(0);
  } else if (name == "USE_TOOL_LENGTH_OFFSET") {
    toolMm_ = Vec3(number_(0) * unit, number_(1) * unit, number_(2) * unit);
    for (int i = 3; i < args.count; ++i) {
      if (number_(i) != 0.0) {
        fail(number, args.offsets[static_cast<std::size_t>(i)],
             "USE_TOOL_LENGTH_OFFSET: offsets of rotary or UVW axes are not supported");
      }
    }
    if (toolMm_.isZero()) {
      emit("G49");
    } else {
      text = "G43.1 X";
      appendLength(text, toolMm_.x());
      text += " Y";
      appendLength(text, toolMm_.y());
      text += " Z";
      appendLength(text, toolMm_.z());
      emit(text);
    }
  } else if (name == "SELECT_PLANE") {
    const std::string_view p = args.count > 0 ? args.items[0] : std::string_view();
    if (p == "CANON_PLANE_XY") {
      plane_ = 0;
    } else if (p == "CANON_PLANE_XZ") {
      plane_ = 1;
    } else if (p == "CANON_PLANE_YZ") {
      plane_ = 2;
    } else {
      fail(number, args.rawOffset, "SELECT_PLANE: the UVW planes are not supported");
    }
  } else if (name == "SET_FEED_RATE") {
    text = "F";
    appendFixed(text, number_(0), 6);
    emit(text);
  } else if (name == "SET_FEED_MODE") {
    const double mode = number_(args.count > 1 ? 1 : 0);
    inverseTime_ = mode == 1.0;
    if (mode == 0.0) emit("G94");
    if (mode == 2.0) emit("G95");
  } else if (name == "SET_SPINDLE_SPEED") {
    text = "S";
    appendFixed(text, number_(args.count > 1 ? 1 : 0), 6);
    emit(text);
  } else if (name == "START_SPINDLE_CLOCKWISE") {
    emit("M3");
  } else if (name == "START_SPINDLE_COUNTERCLOCKWISE") {
    emit("M4");
  } else if (name == "STOP_SPINDLE_TURNING") {
    emit("M5");
  } else if (name == "SELECT_TOOL") {
    emit("T" + toolNumber(0));
  } else if (name == "CHANGE_TOOL") {
    emit("M6");
  } else if (name == "CHANGE_TOOL_NUMBER") {
    emit("M61 Q" + toolNumber(0));
  } else if (name == "MIST_ON" || name == "FLOOD_ON" || name == "MIST_OFF" || name == "FLOOD_OFF") {
    if (name == "MIST_ON") mist_ = true;
    if (name == "FLOOD_ON") flood_ = true;
    if (name == "MIST_OFF") mist_ = false;
    if (name == "FLOOD_OFF") flood_ = false;
    if (name == "MIST_ON") {
      emit("M7");
    } else if (name == "FLOOD_ON") {
      emit("M8");
    } else {
      // M9 turns both off; the one still on is turned on again on a line of its own (LinuxCNC
      // refuses M9 with M7 or M8 on one line: one modal group).
      const std::string next = std::string(eol) + (mist_ ? "M7" : "M8");
      emit("M9" + (mist_ || flood_ ? next : std::string()));
    }
  } else if (name == "DWELL") {
    text = "G4 P";
    appendFixed(text, number_(0), 6);
    emit(text);
  } else if (name == "COMMENT") {
    emit("(" + commentSafe(quotedText(args.raw)) + ")");
  } else if (name == "MESSAGE") {
    emit("(MSG," + commentSafe(quotedText(args.raw)) + ")");
  } else if (name == "PROGRAM_STOP") {
    emit("M0");
  } else if (name == "OPTIONAL_PROGRAM_STOP") {
    emit("M1");
  } else if (name == "PALLET_SHUTTLE") {
    emit("M60");
  } else if (name == "PROGRAM_END") {
    emit("M2");
    programEnd_ = true;
  } else if (name == "SET_MOTION_CONTROL_MODE") {
    const std::string_view mode = args.count > 0 ? args.items[0] : std::string_view();
    if (mode == "CANON_EXACT_STOP") {
      emit("G61.1");
    } else if (mode == "CANON_EXACT_PATH") {
      emit("G61");
    } else {
      const double tolerance = args.count > 1 ? number_(1) : 0.0;
      text = "G64";
      if (tolerance > 0.0) {
        text += " P";
        appendFixed(text, tolerance, 6);
      }
      emit(text);
    }
  } else if (name == "STRAIGHT_PROBE") {
    fail(number, nameOffset,
         "probing moves (G38.x) end where the probe trips: they cannot be compensated offline");
  } else if (name == "RIGID_TAP") {
    fail(number, nameOffset, "rigid tapping (G33.1) is not supported");
  } else if (name == "NURBS_FEED" || name.rfind("NURBS", 0) == 0 || name.rfind("SPLINE", 0) == 0) {
    fail(number, nameOffset, std::string(name) + ": splines (G5.x) are not supported");
  } else if (name == "START_SPEED_FEED_SYNC" || name == "START_SPEED_FEED_SYNCH") {
    synchronized_ = true;
    ++ignored_[std::string(name)];
  } else if (name == "STOP_SPEED_FEED_SYNCH" || name == "STOP_SPEED_FEED_SYNC") {
    synchronized_ = false;
    ++ignored_[std::string(name)];
  } else if (name == "SET_FEED_REFERENCE" || name == "ON_RESET" ||
             name == "SET_NAIVECAM_TOLERANCE" || name == "SET_TRAVERSE_RATE" ||
             name == "TURN_PROBE_ON" || name == "TURN_PROBE_OFF" || name.rfind("LOG", 0) == 0 ||
             name == "FINISH" || name == "SET_SPINDLE_MODE" || name == "START_CHANGE" ||
             name.rfind("ENABLE_", 0) == 0 || name.rfind("DISABLE_", 0) == 0 ||
             name == "ORIENT_SPINDLE" || name == "WAIT_SPINDLE_ORIENT_COMPLETE" ||
             name.rfind("SPINDLE.", 0) == 0 || name == "SET_CUTTER_RADIUS_COMPENSATION" ||
             name == "START_CUTTER_RADIUS_COMPENSATION" ||
             name == "STOP_CUTTER_RADIUS_COMPENSATION" || name == "CLAMP_AXIS" ||
             name == "UNCLAMP_AXIS" || name == "SET_BLOCK_DELETE" || name == "SYSTEM" ||
             name == "SET_ORIGIN_OFFSETS") {
    ++ignored_[std::string(name)];
  } else {
    fail(number, nameOffset, "unknown canonical command " + std::string(name));
  }
  chunk.lines.push_back(work);
}

double CanonReader::argument(const Arguments& args, std::string_view name, long number,
                             int index) const {
  if (index >= args.count) {
    fail(number, args.rawOffset + args.raw.size(),
         std::string(name) + ": expected at least " + std::to_string(index + 1) + " arguments");
  }
  double v = 0.0;
  if (!toNumber(args.items[static_cast<std::size_t>(index)], v)) {
    // What was found is shown escaped and shortened, as every message that echoes input.
    fail(number, args.offsets[static_cast<std::size_t>(index)],
         std::string(name) + ": expected a number, got " +
             config::quoted(args.items[static_cast<std::size_t>(index)]));
  }
  return v;
}

void CanonReader::motion(const Arguments& args, std::string_view name, long number,
                         std::string_view line, std::string_view eol, Chunk& chunk) {
  const bool arc = name == "ARC_FEED";
  const int first = arc ? 6 : 3;
  const auto value = [&](int index) { return argument(args, name, number, index); };
  for (int i = first; i < std::min(args.count, first + 3); ++i) {
    if (value(i) != 0.0) {
      fail(number, args.offsets[static_cast<std::size_t>(i)],
           std::string(name) + ": rotary axes (A, B, C) are not supported");
    }
  }
  if (rotationDeg_ != 0.0) {
    fail(number, 0, "coordinate system rotation (SET_XY_ROTATION) is not supported");
  }
  if (synchronized_ && name != "STRAIGHT_TRAVERSE") {
    fail(number, 0, "spindle-synchronized motion (G33, G76) is not supported");
  }
  if (inverseTime_ && name != "STRAIGHT_TRAVERSE") {
    fail(number, 0,
         "inverse-time feed (G93) is not supported: splitting a move would change its time");
  }
  const double unit = mmPerUnit(units_);
  const Vec3 shift = g5xMm_ + g92Mm_ + toolMm_;
  MotionWork m;
  m.line = number;
  m.startKnown = position_.allKnown();
  m.endKnown = true;
  m.before = printMode();
  m.after = m.before;
  m.move.startMm = position_.machineMm;
  if (!arc) {
    m.move.kind = name == "STRAIGHT_TRAVERSE" ? MoveKind::Rapid : MoveKind::Line;
    for (int k = 0; k < 3; ++k) m.move.endMm[k] = value(k) * unit + shift[k];
  } else {
    static constexpr int kAxes[3][3] = {{0, 1, 2}, {2, 0, 1}, {1, 2, 0}};
    const int a1 = kAxes[plane_][0], a2 = kAxes[plane_][1], an = kAxes[plane_][2];
    m.move.kind = MoveKind::Arc;
    m.move.endMm[a1] = value(0) * unit + shift[a1];
    m.move.endMm[a2] = value(1) * unit + shift[a2];
    m.move.endMm[an] = value(5) * unit + shift[an];
    const double rotation = value(4);
    if (rotation == 0.0 || rotation != std::floor(rotation) || std::abs(rotation) > kMaxArcTurns) {
      fail(number, args.offsets[4],
           "ARC_FEED: rotation must be a non-zero whole number of at most " +
               std::to_string(kMaxArcTurns) + " turns");
    }
    if (m.startKnown) {
      m.move.arc = makeArc(plane_, m.move.startMm, m.move.endMm, value(2) * unit + shift[a1],
                           value(3) * unit + shift[a2], static_cast<int>(rotation));
    }
  }
  position_.machineMm = m.move.endMm;
  position_.known = 7;
  if (!m.startKnown && arc) {
    fail(number, 0, "an arc as the first move: its start is unknown (give --start)");
  }
  LineWork work;
  work.input = line;
  work.eol = eol;
  work.action = LineAction::Motion;
  work.motion = static_cast<std::uint32_t>(chunk.motions.size());
  chunk.motions.push_back(m);
  chunk.lines.push_back(work);
}

}  // namespace volcomp::nc
