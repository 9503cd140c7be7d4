#include <cerrno>
#include <cstddef>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "volcomp/config/json_reader.hpp"

namespace volcomp::config {
namespace {

using Json = nlohmann::json;

// nlohmann keeps the last of repeated keys silently: this parser callback rejects them, naming
// the key path. It sees every event of the parse (public API: json::parse with a callback) and
// keeps one frame per open object or array.
class DuplicateKeyCheck {
 public:
  explicit DuplicateKeyCheck(const std::string& file) : file_(file) {}

  bool operator()(int /*depth*/, Json::parse_event_t event, Json& parsed) {
    switch (event) {
      case Json::parse_event_t::object_start:
        push(true);
        break;
      case Json::parse_event_t::array_start:
        push(false);
        break;
      case Json::parse_event_t::object_end:
      case Json::parse_event_t::array_end:
        frames_.pop_back();
        break;
      case Json::parse_event_t::key: {
        Frame& top = frames_.back();
        const std::string& key = parsed.get_ref<const std::string&>();
        if (!top.seen.insert(key).second) {
          throw ConfigError(file_, pathTo(key),
                            "duplicate key (each key may appear once per object)");
        }
        top.key = key;
        break;
      }
      case Json::parse_event_t::value:
        advance();
        break;
    }
    return true;  // keep everything
  }

 private:
  struct Frame {
    bool object = false;
    std::string segment;  // how this container is reached from its parent: ".key" or "[i]"
    std::string key;      // last key read (objects)
    std::size_t index = 0;
    std::set<std::string> seen;
  };

  // A value inside an array moves that array's element counter.
  void advance() {
    if (!frames_.empty() && !frames_.back().object) ++frames_.back().index;
  }
  void push(bool object) {
    Frame frame;
    frame.object = object;
    if (!frames_.empty()) {
      const Frame& parent = frames_.back();
      // Appended piece by piece: GCC 12 at -O3 reports a false -Wrestrict overlap for "." + key
      // inside libstdc++ (see the top CMakeLists.txt).
      if (parent.object) {
        if (frames_.size() != 1) frame.segment += '.';
        frame.segment += parent.key;
      } else {
        frame.segment += '[';
        frame.segment += std::to_string(parent.index);
        frame.segment += ']';
      }
      advance();
    }
    frames_.push_back(std::move(frame));
  }
  std::string pathTo(const std::string& key) const {
    std::string path;
    for (std::size_t i = 1; i < frames_.size(); ++i) path += frames_[i].segment;
    if (!path.empty()) path += '.';
    return path + key;
  }

  const std::string& file_;
  std::vector<Frame> frames_;
};

// "line L, column C" of a byte offset (both from 1).
std::string lineColumn(std::string_view text, std::size_t offset) {
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

// Offset of the first occurrence of the number `token` outside strings (the parser stops at the
// first number that overflows, and an earlier identical one would have overflowed too).
std::size_t findNumber(std::string_view text, std::string_view token) {
  bool inString = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (inString) {
      if (c == '\\') {
        ++i;
      } else if (c == '"') {
        inString = false;
      }
    } else if (c == '"') {
      inString = true;
    } else if (text.substr(i, token.size()) == token &&
               (i == 0 ||
                std::string_view("0123456789.+-eE").find(text[i - 1]) == std::string_view::npos)) {
      return i;  // a whole number, not the tail of another one
    }
  }
  return text.size();
}

// The library's message without its "[json.exception.parse_error.101] " prefix: users need the
// rest only.
std::string withoutPrefix(std::string message) {
  if (const auto close = message.find("] ");
      message.rfind("[json.exception", 0) == 0 && close != std::string::npos) {
    message.erase(0, close + 2);
  }
  return message;
}

// The library quotes what it read of the failing token ("last read: '...'"), which may be a whole
// string value of any length: only its end, nearest the error, is kept. The cut is at a character
// boundary (never inside a UTF-8 sequence).
std::string shortLastRead(std::string message) {
  constexpr std::size_t kKeptBytes = 40;
  const std::string marker = "; last read: '";
  const auto open = message.find(marker);
  const auto close = message.rfind('\'');
  if (open == std::string::npos || close == std::string::npos) return message;
  const std::size_t from = open + marker.size();
  if (close <= from || close - from <= kKeptBytes) return message;
  std::size_t cut = close - kKeptBytes;
  while (cut < close && (static_cast<unsigned char>(message[cut]) & 0xC0) == 0x80) ++cut;
  message.replace(from, cut - from, "...");
  return message;
}

}  // namespace

nlohmann::json parseJsonText(std::string_view text, const std::string& file) {
  try {
    return Json::parse(text, DuplicateKeyCheck(file));
  } catch (const Json::parse_error& e) {
    throw ConfigError(file, "", "invalid JSON: " + shortLastRead(withoutPrefix(e.what())));
  } catch (const Json::out_of_range& e) {
    // 406: a number beyond the range of a double, reported without a position; the message
    // quotes the number, which locates it.
    const std::string message = e.what();
    const auto open = message.find('\'');
    const auto close = message.rfind('\'');
    if (e.id != 406 || open == std::string::npos || close <= open) {
      throw ConfigError(file, "", "invalid JSON: " + withoutPrefix(message));
    }
    const std::string token = message.substr(open + 1, close - open - 1);
    throw ConfigError(file, "",
                      "invalid JSON: at " + lineColumn(text, findNumber(text, token)) +
                          ": number " + token + " is out of the range of a double");
  }
}

nlohmann::json readJsonFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const std::error_code ec(errno, std::generic_category());
    throw ConfigError(path, "", "cannot open file: " + ec.message());
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw ConfigError(path, "", "cannot read file");
  return parseJsonText(text.str(), path);
}

}  // namespace volcomp::config
