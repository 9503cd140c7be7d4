#pragma once
// Shared by the verbs of the `volcomp` CLI: usage errors, number lists, number formatting.

#include <cstdint>
#include <ostream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "volcomp/model/types.hpp"

namespace volcomp::cli {

/// Exit statuses of the CLI (documented in --help and docs/cli.md).
inline constexpr int kExitOk = 0;
inline constexpr int kExitBadInput = 2;      ///< bad arguments or a bad model / CSV file
inline constexpr int kExitNotConverged = 3;  ///< results printed, but an offset did not converge

/// A bad argument found after CLI11 parsing (e.g. the wrong number of values in --at). main()
/// prints what() as the one line on stderr and exits with kExitBadInput.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// "1.5, -2,3e-2" -> {1.5, -2, 0.03}. Whitespace around values is ignored; every value must be a
/// finite number. Throws UsageError naming `option` on anything else or on a count other than
/// `count` (when count > 0).
std::vector<double> parseNumberList(std::string_view text, std::string_view option,
                                    std::size_t count);

/// "+,-,0" -> per-axis directions (+ positive, - negative, 0 or ? unknown). Throws UsageError.
model::Directions parseDirections(std::string_view text);

/// Shortest text that reads back to the same double (round trip, like %.17g but without the
/// noise digits).
std::string formatDouble(double value);
/// Appends formatDouble(value) to `out` (no allocation beyond out's growth).
void appendDouble(std::string& out, double value);

/// A length in mm as µm with 3 decimals (nm), printf "%.3f" of mm * 1000: "12.345".
std::string fixedMicrometres(double mm);

/// Comma-separated names of the axes whose bit is set in `mask` ("X, Z").
std::string axisList(std::uint8_t mask);

/// Splits at commas; each field trimmed.
std::vector<std::string_view> splitFields(std::string_view text);
/// A finite number filling the whole field (a leading '+' allowed). False otherwise.
bool parseDouble(std::string_view field, double& value);

/// Removes leading/trailing spaces, tabs and carriage returns.
std::string_view trim(std::string_view text);

}  // namespace volcomp::cli
