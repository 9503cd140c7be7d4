#include "volcomp/nc/ngc_reader.hpp"

namespace volcomp::nc {
namespace {

std::string_view trimRight(std::string_view s) {
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// Splits the line around the written motion: the words in `removed` are cut out (with the blanks
// before them), and the motion goes where the first word of `drop` was.
void buildTemplate(const Block& block, std::uint64_t drop, std::uint64_t removed, Chunk& chunk,
                   TextRef& prefix, TextRef& suffix) {
  std::string_view text = block.text;
  if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
  std::string out;
  std::size_t cursor = 0;
  std::size_t insertAt = std::string::npos;
  for (int i = 0; i < block.wordCount; ++i) {
    if ((removed & (1ull << i)) == 0) continue;
    const Word& w = block.words[static_cast<std::size_t>(i)];
    const std::string_view segment = text.substr(cursor, w.begin - cursor);
    if (insertAt == std::string::npos && (drop & (1ull << i)) != 0) {
      out.append(segment);
      insertAt = out.size();
    } else {
      out.append(trimRight(segment));
    }
    cursor = w.end;
  }
  out.append(text.substr(cursor));
  if (insertAt == std::string::npos) insertAt = out.size();
  prefix = chunk.store(std::string_view(out).substr(0, insertAt));
  suffix = chunk.store(std::string_view(out).substr(insertAt));
}

}  // namespace

NgcReader::NgcReader(std::string file, const WorkOffsets& offsets, const ToolTable& tools,
                     std::optional<Vec3> startMm, Decimals decimals)
    : file_(std::move(file)), interpreter_(offsets, tools, startMm, decimals) {}

void NgcReader::read(std::string_view line, std::string_view eol, long number, Chunk& chunk) {
  LineWork work;
  work.input = line;
  work.eol = eol;
  if (interpreter_.ended()) {
    chunk.lines.push_back(work);
    return;
  }
  if (!tokenize(line, block_, error_) || !interpreter_.execute(block_, result_, error_)) {
    throw NcError(file_, number, error_.column, error_.message);
  }
  if (!result_.motion) {
    chunk.lines.push_back(work);
    return;
  }
  MotionWork m;
  m.move = result_.move;
  m.line = number;
  m.startKnown = result_.startKnown;
  m.endKnown = result_.endKnown;
  m.before = result_.before;
  m.after = result_.after;
  const std::uint64_t drop = result_.dropWords;
  if (result_.stopWords == 0) {
    buildTemplate(block_, drop, drop, chunk, m.prefix, m.suffix);
  } else {
    // The stop codes leave the line; they are written on the last line of the move.
    buildTemplate(block_, drop, drop | result_.stopWords, chunk, m.prefix, m.suffix);
    std::string tail;
    for (int i = 0; i < block_.wordCount; ++i) {
      if ((result_.stopWords & (1ull << i)) == 0) continue;
      const Word& w = block_.words[static_cast<std::size_t>(i)];
      if (!tail.empty()) tail += ' ';
      tail.append(block_.text.substr(w.begin, w.end - w.begin));
    }
    m.tail = chunk.store(tail);
  }
  if (result_.feedWord >= 0) {
    const Word& f = block_.words[static_cast<std::size_t>(result_.feedWord)];
    m.feed = chunk.store(block_.text.substr(f.begin, f.end - f.begin));
  }
  work.action = LineAction::Motion;
  work.motion = static_cast<std::uint32_t>(chunk.motions.size());
  chunk.motions.push_back(m);
  chunk.lines.push_back(work);
}

}  // namespace volcomp::nc
