#pragma once
/// Text from files, users or the wire made safe to show in a message or a log line.
///
/// Messages quote what they did not understand ("expected a finite number, got \"1,5\""), and what
/// they quote can be anything: invalid UTF-8, control characters, terminal escape sequences that
/// recolour or clear a terminal, a 100 kB field. printable() keeps every printable character of
/// valid UTF-8 as it is and writes the rest visibly:
///   - newline, carriage return, tab as \n, \r, \t; other C0 controls and DEL as \xHH (so ESC is
///     \x1b and no escape sequence reaches the terminal);
///   - C1 controls (U+0080..U+009F, CSI among them), bidirectional overrides and isolates
///     (U+200E, U+200F, U+202A..U+202E, U+2066..U+2069) and the line and paragraph separators
///     (U+2028, U+2029) as \uHHHH;
///   - each byte that is not part of valid UTF-8 (overlong forms, surrogates, beyond U+10FFFF,
///     truncated sequences) as \xHH.
/// The result is at most `maxBytes` long (cut at a character boundary, "..." appended when cut).
/// A backslash is kept as it is, so text that went through printable() once comes out of it again
/// unchanged (when not cut): ConfigError passes its whole message through it, parts that a parser
/// already quoted included.

#include <cstddef>
#include <string>
#include <string_view>

namespace volcomp::config {

/// Bytes a quoted value keeps by default: enough to recognise it, short enough for one line.
inline constexpr std::size_t kQuotedBytes = 60;

/// `raw` with everything that is not printable valid UTF-8 escaped (see above), at most
/// `maxBytes` (>= 3) bytes long.
std::string printable(std::string_view raw, std::size_t maxBytes = std::string::npos);

/// printable(raw, maxBytes) between double quotes, a double quote inside written as \": the way a
/// message shows a value it read.
std::string quoted(std::string_view raw, std::size_t maxBytes = kQuotedBytes);

/// True when printable(text) == text for any limit: valid UTF-8 without the characters above.
bool isPrintable(std::string_view text) noexcept;

}  // namespace volcomp::config
