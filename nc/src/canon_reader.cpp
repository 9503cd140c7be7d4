#include "volcomp/nc/canon_reader.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iterator>

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

// Parses "  12 N..... NAME(args)"; returns false when the line is not in that
// shape.
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

// One canonical call being read: what its handler needs to know and to give
// back.
struct CanonReader::Call {
  Call(long n, std::string_view l, std::string_view e, Chunk& c, LineWork& w)
      : number(n), line(l), eol(e), chunk(c), work(w) {}

  std::string_view name;
  std::size_t nameOffset = 0;
  long number = 0;
  std::string_view line;
  std::string_view eol;
  Arguments args;
  Chunk& chunk;
  LineWork& work;
  const char* text = nullptr;  // the table entry's fixed text
  bool motion = false;         // the handler queued a motion line itself
};

// The handlers of the canonical calls, one per call or group of calls that do
// the same.
struct CanonReader::Commands {
  using Handler = void (*)(CanonReader&, Call&);
  struct Entry {
    std::string_view name;
    Handler handler;
    const char* text = nullptr;
  };

  static double number(const CanonReader& r, const Call& c, int index) {
    return r.argument(c.args, c.name, c.number, index);
  }
  static std::string toolNumber(const CanonReader& r, const Call& c, int index) {
    const double tool = number(r, c, index);
    if (!isToolNumber(tool)) {
      r.fail(c.number, c.args.offsets[static_cast<std::size_t>(index)],
             std::string(c.name) + ": tool number must be a whole number in 0..2147483647");
    }
    return std::to_string(static_cast<long>(tool));
  }
  static void emit(Call& c, const std::string& text) {
    c.work.action = LineAction::Text;
    c.work.text = c.chunk.store(text);
  }

  static void motion(CanonReader& r, Call& c) {
    r.motion(c.args, c.name, c.number, c.line, c.eol, c.chunk);
    c.motion = true;
  }
  static void fixedText(CanonReader&, Call& c) { emit(c, c.text); }
  static void refuse(CanonReader& r, Call& c) { r.fail(c.number, c.nameOffset, c.text); }
  static void ignore(CanonReader& r, Call& c) { ++r.ignored_[std::string(c.name)]; }

  static void useLengthUnits(CanonReader& r, Call& c) {
    const std::string_view u = c.args.count > 0 ? c.args.items[0] : std::string_view();
    if (u != "CANON_UNITS_MM" && u != "CANON_UNITS_INCHES") {
      r.fail(c.number, c.args.rawOffset,
             "USE_LENGTH_UNITS: expected CANON_UNITS_MM or CANON_UNITS_INCHES");
    }
    const LengthUnit next = u == "CANON_UNITS_MM" ? LengthUnit::Mm : LengthUnit::Inch;
    if (!r.unitsWritten_ || next != r.units_) emit(c, next == LengthUnit::Mm ? "G21" : "G20");
    r.units_ = next;
    r.unitsWritten_ = true;
  }

  static void setG5xOffset(CanonReader& r, Call& c) {
    const double unit = mmPerUnit(r.units_);
    const double index = number(r, c, 0);
    if (index < 1 || index > 9 || index != std::floor(index)) {
      r.fail(c.number, c.args.offsets[0], "SET_G5X_OFFSET: coordinate system must be 1 .. 9");
    }
    const auto k = static_cast<std::size_t>(index) - 1;
    const Vec3 v(number(r, c, 1) * unit, number(r, c, 2) * unit, number(r, c, 3) * unit);
    std::string text;
    if (!r.systemsMm_[k]) {
      r.systemsMm_[k] = v;
    } else if ((*r.systemsMm_[k] - v).cwiseAbs().maxCoeff() > 1e-9) {
      // The program changed this coordinate system (G10 L2/L20): the controller
      // must too.
      text += "G10 L2 P" + std::to_string(k + 1) + " X";
      appendFixed(text, v.x() / unit, 6);
      text += " Y";
      appendFixed(text, v.y() / unit, 6);
      text += " Z";
      appendFixed(text, v.z() / unit, 6);
      r.systemsMm_[k] = v;
    }
    if (r.system_ != static_cast<int>(k)) {
      if (!text.empty()) text += '\n';
      text += coordinateSystemName(static_cast<int>(k));
      r.system_ = static_cast<int>(k);
    }
    r.g5xMm_ = v;
    if (!text.empty()) emit(c, text);
  }

  static void setG92Offset(CanonReader& r, Call& c) {
    const double unit = mmPerUnit(r.units_);
    r.g92Mm_ = Vec3(number(r, c, 0) * unit, number(r, c, 1) * unit, number(r, c, 2) * unit);
    if (!r.g92StartMm_) r.g92StartMm_ = r.g92Mm_;
  }

  static void setXyRotation(CanonReader& r, Call& c) { r.rotationDeg_ = number(r, c, 0); }

  static void useToolLengthOffset(CanonReader& r, Call& c) {
    const double unit = mmPerUnit(r.units_);
    r.toolMm_ = Vec3(number(r, c, 0) * unit, number(r, c, 1) * unit, number(r, c, 2) * unit);
    for (int i = 3; i < c.args.count; ++i) {
      if (number(r, c, i) != 0.0) {
        r.fail(c.number, c.args.offsets[static_cast<std::size_t>(i)],
               "USE_TOOL_LENGTH_OFFSET: offsets of rotary or UVW axes are not "
               "supported");
      }
    }
    if (r.toolMm_.isZero()) {
      emit(c, "G49");
      return;
    }
    std::string text = "G43.1 X";
    r.appendLength(text, r.toolMm_.x());
    text += " Y";
    r.appendLength(text, r.toolMm_.y());
    text += " Z";
    r.appendLength(text, r.toolMm_.z());
    emit(c, text);
  }

  static void selectPlane(CanonReader& r, Call& c) {
    const std::string_view p = c.args.count > 0 ? c.args.items[0] : std::string_view();
    if (p == "CANON_PLANE_XY") {
      r.plane_ = 0;
    } else if (p == "CANON_PLANE_XZ") {
      r.plane_ = 1;
    } else if (p == "CANON_PLANE_YZ") {
      r.plane_ = 2;
    } else {
      r.fail(c.number, c.args.rawOffset, "SELECT_PLANE: the UVW planes are not supported");
    }
  }

  // F, S and G4 P: the letter and the call's value as it was given.
  static void fixedTextAndNumber(CanonReader& r, Call& c, int index) {
    std::string text = c.text;
    appendFixed(text, number(r, c, index), 6);
    emit(c, text);
  }
  static void setFeedRate(CanonReader& r, Call& c) { fixedTextAndNumber(r, c, 0); }
  static void dwell(CanonReader& r, Call& c) { fixedTextAndNumber(r, c, 0); }
  // With two arguments the first is the spindle.
  static void setSpindleSpeed(CanonReader& r, Call& c) {
    fixedTextAndNumber(r, c, c.args.count > 1 ? 1 : 0);
  }

  static void setFeedMode(CanonReader& r, Call& c) {
    const double mode = number(r, c, c.args.count > 1 ? 1 : 0);
    r.inverseTime_ = mode == 1.0;
    if (mode == 0.0) emit(c, "G94");
    if (mode == 2.0) emit(c, "G95");
  }

  static void selectTool(CanonReader& r, Call& c) { emit(c, "T" + toolNumber(r, c, 0)); }
  static void changeToolNumber(CanonReader& r, Call& c) { emit(c, "M61 Q" + toolNumber(r, c, 0)); }

  static void coolant(CanonReader& r, Call& c) {
    if (c.name == "MIST_ON") r.mist_ = true;
    if (c.name == "FLOOD_ON") r.flood_ = true;
    if (c.name == "MIST_OFF") r.mist_ = false;
    if (c.name == "FLOOD_OFF") r.flood_ = false;
    if (c.name == "MIST_ON") {
      emit(c, "M7");
    } else if (c.name == "FLOOD_ON") {
      emit(c, "M8");
    } else {
      // M9 turns both off; the one still on is turned on again on a line of its
      // own (LinuxCNC refuses M9 with M7 or M8 on one line: one modal group).
      const std::string next = std::string(c.eol) + (r.mist_ ? "M7" : "M8");
      emit(c, "M9" + (r.mist_ || r.flood_ ? next : std::string()));
    }
  }

  static void comment(CanonReader&, Call& c) {
    emit(c, "(" + commentSafe(quotedText(c.args.raw)) + ")");
  }
  static void message(CanonReader&, Call& c) {
    emit(c, "(MSG," + commentSafe(quotedText(c.args.raw)) + ")");
  }

  static void programEnd(CanonReader& r, Call& c) {
    emit(c, "M2");
    r.programEnd_ = true;
  }

  static void setMotionControlMode(CanonReader& r, Call& c) {
    const std::string_view mode = c.args.count > 0 ? c.args.items[0] : std::string_view();
    if (mode == "CANON_EXACT_STOP") {
      emit(c, "G61.1");
    } else if (mode == "CANON_EXACT_PATH") {
      emit(c, "G61");
    } else {
      const double tolerance = c.args.count > 1 ? number(r, c, 1) : 0.0;
      std::string text = "G64";
      if (tolerance > 0.0) {
        text += " P";
        appendFixed(text, tolerance, 6);
      }
      emit(c, text);
    }
  }

  static void startSync(CanonReader& r, Call& c) {
    r.synchronized_ = true;
    ignore(r, c);
  }
  static void stopSync(CanonReader& r, Call& c) {
    r.synchronized_ = false;
    ignore(r, c);
  }

  static const Entry* find(std::string_view name);
};

const CanonReader::Commands::Entry* CanonReader::Commands::find(std::string_view name) {
  // Sorted by name: looked up by binary search for every line.
  static constexpr Entry kTable[] = {
      {"ARC_FEED", motion},
      {"CHANGE_TOOL", fixedText, "M6"},
      {"CHANGE_TOOL_NUMBER", changeToolNumber},
      {"CLAMP_AXIS", ignore},
      {"COMMENT", comment},
      {"DWELL", dwell, "G4 P"},
      {"FINISH", ignore},
      {"FLOOD_OFF", coolant},
      {"FLOOD_ON", coolant},
      {"MESSAGE", message},
      {"MIST_OFF", coolant},
      {"MIST_ON", coolant},
      {"ON_RESET", ignore},
      {"OPTIONAL_PROGRAM_STOP", fixedText, "M1"},
      {"ORIENT_SPINDLE", ignore},
      {"PALLET_SHUTTLE", fixedText, "M60"},
      {"PROGRAM_END", programEnd},
      {"PROGRAM_STOP", fixedText, "M0"},
      {"RIGID_TAP", refuse, "rigid tapping (G33.1) is not supported"},
      {"SELECT_PLANE", selectPlane},
      {"SELECT_TOOL", selectTool},
      {"SET_BLOCK_DELETE", ignore},
      {"SET_CUTTER_RADIUS_COMPENSATION", ignore},
      {"SET_FEED_MODE", setFeedMode},
      {"SET_FEED_RATE", setFeedRate, "F"},
      {"SET_FEED_REFERENCE", ignore},
      {"SET_G5X_OFFSET", setG5xOffset},
      {"SET_G92_OFFSET", setG92Offset},
      {"SET_MOTION_CONTROL_MODE", setMotionControlMode},
      {"SET_NAIVECAM_TOLERANCE", ignore},
      {"SET_ORIGIN_OFFSETS", ignore},
      {"SET_SPINDLE_MODE", ignore},
      {"SET_SPINDLE_SPEED", setSpindleSpeed, "S"},
      {"SET_TRAVERSE_RATE", ignore},
      {"SET_XY_ROTATION", setXyRotation},
      {"START_CHANGE", ignore},
      {"START_CUTTER_RADIUS_COMPENSATION", ignore},
      {"START_SPEED_FEED_SYNC", startSync},
      {"START_SPEED_FEED_SYNCH", startSync},
      {"START_SPINDLE_CLOCKWISE", fixedText, "M3"},
      {"START_SPINDLE_COUNTERCLOCKWISE", fixedText, "M4"},
      {"STOP_CUTTER_RADIUS_COMPENSATION", ignore},
      {"STOP_SPEED_FEED_SYNC", stopSync},
      {"STOP_SPEED_FEED_SYNCH", stopSync},
      {"STOP_SPINDLE_TURNING", fixedText, "M5"},
      {"STRAIGHT_FEED", motion},
      {"STRAIGHT_PROBE", refuse,
       "probing moves (G38.x) end where the probe trips: they cannot be "
       "compensated offline"},
      {"STRAIGHT_TRAVERSE", motion},
      {"SYSTEM", ignore},
      {"TURN_PROBE_OFF", ignore},
      {"TURN_PROBE_ON", ignore},
      {"UNCLAMP_AXIS", ignore},
      {"USE_LENGTH_UNITS", useLengthUnits},
      {"USE_TOOL_LENGTH_OFFSET", useToolLengthOffset},
      {"WAIT_SPINDLE_ORIENT_COMPLETE", ignore},
  };

  static_assert(std::ranges::is_sorted(kTable, {}, &Entry::name));
  const auto it = std::ranges::lower_bound(kTable, name, {}, &Entry::name);
  return it != std::end(kTable) && it->name == name ? it : nullptr;
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
  Call c(number, line, eol, chunk, work);
  if (!splitCanonical(line, c.name, c.nameOffset, c.args.raw, c.args.rawOffset)) {
    fail(number, 0,
         "not a canonical command line (expected the output of rs274 -g, such "
         "as \"  12 N..... "
         "STRAIGHT_FEED(1.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)\")");
  }
  // Free text (comments, messages, log lines, shell commands) is not split into
  // arguments.
  if (c.name != "COMMENT" && c.name != "MESSAGE" && c.name.rfind("LOG", 0) != 0 &&
      c.name != "SYSTEM") {
    splitArguments(c.args, number);
  }
  if (const Commands::Entry* entry = Commands::find(c.name)) {
    c.text = entry->text;
    entry->handler(*this, c);
    if (c.motion) return;
  } else if (c.name.rfind("NURBS", 0) == 0 || c.name.rfind("SPLINE", 0) == 0) {
    fail(number, c.nameOffset, std::string(c.name) + ": splines (G5.x) are not supported");
  } else if (c.name.rfind("LOG", 0) == 0 || c.name.rfind("ENABLE_", 0) == 0 ||
             c.name.rfind("DISABLE_", 0) == 0 || c.name.rfind("SPINDLE.", 0) == 0) {
    Commands::ignore(*this, c);
  } else {
    fail(number, c.nameOffset, "unknown canonical command " + std::string(c.name));
  }
  chunk.lines.push_back(work);
}

void CanonReader::splitArguments(Arguments& args, long number) const {
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

double CanonReader::argument(const Arguments& args, std::string_view name, long number,
                             int index) const {
  if (index >= args.count) {
    fail(number, args.rawOffset + args.raw.size(),
         std::string(name) + ": expected at least " + std::to_string(index + 1) + " arguments");
  }
  double v = 0.0;
  if (!toNumber(args.items[static_cast<std::size_t>(index)], v)) {
    // What was found is shown escaped and shortened, as every message that
    // echoes input.
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
         "inverse-time feed (G93) is not supported: splitting a move would "
         "change its time");
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
