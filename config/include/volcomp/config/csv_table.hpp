#pragma once
/// The one reader for every CSV file volcomp takes in (points to evaluate, calibration
/// measurements, planning candidates, device readings). What it accepts:
///
/// - Lines starting with '#' (after leading blanks) and blank lines are skipped anywhere; a UTF-8
///   byte-order mark before the first line is ignored; CRLF line ends are accepted.
/// - The first other line is the header: column names in any order, case-insensitive, blanks
///   around names ignored, blanks and hyphens inside a name read as '_' ("Run Number" is
///   run_number). A schema may give a column alternative names (aliases: "nominal" for target).
/// - Fields are separated by commas. When the header holds ';' and no ',', the file is
///   semicolon-separated (as spreadsheets and laser software in German or French locales write
///   it) and numbers take a decimal comma ("12,5"; a decimal point is accepted too).
/// - Units: every Length or Angle column may carry its unit in the header, written `x_mm`,
///   `x [mm]`, `x (mm)` or `x mm`. Length units: mm, um (also µm, micron), nm, m, in (also inch);
///   angle units: rad, mrad, urad (also µrad), arcsec, deg. A bare name means mm for lengths and
///   rad for angles (so `x,y,z,ex,ey,ez` is read as mm, as always), unless the schema sets
///   lengthUnitRequired: then a bare length column is refused. Values are converted on reading:
///   number() returns mm and rad. Number, Text and Direction columns take no unit.
/// - A field may be quoted ("..." with "" for a quote), so that a direction such as "+,-,+" fits
///   in one field.
/// - Unknown, duplicated or missing required columns, a column group given in part (tx without
///   ty, tz), rows with another field count than the header, and values that are not finite
///   numbers are rejected with a ConfigError whose key path is "line N" or "line N, column NAME".
///   A schema with acceptOtherColumns takes unknown columns (and names with an unknown unit
///   suffix, such as temp_c) as not read and lists them in otherColumns(); its rows may then have
///   more fields than the header. An input without a header throws CsvNoHeader.
///
/// Reading is streaming (one row at a time, through LineReader: a line is at most 1 MiB) so that
/// files of millions of points are not held in memory; values are converted only when asked for.

#include <cstddef>
#include <fstream>
#include <initializer_list>
#include <istream>
#include <string>
#include <string_view>
#include <vector>

#include "volcomp/config/config_error.hpp"
#include "volcomp/config/text_input.hpp"
#include "volcomp/model/types.hpp"

namespace volcomp::config {

/// What a column holds: it decides the accepted unit suffixes and the default unit.
enum class CsvQuantity {
  Length,     ///< mm by default; suffixes mm, um, nm
  Angle,      ///< rad by default; suffixes rad, mrad, urad, arcsec, deg
  Number,     ///< a plain number, no suffix (weights, joint values in their own units)
  Direction,  ///< direction of travel per axis: "+-+", "+,-,+" (quoted), "0" or "?" = unknown
  Text,       ///< any text, read with field() (names, labels, symbols); no unit
};

struct CsvColumn {
  std::string name;  ///< lower case, without unit suffix
  CsvQuantity quantity = CsvQuantity::Number;
  bool required = false;
  /// Other names of the column in a header (lower case, '_' for blanks); `name` stays the one
  /// to ask the reader for.
  std::vector<std::string> aliases;
};

struct CsvSchema {
  std::vector<CsvColumn> columns;
  /// Columns that must come together or not at all, e.g. {"tx", "ty", "tz"}.
  std::vector<std::vector<std::string>> groups;
  /// Names accepted in the header and not read (e.g. another tool's output columns).
  std::vector<std::string> ignored;
  /// A Length column without a unit in the header is refused instead of read as mm (for files
  /// from instruments, where a wrong guess of the unit would go unnoticed).
  bool lengthUnitRequired = false;
  /// Columns the schema does not know are accepted, not read, and listed by otherColumns().
  bool acceptOtherColumns = false;

  /// Adds columns of one quantity; returns *this for chaining.
  CsvSchema& add(std::initializer_list<const char*> names, CsvQuantity quantity,
                 bool required = false);
  /// Adds optional columns that come together (also registered as a group).
  CsvSchema& addGroup(std::initializer_list<const char*> names, CsvQuantity quantity);
  CsvSchema& ignore(std::initializer_list<const char*> names);
  /// Gives the column `name` (added before) alternative header names.
  CsvSchema& alias(const char* name, std::initializer_list<const char*> aliases);
};

/// Thrown for an input without a header line (empty, or only comments and blank lines).
class CsvNoHeader : public ConfigError {
 public:
  using ConfigError::ConfigError;
};

/// The columns of a file of positions (points to evaluate or predict at, planning candidates):
/// x,y,z (lengths, required), tx,ty,tz (tool offset, together or not at all), direction.
CsvSchema positionsSchema();

/// Streaming reader over a CSV text with a header (see the file comment).
class CsvReader {
 public:
  /// Reads up to and including the header. Throws ConfigError (file, "line N", what) for a bad
  /// header and for an input without one.
  CsvReader(std::istream& input, std::string file, CsvSchema schema);

  /// Opens `path` (openTextFile: throws ConfigError(path, "", why) for a missing file, a
  /// directory, ...).
  static std::ifstream open(const std::string& path);

  const std::string& file() const noexcept { return file_; }
  /// Column index of `name` (lower case, no suffix), or -1 when the header does not have it.
  int column(std::string_view name) const noexcept;
  bool has(std::string_view name) const noexcept { return column(name) >= 0; }
  /// Header names (as written) that no schema column took, when the schema accepts other
  /// columns; empty names are not listed.
  const std::vector<std::string>& otherColumns() const noexcept { return other_; }
  /// Header text of a column as written (e.g. "ex_um"), for messages.
  const std::string& headerName(int column) const;
  /// The header's column names as written, joined by the file's delimiter.
  std::string headerText() const;

  /// Advances to the next data row; false at the end of the input. Throws ConfigError for a row
  /// whose field count differs from the header's, or when reading fails.
  bool next();
  /// Line number (1-based) of the current row, or of the header before the first next().
  std::size_t line() const noexcept { return line_; }
  /// Value of a column of the current row in mm / rad (Length / Angle) or as written (Number);
  /// a decimal comma is read in a semicolon-separated file.
  /// Throws ConfigError at "line N, column NAME" when it is not a finite number.
  double number(int column) const;
  double number(std::string_view name) const { return number(requiredColumn(name)); }
  /// Directions of a Direction column (one per axis X, Y, Z).
  model::Directions directions(int column) const;
  /// The raw text of a field of the current row (trimmed, unquoted).
  std::string_view field(int column) const;

  /// Throws ConfigError(file, "line N, column NAME", message) for the current row.
  [[noreturn]] void fail(int column, const std::string& message) const;
  /// Throws ConfigError(file, "line N", message) for the current row.
  [[noreturn]] void fail(const std::string& message) const;

 private:
  struct Bound {
    int schemaIndex = -1;  ///< index into schema_.columns, -1 for an ignored column
    double factor = 1.0;   ///< to mm / rad
    std::string written;   ///< as in the header
  };
  bool readLine();
  void bindHeaderField(std::size_t column, std::vector<std::string>& seen);
  void splitCurrent();
  void readHeader();
  int requiredColumn(std::string_view name) const;

  LineReader lines_;
  std::string file_;
  CsvSchema schema_;
  std::vector<Bound> header_;
  std::vector<int> columnOfSchema_;  ///< schema index -> header column (-1 absent)
  std::vector<std::string> other_;
  char delimiter_ = ',';
  bool decimalComma_ = false;
  std::string text_;
  std::vector<std::string_view> fields_;
  std::vector<std::string> unquoted_;  ///< storage for fields that had quotes
  std::size_t line_ = 0;
};

/// Directions from text such as "+-+", "+,-,+", "+ - 0" (one symbol per axis: + positive,
/// - negative, 0 or ? unknown). Returns false when the text is not that.
bool parseDirectionsText(std::string_view text, model::Directions& directions) noexcept;

}  // namespace volcomp::config
