#include "volcomp/nc/ngc_interpreter.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "volcomp/nc/numbers.hpp"

namespace volcomp::nc {
namespace {

constexpr const char* kNotAToolNumber = "tool number must be a whole number in 0..2147483647";

// Modal groups of the G codes we know (LinuxCNC numbering); -1 = not a G code of the subset.
enum Group : int {
  kNonModal = 0,
  kMotion = 1,
  kPlane = 2,
  kDistance = 3,
  kArcDistance = 4,
  kFeedMode = 5,
  kUnits = 6,
  kCutterComp = 7,
  kToolLength = 8,
  kReturnMode = 10,
  kCoordinateSystem = 12,
  kPathControl = 13,
  kSpindleMode = 14,
  kGroups = 15,
};

int groupOf(int code) {
  switch (code) {
    case 0:
    case 10:
    case 20:
    case 30:
    case 800:
      return kMotion;
    case 40:
    case 530:
      return kNonModal;
    case 170:
    case 180:
    case 190:
      return kPlane;
    case 900:
    case 910:
      return kDistance;
    case 901:
    case 911:
      return kArcDistance;
    case 940:
    case 950:
      return kFeedMode;
    case 200:
    case 210:
      return kUnits;
    case 400:
      return kCutterComp;
    case 430:
    case 431:
    case 490:
      return kToolLength;
    case 980:
    case 990:
      return kReturnMode;
    case 540:
    case 550:
    case 560:
    case 570:
    case 580:
    case 590:
    case 591:
    case 592:
    case 593:
      return kCoordinateSystem;
    case 610:
    case 611:
    case 640:
      return kPathControl;
    case 960:
    case 970:
      return kSpindleMode;
    default:
      return -1;
  }
}

std::string gName(int code) {
  std::string s = "G" + std::to_string(code / 10);
  if (code % 10 != 0) s += "." + std::to_string(code % 10);
  return s;
}

// Why a G code outside the subset is rejected.
std::string unsupportedG(int code) {
  const std::string g = gName(code);
  if (code == 410 || code == 420 || code == 411 || code == 421) {
    return g +
           " (cutter radius compensation) is not supported: compensate the tool radius in the "
           "CAM system, or flatten the program with rs274 -g";
  }
  if (code == 730 || code == 760 || (code >= 810 && code <= 890)) {
    return g + " (canned cycle) is not supported; flatten the program with rs274 -g";
  }
  if (code >= 920 && code <= 923) {
    return g +
           " (G92 axis offsets set by the program) is not supported; set the offset in the "
           "work offsets instead";
  }
  if (code == 100) return g + " (offsets set by the program) is not supported";
  if (code == 280 || code == 281 || code == 300 || code == 301) {
    return g + " (move to a stored position) is not supported";
  }
  if (code >= 382 && code <= 385) return g + " (probing) cannot be compensated offline";
  if (code == 330 || code == 331) return g + " (spindle-synchronized motion) is not supported";
  if (code == 50 || code == 51 || code == 52 || code == 53)
    return g + " (splines) is not supported";
  if (code == 930)
    return g + " (inverse time feed) is not supported: splitting a move would change its time";
  if (code == 70 || code == 80) return g + " (lathe diameter/radius mode) is not supported";
  if (code == 432) return g + " (additional tool offset) is not supported";
  if (code == 171 || code == 181 || code == 191) return g + " (UVW plane) is not supported";
  return g + " is not in the supported subset (see docs/nc.md)";
}

bool supportedM(int m) {
  return (m >= 0 && m <= 9) || m == 19 || m == 30 || (m >= 48 && m <= 53) || m == 60 ||
         (m >= 61 && m <= 68) || (m >= 100 && m <= 199);
}

bool isStopM(int m) {
  return m == 0 || m == 1 || m == 2 || m == 30 || m == 60;
}

bool failAt(LineError& error, const Word& w, std::string message) {
  error.column = static_cast<int>(w.begin) + 1;
  error.message = std::move(message);
  return false;
}

// LinuxCNC's arc tolerances (CENTER_ARC_RADIUS_TOLERANCE_*, SPIRAL_RELATIVE_TOLERANCE,
// RADIUS_TOLERANCE_*), in program units.
struct ArcTolerances {
  double spiralAbs;
  double spiralRel = 0.001;
  double radius;
};

ArcTolerances arcTolerances(LengthUnit units) {
  return units == LengthUnit::Inch ? ArcTolerances{0.002, 0.001, 0.00005}
                                   : ArcTolerances{0.02, 0.001, 0.00127};
}

// A point in the plane of an arc: its coordinates along the plane's first and second axis.
struct InPlane {
  double first = 0.0;
  double second = 0.0;
};

// The centre of an R arc, as LinuxCNC's arc_data_r computes it.
bool centreFromRadius(const Word& r, bool clockwise, const ArcTolerances& tol, InPlane s, InPlane e,
                      InPlane& centre, LineError& error) {
  const double s1 = s.first, s2 = s.second;
  const double e1 = e.first, e2 = e.second;
  if (e1 == s1 && e2 == s2) {
    return failAt(error, r, "an R arc cannot end where it starts (use I, J, K for a full circle)");
  }
  const double absRadius = std::abs(r.value);
  const double m1 = (e1 + s1) / 2.0, m2 = (e2 + s2) / 2.0;
  double halfLength = std::hypot(m1 - e1, m2 - e2);
  if (halfLength - absRadius > tol.radius) {
    return failAt(error, r, "arc radius too small to reach the end point");
  }
  if (halfLength / absRadius > 1.0 - 1e-12) halfLength = absRadius;
  const double theta = ((clockwise && r.value > 0) || (!clockwise && r.value < 0))
                           ? std::atan2(e2 - s2, e1 - s1) - std::numbers::pi / 2
                           : std::atan2(e2 - s2, e1 - s1) + std::numbers::pi / 2;
  const double turn2 = std::asin(halfLength / absRadius);
  const double offset = absRadius * std::cos(turn2);
  centre.first = m1 + offset * std::cos(theta);
  centre.second = m2 + offset * std::sin(theta);
  return true;
}

// The centre of an IJK arc (from the start in G91.1, absolute in G90.1); start and end radius
// may differ within LinuxCNC's spiral tolerance.
bool centreFromOffsets(const Word* i1, const Word* i2, bool incremental, LengthUnit units,
                       const ArcTolerances& tol, InPlane s, InPlane e, InPlane& centre,
                       LineError& error) {
  const double v1 = i1 ? i1->value : 0.0;
  const double v2 = i2 ? i2->value : 0.0;
  centre.first = incremental ? s.first + v1 : v1;
  centre.second = incremental ? s.second + v2 : v2;
  const double r1 = std::hypot(centre.first - s.first, centre.second - s.second);
  const double r2 = std::hypot(centre.first - e.first, centre.second - e.second);
  const Word& at = i1 ? *i1 : *i2;
  if (r1 < tol.radius || r2 < tol.radius) return failAt(error, at, "zero-radius arc");
  const double absErr = std::abs(r1 - r2);
  if (absErr > tol.spiralAbs && absErr / std::max(r1, r2) > tol.spiralRel) {
    return failAt(error, at,
                  "radius to the end of the arc differs from the radius to the start by " +
                      std::to_string(absErr) + (units == LengthUnit::Inch ? " in" : " mm"));
  }
  return true;
}

}  // namespace

NgcInterpreter::NgcInterpreter(const WorkOffsets& offsets, const ToolTable& tools,
                               std::optional<Vec3> startMm, Decimals decimals)
    : offsets_(offsets), tools_(tools), decimals_(decimals), system_(offsets.active) {
  if (startMm) {
    position_.machineMm = *startMm;
    position_.known = 7;
  }
}

Frame NgcInterpreter::frame() const noexcept {
  Frame f;
  f.unitMm = mmPerUnit(units_);
  f.shiftMm =
      offsets_.systemsMm[static_cast<std::size_t>(system_)] + offsets_.g92Mm + toolOffsetMm_;
  return f;
}

PrintMode NgcInterpreter::printMode() const noexcept {
  PrintMode m;
  m.frame = frame();
  m.incremental = incremental_;
  m.decimals = units_ == LengthUnit::Inch ? decimals_.inch : decimals_.mm;
  return m;
}

// The words of one line, sorted by what they are: G codes by modal group, M codes in order,
// every other letter by its index in the line.
struct NgcInterpreter::LineWords {
  const Block* block = nullptr;
  std::array<int, kGroups> groupCode{};
  std::array<int, kGroups> groupWord{};
  bool g53 = false;
  int g4 = -1;
  std::array<int, 26> letterWord{};
  int mCount = 0;
  std::array<int, 8> mCodes{};
  std::array<int, 8> mWords{};
  int fWord = -1;

  explicit LineWords(const Block& b) : block(&b) {
    groupCode.fill(-1);
    letterWord.fill(-1);
  }
  const Word& at(int i) const { return block->words[static_cast<std::size_t>(i)]; }
  int index(char l) const { return letterWord[static_cast<std::size_t>(l - 'A')]; }
  const Word* word(char l) const {
    const int i = index(l);
    return i < 0 ? nullptr : &at(i);
  }
  int code(int group) const { return groupCode[static_cast<std::size_t>(group)]; }
  const Word& codeWord(int group) const { return at(groupWord[static_cast<std::size_t>(group)]); }
  bool ends() const {
    for (int k = 0; k < mCount; ++k) {
      if (mCodes[static_cast<std::size_t>(k)] == 2 || mCodes[static_cast<std::size_t>(k)] == 30) {
        return true;
      }
    }
    return false;
  }
  // The first of I, J, K, R on the line (for a message about arc words without an arc).
  const Word* firstArcWord() const {
    return word('I') ? word('I') : word('J') ? word('J') : word('K') ? word('K') : word('R');
  }
};

bool NgcInterpreter::execute(const Block& block, NgcLine& out, LineError& error) {
  out = NgcLine{};
  out.before = printMode();
  out.after = out.before;
  if (ended_ || block.percent || block.wordCount == 0) return true;

  LineWords words(block);
  if (!sortWords(words, out, error)) return false;
  out.feedWord = words.fWord;

  // In LinuxCNC's order of execution: feed mode, F, T, M6 / M61, G4, plane, units, cutter
  // compensation, tool length offset, coordinate system, path control, distance modes, motion,
  // stop codes.
  if (!applyFeedAndTools(words, error)) return false;
  if (words.g4 >= 0 && words.word('P') == nullptr) {
    return failAt(error, words.at(words.g4), "G4 needs P (seconds)");
  }
  if (const int code = words.code(kPlane); code >= 0) {
    plane_ = code == 170 ? 0 : code == 180 ? 1 : 2;
  }
  if (const int code = words.code(kUnits); code >= 0) {
    units_ = code == 200 ? LengthUnit::Inch : LengthUnit::Mm;
  }
  bool axisWordsUsed = false;
  if (!applyToolLength(words, axisWordsUsed, error)) return false;
  if (!applyCoordinateSystem(words, error)) return false;
  if (const int code = words.code(kDistance); code >= 0) incremental_ = code == 910;
  if (const int code = words.code(kArcDistance); code >= 0) arcIncremental_ = code == 911;
  out.after = printMode();
  out.after.machineCoordinates = words.g53;
  if (offsets_.rotationDeg[static_cast<std::size_t>(system_)] != 0.0) {
    error.column = 1;
    error.message = std::string(coordinateSystemName(system_)) +
                    " is rotated (G10 L2 R in the work offsets): coordinate system rotation is "
                    "not supported";
    return false;
  }
  return executeMotion(words, axisWordsUsed, out, error);
}

bool NgcInterpreter::sortWords(LineWords& words, NgcLine& out, LineError& error) const {
  const Block& block = *words.block;
  for (int i = 0; i < block.wordCount; ++i) {
    const Word& w = words.at(i);
    if (w.letter == 'G') {
      const double tenths = w.value * 10.0;
      const auto code = static_cast<int>(std::lround(tenths));
      if (std::abs(tenths - code) > 1e-6 || code < 0) {
        return failAt(
            error, w,
            "not a G code: G" + std::string(block.text.substr(w.begin + 1, w.end - w.begin - 1)));
      }
      const int group = groupOf(code);
      if (group < 0) return failAt(error, w, unsupportedG(code));
      if (code == 40) {
        words.g4 = i;
        continue;
      }
      if (code == 530) {
        words.g53 = true;
        out.dropWords |= 1ull << i;
        continue;
      }
      if (words.code(group) >= 0) {
        return failAt(error, w,
                      gName(code) + " and " + gName(words.code(group)) +
                          " are in the same modal group: only one per line");
      }
      words.groupCode[static_cast<std::size_t>(group)] = code;
      words.groupWord[static_cast<std::size_t>(group)] = i;
      continue;
    }
    if (w.letter == 'M') {
      const auto m = static_cast<int>(std::lround(w.value));
      if (w.value != m || m < 0) return failAt(error, w, "not an M code");
      if (m >= 70 && m <= 73) {
        return failAt(error, w,
                      "M" + std::to_string(m) +
                          " (save/restore modal state) is not supported; flatten the program "
                          "with rs274 -g");
      }
      if (!supportedM(m)) {
        return failAt(error, w, "M" + std::to_string(m) + " is not in the supported subset");
      }
      if (words.mCount == static_cast<int>(words.mCodes.size())) {
        return failAt(error, w, "too many M codes");
      }
      words.mCodes[static_cast<std::size_t>(words.mCount)] = m;
      words.mWords[static_cast<std::size_t>(words.mCount++)] = i;
      if (isStopM(m)) out.stopWords |= 1ull << i;
      continue;
    }
    const int letter = w.letter - 'A';
    if (w.letter == 'A' || w.letter == 'B' || w.letter == 'C' || w.letter == 'U' ||
        w.letter == 'V' || w.letter == 'W') {
      return failAt(error, w,
                    std::string("axis ") + w.letter +
                        " is not supported: the model and the compensation are for X, Y, Z");
    }
    if (w.letter == 'L') return failAt(error, w, "L words (canned cycles, G10) are not supported");
    if (w.letter == 'D')
      return failAt(error, w, "D words (cutter radius compensation) are not supported");
    if (w.letter == 'E') return failAt(error, w, "E words are not supported");
    if (words.letterWord[static_cast<std::size_t>(letter)] >= 0 && w.letter != 'N') {
      return failAt(error, w, std::string(1, w.letter) + " word given twice on one line");
    }
    words.letterWord[static_cast<std::size_t>(letter)] = i;
    if (w.letter == 'F') words.fWord = i;
  }
  return true;
}

bool NgcInterpreter::applyFeedAndTools(const LineWords& words, LineError& error) {
  if (const Word* f = words.word('F')) {
    if (f->value < 0) return failAt(error, *f, "negative feed rate");
    feed_ = f->value;
  }
  if (const Word* t = words.word('T')) {
    if (!isToolNumber(t->value)) return failAt(error, *t, kNotAToolNumber);
    selectedTool_ = static_cast<int>(t->value);
  }
  for (int k = 0; k < words.mCount; ++k) {
    const int m = words.mCodes[static_cast<std::size_t>(k)];
    const Word& w = words.at(words.mWords[static_cast<std::size_t>(k)]);
    if (m == 6) {
      if (selectedTool_ < 0) return failAt(error, w, "M6 without a tool selected (T word)");
      toolInSpindle_ = selectedTool_;
    }
    if (m == 61) {
      const Word* q = words.word('Q');
      if (q == nullptr) return failAt(error, w, "M61 needs Q with a tool number");
      if (!isToolNumber(q->value)) return failAt(error, *q, kNotAToolNumber);
      toolInSpindle_ = static_cast<int>(q->value);
    }
  }
  return true;
}

bool NgcInterpreter::applyToolLength(const LineWords& words, bool& axisWordsUsed,
                                     LineError& error) {
  const int code = words.code(kToolLength);
  if (code < 0) return true;
  if (code == 490) {
    toolOffsetMm_.setZero();
  } else if (code == 430) {
    int tool = toolInSpindle_;
    if (const Word* h = words.word('H')) {
      if (!isToolNumber(h->value)) return failAt(error, *h, kNotAToolNumber);
      tool = static_cast<int>(h->value);
    }
    const auto it = tools_.find(tool);
    if (it == tools_.end()) {
      if (tool != 0) {
        return failAt(error, words.codeWord(kToolLength),
                      "G43: tool " + std::to_string(tool) +
                          " is not in the tool table (give it with --tool-table or in the "
                          "work-offset JSON)");
      }
      toolOffsetMm_.setZero();
    } else {
      toolOffsetMm_ = it->second;
    }
  } else {  // G43.1: the axis words are the tool offsets
    const double unit = mmPerUnit(units_);
    toolOffsetMm_.setZero();
    for (int k = 0; k < 3; ++k) {
      if (const Word* a = words.word(static_cast<char>('X' + k))) {
        toolOffsetMm_[k] = a->value * unit;
      }
    }
    axisWordsUsed = true;
  }
  return true;
}

bool NgcInterpreter::applyCoordinateSystem(const LineWords& words, LineError& error) {
  const int code = words.code(kCoordinateSystem);
  if (code < 0) return true;
  const int index = code < 591 ? code / 10 - 54 : 6 + (code - 591);
  if (offsets_.rotationDeg[static_cast<std::size_t>(index)] != 0.0) {
    return failAt(error, words.codeWord(kCoordinateSystem),
                  std::string(coordinateSystemName(index)) +
                      " is rotated (G10 L2 R): coordinate system rotation is not supported");
  }
  system_ = index;
  return true;
}

bool NgcInterpreter::executeMotion(const LineWords& words, bool axisWordsUsed, NgcLine& out,
                                   LineError& error) {
  const Block& block = *words.block;
  const auto word = [&](char l) { return words.word(l); };
  const bool hasAxis = !axisWordsUsed && (word('X') || word('Y') || word('Z'));
  if (const int code = words.code(kMotion); code >= 0) {
    motion_ = code == 800 ? -1 : code / 10;
    out.dropWords |= 1ull << words.groupWord[kMotion];
  }
  const bool explicitMotion = words.code(kMotion) >= 0 && words.code(kMotion) != 800;
  const bool arcWords = word('I') || word('J') || word('K') || word('R');
  if (!hasAxis && !(explicitMotion && motion_ >= 2 && arcWords)) {
    if (words.g53) return failAt(error, block.words[0], "G53 without axis words");
    if (arcWords && motion_ < 2) {
      const Word* w = words.firstArcWord();
      return failAt(error, *w, std::string(1, w->letter) + " word without an arc (G2, G3)");
    }
    out.programEnd = false;
    if (words.ends()) {
      ended_ = true;
      out.programEnd = true;
    }
    // A line without motion keeps the position; in machine terms it may change with the frame.
    return true;
  }
  if (!checkMotion(words, error)) return false;
  const Position start = position_;
  const Vec3 startProgram = frame().toProgram(start.machineMm);
  Vec3 endMm = start.machineMm;
  std::uint8_t known = start.known;
  moveEnd(words, startProgram, endMm, known, out);
  out.motion = true;
  out.startKnown = start.allKnown();
  out.endKnown = known == 7;
  out.move.kind = motion_ == 0 ? MoveKind::Rapid : motion_ == 1 ? MoveKind::Line : MoveKind::Arc;
  out.move.startMm = start.machineMm;
  out.move.endMm = endMm;

  if (motion_ >= 2) {
    if (!arcMove(words, startProgram, out, error)) return false;
    if (!out.startKnown) return true;  // centre and sweep need the start
  } else if (word('R') || word('I') || word('J') || word('K')) {
    const Word* w = words.firstArcWord();
    return failAt(error, *w, std::string(1, w->letter) + " word without an arc (G2, G3)");
  }

  position_.machineMm = endMm;
  position_.known = known;
  if (words.ends()) {
    ended_ = true;
    out.programEnd = true;
  }
  return true;
}

bool NgcInterpreter::checkMotion(const LineWords& words, LineError& error) const {
  const Block& block = *words.block;
  const auto word = [&](char l) { return words.word(l); };
  if (motion_ < 0) {
    const Word* w = word('X') ? word('X') : word('Y') ? word('Y') : word('Z');
    return failAt(error, *w, "axis words without a motion (G0, G1, G2, G3) in effect");
  }
  if (words.g53 && motion_ >= 2) {
    return failAt(error, block.words[0], "G53 with an arc (G2, G3)");
  }
  if (words.g53 && incremental_) {
    return failAt(error, block.words[0], "G53 in incremental mode (G91)");
  }
  if (motion_ >= 1 && feed_ <= 0.0) {
    const Word* w = word('X')   ? word('X')
                    : word('Y') ? word('Y')
                    : word('Z') ? word('Z')
                                : &block.words[0];
    return failAt(error, *w, "feed move with zero feed rate (no F word yet)");
  }
  return true;
}

void NgcInterpreter::moveEnd(const LineWords& words, const Vec3& startProgram, Vec3& endMm,
                             std::uint8_t& known, NgcLine& out) const {
  const double unit = mmPerUnit(units_);
  const Frame f = frame();
  for (int k = 0; k < 3; ++k) {
    const int wi = words.index(static_cast<char>('X' + k));
    if (wi < 0) continue;
    out.dropWords |= 1ull << wi;
    const double v = words.at(wi).value;
    if (words.g53) {
      endMm[k] = v * unit;
      known |= static_cast<std::uint8_t>(1u << k);
    } else if (incremental_) {
      endMm[k] = (startProgram[k] + v) * unit + f.shiftMm[k];
    } else {
      endMm[k] = v * unit + f.shiftMm[k];
      known |= static_cast<std::uint8_t>(1u << k);
    }
  }
}

bool NgcInterpreter::arcMove(const LineWords& words, const Vec3& startProgram, NgcLine& out,
                             LineError& error) const {
  static constexpr int kAxes[3][3] = {{0, 1, 2}, {2, 0, 1}, {1, 2, 0}};
  const int a1 = kAxes[plane_][0];
  const int a2 = kAxes[plane_][1];
  const int an = kAxes[plane_][2];
  const char c1 = static_cast<char>('I' + a1);
  const char c2 = static_cast<char>('I' + a2);
  const char cn = static_cast<char>('I' + an);
  for (char c : {'I', 'J', 'K', 'R', 'P'}) {
    if (const int wi = words.index(c); wi >= 0) out.dropWords |= 1ull << wi;
  }
  if (const Word* w = words.word(cn)) {
    return failAt(error, *w,
                  std::string(1, cn) + " word with an arc in the " +
                      (plane_ == 0   ? "XY (G17)"
                       : plane_ == 1 ? "XZ (G18)"
                                     : "YZ (G19)") +
                      " plane");
  }
  int turns = 1;
  if (const Word* p = words.word('P')) {
    if (p->value < 1 || p->value > kMaxArcTurns || p->value != std::floor(p->value)) {
      return failAt(
          error, *p,
          "P (turns of an arc) must be a whole number in 1.." + std::to_string(kMaxArcTurns));
    }
    turns = static_cast<int>(p->value);
  }
  const Word* r = words.word('R');
  const Word* i1 = words.word(c1);
  const Word* i2 = words.word(c2);
  if (r != nullptr && (i1 != nullptr || i2 != nullptr)) {
    return failAt(error, *r, "an arc takes either R or a centre (I, J, K), not both");
  }
  if (r == nullptr && i1 == nullptr && i2 == nullptr) {
    return failAt(error, words.at(words.groupWord[kMotion] >= 0 ? words.groupWord[kMotion] : 0),
                  std::string("arc without a centre (") + c1 + ", " + c2 + ") or a radius (R)");
  }
  if (!out.startKnown) return true;
  const Frame f = frame();
  const ArcTolerances tol = arcTolerances(units_);
  const Vec3 endProgram = f.toProgram(out.move.endMm);
  const InPlane start{startProgram[a1], startProgram[a2]};
  const InPlane end{endProgram[a1], endProgram[a2]};
  InPlane centre;
  const int rotationSign = motion_ == 2 ? -1 : 1;
  if (r != nullptr) {
    if (!centreFromRadius(*r, motion_ == 2, tol, start, end, centre, error)) return false;
  } else if (!centreFromOffsets(i1, i2, arcIncremental_, units_, tol, start, end, centre, error)) {
    return false;
  }
  Vec3 centreProgram = startProgram;
  centreProgram[a1] = centre.first;
  centreProgram[a2] = centre.second;
  const Vec3 centreMm = f.toMachine(centreProgram);
  out.move.arc = makeArc(plane_, out.move.startMm, out.move.endMm, centreMm[a1], centreMm[a2],
                         rotationSign * turns);
  return true;
}

}  // namespace volcomp::nc
