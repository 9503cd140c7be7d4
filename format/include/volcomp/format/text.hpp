#pragma once
/// Text in fixed-width columns, as printf pads strings: widths count bytes (the columns line up
/// for ASCII text), and text already as wide as the column or wider is returned unchanged.

#include <cstddef>
#include <string>
#include <string_view>

namespace volcomp::format {

/// printf "%-*s": `text` followed by spaces up to `width` bytes.
std::string padRight(std::string_view text, std::size_t width);

/// printf "%*s": spaces up to `width` bytes, then `text`.
std::string padLeft(std::string_view text, std::size_t width);

}  // namespace volcomp::format
