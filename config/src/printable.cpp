#include "volcomp/config/printable.hpp"

#include <cstdint>

namespace volcomp::config {
namespace {

constexpr char kHex[] = "0123456789abcdef";

/// Length of the valid UTF-8 sequence at the start of `s` and its code point; 0 when the bytes
/// there are not valid UTF-8 (RFC 3629: no overlong forms, no surrogates, nothing past U+10FFFF).
std::size_t decodeUtf8(std::string_view s, char32_t& codePoint) noexcept {
  const auto byte = [&](std::size_t i) { return static_cast<std::uint8_t>(s[i]); };
  const std::uint8_t b0 = byte(0);
  if (b0 < 0x80) {
    codePoint = b0;
    return 1;
  }
  std::size_t length = 0;
  char32_t min = 0;
  if ((b0 & 0xE0) == 0xC0) {
    length = 2;
    codePoint = b0 & 0x1F;
    min = 0x80;
  } else if ((b0 & 0xF0) == 0xE0) {
    length = 3;
    codePoint = b0 & 0x0F;
    min = 0x800;
  } else if ((b0 & 0xF8) == 0xF0) {
    length = 4;
    codePoint = b0 & 0x07;
    min = 0x10000;
  } else {
    return 0;
  }
  if (s.size() < length) return 0;
  for (std::size_t i = 1; i < length; ++i) {
    if ((byte(i) & 0xC0) != 0x80) return 0;
    codePoint = (codePoint << 6) | (byte(i) & 0x3F);
  }
  if (codePoint < min || codePoint > 0x10FFFF || (codePoint >= 0xD800 && codePoint <= 0xDFFF)) {
    return 0;
  }
  return length;
}

/// Characters that change how a terminal shows the text after them, or break a line.
bool isInvisibleControl(char32_t c) noexcept {
  return (c >= 0x80 && c <= 0x9F) || c == 0x200E || c == 0x200F || (c >= 0x202A && c <= 0x202E) ||
         (c >= 0x2066 && c <= 0x2069) || c == 0x2028 || c == 0x2029;
}

/// Appends the printable form of the character at the start of `s`; returns the bytes consumed.
std::size_t appendOne(std::string_view s, std::string& out) {
  char32_t c = 0;
  const std::size_t length = decodeUtf8(s, c);
  if (length == 0) {
    const auto b = static_cast<std::uint8_t>(s[0]);
    out += "\\x";
    out += kHex[b >> 4];
    out += kHex[b & 0xF];
    return 1;
  }
  if (c == '\n') {
    out += "\\n";
  } else if (c == '\r') {
    out += "\\r";
  } else if (c == '\t') {
    out += "\\t";
  } else if (c < 0x20 || c == 0x7F) {
    out += "\\x";
    out += kHex[c >> 4];
    out += kHex[c & 0xF];
  } else if (isInvisibleControl(c)) {
    out += "\\u";
    for (int shift = 12; shift >= 0; shift -= 4) out += kHex[(c >> shift) & 0xF];
  } else {
    out.append(s.substr(0, length));
  }
  return length;
}

std::string escape(std::string_view raw, std::size_t maxBytes, bool escapeQuotes) {
  if (maxBytes < 3) maxBytes = 3;
  std::string out;
  std::size_t cutAt = 0;  // the last character boundary that leaves room for "..."
  for (std::size_t i = 0; i < raw.size() && out.size() <= maxBytes;) {
    if (escapeQuotes && raw[i] == '"') {
      out += "\\\"";
      ++i;
    } else {
      i += appendOne(raw.substr(i), out);
    }
    if (out.size() <= maxBytes - 3) cutAt = out.size();
  }
  if (out.size() > maxBytes) {
    out.resize(cutAt);
    out += "...";
  }
  return out;
}

}  // namespace

std::string printable(std::string_view raw, std::size_t maxBytes) {
  return escape(raw, maxBytes, false);
}

std::string quoted(std::string_view raw, std::size_t maxBytes) {
  return '"' + escape(raw, maxBytes, true) + '"';
}

bool isPrintable(std::string_view text) noexcept {
  for (std::size_t i = 0; i < text.size();) {
    char32_t c = 0;
    const std::size_t length = decodeUtf8(text.substr(i), c);
    if (length == 0 || c < 0x20 || c == 0x7F || isInvisibleControl(c)) return false;
    i += length;
  }
  return true;
}

}  // namespace volcomp::config
