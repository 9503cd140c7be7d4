#include "volcomp/sim/nc_program.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "volcomp/nc/canon_reader.hpp"
#include "volcomp/nc/nc_error.hpp"
#include "volcomp/nc/ngc_reader.hpp"
#include "volcomp/nc/text_io.hpp"

namespace volcomp::sim {
namespace {

bool canonicalFile(const std::string& path) {
  nc::FileSource source(path, 1u << 16);
  const std::string_view text = source.nextLines();
  std::size_t pos = 0;
  while (pos < text.size()) {
    const std::size_t nl = text.find('\n', pos);
    const std::string_view line =
        text.substr(pos, (nl == std::string_view::npos ? text.size() : nl) - pos);
    if (line.find_first_not_of(" \t\r") != std::string_view::npos) {
      return nc::CanonReader::looksCanonical(line);
    }
    if (nl == std::string_view::npos) break;
    pos = nl + 1;
  }
  return false;
}

// The simulator samples whole moves and files them in a grid of cells: a position beyond a
// kilometre (a wrong offset or unit) would take forever or overflow the cell index.
void refuseBeyondRange(const nc::Move& move, const std::string& file, long line) {
  static constexpr char kAxes[3] = {'X', 'Y', 'Z'};
  std::ostringstream message;
  for (const nc::Vec3& p : {move.startMm, move.endMm}) {
    for (int k = 0; k < 3 && message.tellp() == 0; ++k) {
      if (!(std::abs(p[k]) <= nc::kMaxPositionMm)) {
        message << kAxes[k] << " at " << p[k] << " mm is";
      }
    }
  }
  const double radiusMm = std::max(move.arc.startRadius, move.arc.endRadius);
  if (message.tellp() == 0 && move.kind == nc::MoveKind::Arc && !(radiusMm <= nc::kMaxPositionMm)) {
    message << "an arc of radius " << radiusMm << " mm reaches";
  }
  if (message.tellp() == 0) return;
  message << " beyond +-" << nc::kMaxPositionMm << " mm: is a work offset or the unit wrong?";
  throw nc::NcError(file, line, 0, message.str());
}

}  // namespace

int piecesOf(const NcProgramMove& m, double wanted, const std::string& file, const char* what) {
  if (!(wanted <= kMaxPiecesPerMove)) {
    std::ostringstream message;
    message << "this move would need " << wanted << " " << what << ", more than the "
            << kMaxPiecesPerMove << " the simulator splits one move into";
    throw nc::NcError(file, m.line, 0, message.str());
  }
  return std::max(1, static_cast<int>(std::ceil(wanted)));
}

int arcChords(const NcProgramMove& m, double toleranceMm, const std::string& file) {
  if (m.move.kind != nc::MoveKind::Arc) return 1;
  const double r = std::max(m.move.arc.startRadius, m.move.arc.endRadius);
  const double maxAngle = r > toleranceMm ? 2.0 * std::acos(1.0 - toleranceMm / r) : 1.0;
  std::ostringstream what;
  what << "chords within " << toleranceMm << " mm";
  return piecesOf(m, std::abs(m.move.arc.sweep) / maxAngle, file, what.str().c_str());
}

std::vector<NcProgramMove> readNcProgram(const NcProgramSpec& spec) {
  const nc::LengthUnit units =
      spec.machineUnits == "inch" ? nc::LengthUnit::Inch : nc::LengthUnit::Mm;
  nc::WorkOffsets offsets;
  nc::ToolTable tools;
  for (const std::string& f : spec.workOffsets) nc::readWorkOffsetsFile(f, units, offsets, tools);
  if (!spec.toolTable.empty()) nc::readToolTableFile(spec.toolTable, units, tools);
  std::optional<nc::Vec3> start;
  if (spec.startMm) start = nc::Vec3((*spec.startMm)[0], (*spec.startMm)[1], (*spec.startMm)[2]);
  std::unique_ptr<nc::ProgramReader> reader;
  if (canonicalFile(spec.file)) {
    reader = std::make_unique<nc::CanonReader>(spec.file, start, nc::Decimals{});
  } else {
    reader = std::make_unique<nc::NgcReader>(spec.file, offsets, tools, start, nc::Decimals{});
  }
  std::vector<NcProgramMove> moves;
  nc::FileSource source(spec.file);
  nc::Chunk chunk;
  long number = 0;
  bool markNext = false;
  while (true) {
    const std::string_view text = source.nextLines();
    if (text.empty()) break;
    std::size_t pos = 0;
    while (pos < text.size()) {
      const std::size_t nl = text.find('\n', pos);
      std::string_view line =
          text.substr(pos, (nl == std::string_view::npos ? text.size() : nl) - pos);
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      pos = nl == std::string_view::npos ? text.size() : nl + 1;
      chunk.clear();
      reader->read(line, "\n", ++number, chunk);
      const bool marker = line.find("volcomp:") != std::string_view::npos;
      for (const nc::LineWork& lw : chunk.lines) {
        if (lw.action != nc::LineAction::Motion) continue;
        const nc::MotionWork& w = chunk.motions[lw.motion];
        const bool marked = marker || markNext;
        markNext = false;
        if (!w.startKnown || !w.endKnown) continue;
        refuseBeyondRange(w.move, spec.file, number);
        moves.push_back(NcProgramMove{w.move, number, marked});
      }
      // A canonical COMMENT("volcomp: ...") marks the motion that follows it.
      if (marker && chunk.motions.empty()) markNext = true;
    }
  }
  return moves;
}

Path ncProgramPath(const NcProgramSpec& spec, double feedMmMin) {
  std::vector<Vec3> points;
  for (const NcProgramMove& m : readNcProgram(spec)) {
    const int n = arcChords(m, 1e-4, spec.file);
    if (points.empty()) points.push_back({m.move.startMm[0], m.move.startMm[1], m.move.startMm[2]});
    for (int i = 1; i <= n; ++i) {
      const nc::Vec3 p = m.move.at(static_cast<double>(i) / n);
      points.push_back({p[0], p[1], p[2]});
    }
  }
  if (points.empty()) throw std::runtime_error(spec.file + ": no moves with a known position");
  return Path::polyline(std::move(points), feedMmMin);
}

}  // namespace volcomp::sim
