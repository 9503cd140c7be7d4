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

// nlohmann keeps the last of repeated keys silently and reports number overflow without a
// position; this SAX handler builds the same DOM but rejects both with a usable location.
class CheckingSax : public nlohmann::detail::json_sax_dom_parser<Json> {
 public:
  CheckingSax(Json& document, std::string_view text, const std::string& file)
      : json_sax_dom_parser<Json>(document, true), text_(text), file_(file) {}

  bool null() { return value(&Base::null); }
  bool boolean(bool v) {
    return value([&] { return Base::boolean(v); });
  }
  bool number_integer(Json::number_integer_t v) {
    return value([&] { return Base::number_integer(v); });
  }
  bool number_unsigned(Json::number_unsigned_t v) {
    return value([&] { return Base::number_unsigned(v); });
  }
  bool number_float(Json::number_float_t v, const Json::string_t& s) {
    return value([&] { return Base::number_float(v, s); });
  }
  bool string(Json::string_t& v) {
    return value([&] { return Base::string(v); });
  }
  bool binary(Json::binary_t& v) {
    return value([&] { return Base::binary(v); });
  }

  bool start_object(std::size_t n) {
    push(true);
    return Base::start_object(n);
  }
  bool end_object() {
    frames_.pop_back();
    return Base::end_object();
  }
  bool start_array(std::size_t n) {
    push(false);
    return Base::start_array(n);
  }
  bool end_array() {
    frames_.pop_back();
    return Base::end_array();
  }
  bool key(Json::string_t& k) {
    Frame& top = frames_.back();
    if (!top.seen.insert(k).second) {
      throw ConfigError(file_, pathOf(frames_.size(), k),
                        "duplicate key (each key may appear once per object)");
    }
    top.key = k;
    return Base::key(k);
  }

  template <class Exception>
  bool parse_error(std::size_t position, const std::string& lastToken, const Exception& ex) {
    std::string message = ex.what();
    // Drop the library's "[json.exception.parse_error.101] " prefix: users need the rest only.
    if (const auto close = message.find("] ");
        message.rfind("[json.exception", 0) == 0 && close != std::string::npos) {
      message.erase(0, close + 2);
    }
    if (ex.id == 406) {
      const std::size_t start = position >= lastToken.size() ? position - lastToken.size() : 0;
      message =
          "at " + lineColumn(start) + ": number " + lastToken + " is out of the range of a double";
    }
    throw ConfigError(file_, "", "invalid JSON: " + message);
  }

 private:
  using Base = nlohmann::detail::json_sax_dom_parser<Json>;
  struct Frame {
    bool object = false;
    std::string segment;  // how this container is reached from its parent: ".key" or "[i]"
    std::string key;      // last key read (objects)
    std::size_t index = 0;
    std::set<std::string> seen;
  };

  template <class F>
  bool value(F&& f) {
    advance();
    return f();
  }
  bool value(bool (Base::*f)()) {
    advance();
    return (this->*f)();
  }
  // A value inside an array moves that array's element counter.
  void advance() {
    if (!frames_.empty() && !frames_.back().object) ++frames_.back().index;
  }
  void push(bool object) {
    Frame frame;
    frame.object = object;
    if (!frames_.empty()) {
      Frame& parent = frames_.back();
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
  std::string pathOf(std::size_t depth, const std::string& lastKey) const {
    std::string path;
    for (std::size_t i = 1; i < depth; ++i) path += frames_[i].segment;
    if (!path.empty()) path += '.';
    return path + lastKey;
  }
  std::string lineColumn(std::size_t offset) const {
    std::size_t line = 1, column = 1;
    for (std::size_t i = 0; i < offset && i < text_.size(); ++i) {
      if (text_[i] == '\n') {
        ++line;
        column = 1;
      } else {
        ++column;
      }
    }
    return "line " + std::to_string(line) + ", column " + std::to_string(column);
  }

  std::string_view text_;
  const std::string& file_;
  std::vector<Frame> frames_;
};

}  // namespace

nlohmann::json parseJsonText(std::string_view text, const std::string& file) {
  Json root;
  CheckingSax sax(root, text, file);
  Json::sax_parse(text, &sax);
  return root;
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
