#include "volcomp/config/dbc_file.hpp"

#include <cctype>
#include <charconv>

#include "volcomp/config/config_error.hpp"
#include "volcomp/config/text_input.hpp"

namespace volcomp::config {
namespace {

using can::ByteOrder;
using can::DbcDatabase;
using can::DbcMessage;
using can::DbcSignal;
using can::SignalSpec;
using can::ValueType;

constexpr std::uint32_t kExtendedFlag = 0x80000000u;
constexpr std::uint32_t kIndependentSignalsId = 0xC0000000u;

/// A cursor over one line; every `expect…` throws ConfigError at "line N".
class LineParser {
 public:
  LineParser(std::string_view line, const std::string& file, std::size_t lineNumber)
      : line_(line), file_(file), lineNumber_(lineNumber) {}

  [[noreturn]] void fail(const std::string& message) const {
    throw ConfigError(file_, "line " + std::to_string(lineNumber_), message);
  }

  void skipSpace() {
    while (pos_ < line_.size() && std::isspace(static_cast<unsigned char>(line_[pos_]))) ++pos_;
  }
  bool atEnd() {
    skipSpace();
    return pos_ >= line_.size();
  }
  char peek() {
    skipSpace();
    return pos_ < line_.size() ? line_[pos_] : '\0';
  }
  void expectChar(char c, const char* what) {
    if (peek() != c) fail(std::string("expected '") + c + "' " + what);
    ++pos_;
  }
  std::string_view word() {
    skipSpace();
    const std::size_t begin = pos_;
    while (pos_ < line_.size() && !std::isspace(static_cast<unsigned char>(line_[pos_])) &&
           line_[pos_] != ':' && line_[pos_] != ';')
      ++pos_;
    return line_.substr(begin, pos_ - begin);
  }
  std::string_view identifier(const char* what) {
    skipSpace();
    const std::size_t begin = pos_;
    while (pos_ < line_.size() &&
           (std::isalnum(static_cast<unsigned char>(line_[pos_])) || line_[pos_] == '_'))
      ++pos_;
    if (pos_ == begin) fail(std::string("expected ") + what);
    return line_.substr(begin, pos_ - begin);
  }
  std::uint64_t unsignedNumber(const char* what) {
    skipSpace();
    std::uint64_t value = 0;
    const char* first = line_.data() + pos_;
    auto [ptr, ec] = std::from_chars(first, line_.data() + line_.size(), value);
    if (ec != std::errc{}) fail(std::string("expected ") + what + " (an unsigned integer)");
    pos_ += static_cast<std::size_t>(ptr - first);
    return value;
  }
  double realNumber(const char* what) {
    skipSpace();
    if (pos_ < line_.size() && line_[pos_] == '+') ++pos_;  // from_chars refuses a '+' sign
    double value = 0.0;
    const char* first = line_.data() + pos_;
    auto [ptr, ec] = std::from_chars(first, line_.data() + line_.size(), value);
    if (ec != std::errc{}) fail(std::string("expected ") + what + " (a number)");
    pos_ += static_cast<std::size_t>(ptr - first);
    return value;
  }
  std::string quoted(const char* what) {
    expectChar('"', what);
    const std::size_t end = line_.find('"', pos_);
    if (end == std::string_view::npos) fail(std::string("unterminated ") + what);
    std::string text(line_.substr(pos_, end - pos_));
    pos_ = end + 1;
    return text;
  }

 private:
  std::string_view line_;
  const std::string& file_;
  std::size_t lineNumber_;
  std::size_t pos_ = 0;
};

void parseMessage(LineParser& p, DbcDatabase& db, bool& skipSignals) {
  const std::uint64_t rawId = p.unsignedNumber("message identifier");
  if (rawId > 0xFFFFFFFFu) p.fail("message identifier does not fit 32 bits");
  const auto id32 = static_cast<std::uint32_t>(rawId);
  const std::string name(p.identifier("message name"));
  p.expectChar(':', "after the message name");
  const std::uint64_t length = p.unsignedNumber("message length");
  if (id32 == kIndependentSignalsId) {
    skipSignals = true;
    return;
  }
  skipSignals = false;
  DbcMessage message;
  message.name = name;
  message.extended = (id32 & kExtendedFlag) != 0;
  message.id = message.extended ? (id32 & can::kExtendedIdMax) : id32;
  if (!can::isValidId(message.id, message.extended))
    p.fail("standard identifier " + std::to_string(message.id) + " exceeds 0x7FF");
  if (length > can::kFdMaxLength || !can::isValidLength(length, true))
    p.fail("message length " + std::to_string(length) + " is not a valid CAN/CAN FD length");
  message.length = static_cast<std::size_t>(length);
  db.messages.push_back(std::move(message));
}

void parseSignal(LineParser& p, DbcMessage& message) {
  DbcSignal signal;
  SignalSpec& spec = signal.spec;
  spec.name = std::string(p.identifier("signal name"));
  if (p.peek() != ':') signal.multiplexer = std::string(p.word());
  p.expectChar(':', "after the signal name");
  const std::uint64_t start = p.unsignedNumber("start bit");
  p.expectChar('|', "between start bit and length");
  const std::uint64_t length = p.unsignedNumber("signal length");
  p.expectChar('@', "before the byte order");
  const char order = p.peek();
  if (order != '0' && order != '1') p.fail("expected byte order @0 (Motorola) or @1 (Intel)");
  p.expectChar(order, "");
  const char sign = p.peek();
  if (sign != '+' && sign != '-') p.fail("expected sign + (unsigned) or - (signed)");
  p.expectChar(sign, "");
  p.expectChar('(', "before the scale");
  spec.scale = p.realNumber("scale");
  p.expectChar(',', "between scale and offset");
  spec.offset = p.realNumber("offset");
  p.expectChar(')', "after the offset");
  p.expectChar('[', "before the minimum");
  spec.minimum = p.realNumber("minimum");
  p.expectChar('|', "between minimum and maximum");
  spec.maximum = p.realNumber("maximum");
  p.expectChar(']', "after the maximum");
  spec.unit = p.quoted("unit string");
  if (start >= 8 * can::kFdMaxLength)
    p.fail("start bit " + std::to_string(start) + " beyond 64 bytes");
  if (length < 1 || length > 64) p.fail("signal length must be 1..64 bits");
  spec.startBit = static_cast<unsigned>(start);
  spec.length = static_cast<unsigned>(length);
  spec.byteOrder = order == '1' ? ByteOrder::Intel : ByteOrder::Motorola;
  spec.valueType = sign == '-' ? ValueType::Signed : ValueType::Unsigned;
  spec.frameId = message.id;
  spec.extended = message.extended;
  if (const std::string problem = layoutProblem(spec); !problem.empty())
    p.fail("signal " + spec.name + ": " + problem);
  if (bytesNeeded(spec) > message.length)
    p.fail("signal " + spec.name + " extends beyond the message's " +
           std::to_string(message.length) + " bytes");
  message.signals.push_back(std::move(signal));
}

void parseValueType(LineParser& p, DbcDatabase& db) {
  if (p.atEnd()) return;  // the keyword listed alone in the NS_ block
  const std::uint64_t rawId = p.unsignedNumber("message identifier");
  const std::string name(p.identifier("signal name"));
  p.expectChar(':', "after the signal name");
  const std::uint64_t kind = p.unsignedNumber("value type (1 = float32, 2 = float64)");
  if (kind != 1 && kind != 2) p.fail("value type must be 1 (float32) or 2 (float64)");
  if (rawId == kIndependentSignalsId) return;
  const bool extended = (rawId & kExtendedFlag) != 0;
  const auto id =
      static_cast<std::uint32_t>(rawId & (extended ? can::kExtendedIdMax : 0xFFFFFFFFu));
  for (DbcMessage& message : db.messages) {
    if (message.id != id || message.extended != extended) continue;
    for (DbcSignal& signal : message.signals) {
      if (signal.spec.name != name) continue;
      signal.spec.valueType = kind == 1 ? ValueType::Float32 : ValueType::Float64;
      if (const std::string problem = layoutProblem(signal.spec); !problem.empty())
        p.fail("signal " + name + ": " + problem);
      return;
    }
  }
  p.fail("SIG_VALTYPE_ names unknown signal " + name + " of message " + std::to_string(rawId));
}

}  // namespace

DbcDatabase parseDbc(std::string_view text, const std::string& file) {
  DbcDatabase db;
  bool skipSignals = false;
  std::size_t lineNumber = 0;
  std::size_t begin = 0;
  while (begin <= text.size()) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(begin, end - begin);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    ++lineNumber;
    begin = end + 1;

    LineParser p(line, file, lineNumber);
    if (p.atEnd()) continue;
    const std::string_view keyword = p.word();
    if (keyword == "BO_") {
      parseMessage(p, db, skipSignals);
    } else if (keyword == "SG_") {
      if (skipSignals) continue;
      if (db.messages.empty()) p.fail("SG_ before any BO_ message");
      parseSignal(p, db.messages.back());
    } else if (keyword == "SIG_VALTYPE_") {
      parseValueType(p, db);
    }  // every other keyword is outside the subset and skipped
  }
  return db;
}

DbcDatabase readDbcFile(const std::string& path) {
  return parseDbc(readTextFile(path), path);
}

}  // namespace volcomp::config
