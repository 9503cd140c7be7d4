#include "eval_points.hpp"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string_view>
#include <vector>

#include "cli_support.hpp"
#include "volcomp/config/config_error.hpp"

namespace volcomp::cli {
namespace {

constexpr std::size_t kProgressEvery = 100000;
constexpr std::size_t kFlushBytes = 1 << 20;

std::string lineKey(std::size_t line) {
  return "line " + std::to_string(line);
}

std::string shown(std::string_view line) {
  std::string s(trim(line));
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return "\"" + s + "\"";
}

bool isHeader(std::string_view line) {
  if (line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);  // UTF-8 BOM from spreadsheets
  const std::vector<std::string_view> fields = splitFields(line);
  if (fields.size() != 3) return false;
  const char* names[3] = {"x", "y", "z"};
  for (std::size_t i = 0; i < 3; ++i) {
    if (fields[i].size() != 1 || (fields[i][0] | 0x20) != names[i][0]) return false;
  }
  return true;
}

class OutputFile {
 public:
  explicit OutputFile(const std::string& path) : path_(path), stream_(path, std::ios::binary) {
    if (!stream_) throw config::ConfigError(path, "", "cannot open for writing");
    buffer_.reserve(kFlushBytes + 4096);
  }
  ~OutputFile() {
    if (!committed_) {
      stream_.close();
      std::error_code ignored;
      std::filesystem::remove(path_, ignored);
    }
  }
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  std::string& buffer() { return buffer_; }
  void flushIfLarge() {
    if (buffer_.size() >= kFlushBytes) flush();
  }
  void commit() {
    flush();
    stream_.close();
    if (!stream_) throw config::ConfigError(path_, "", "write failed");
    committed_ = true;
  }

 private:
  void flush() {
    stream_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
    if (!stream_) throw config::ConfigError(path_, "", "write failed");
    buffer_.clear();
  }
  std::string path_;
  std::ofstream stream_;
  std::string buffer_;
  bool committed_ = false;
};

}  // namespace

PointsSummary evaluatePointsFile(const model::MachineModel& model,
                                 const model::Directions& directions, model::EvalMode mode,
                                 const std::string& inPath, const std::string& outPath) {
  std::ifstream in(inPath, std::ios::binary);
  if (!in) throw config::ConfigError(inPath, "", "cannot open file");
  std::string line;
  std::size_t lineNumber = 0;
  bool haveHeader = false;
  while (!haveHeader && std::getline(in, line)) {
    ++lineNumber;
    if (trim(line).empty()) continue;
    if (!isHeader(line)) {
      throw config::ConfigError(inPath, lineKey(lineNumber),
                                "expected the header x,y,z, got " + shown(line));
    }
    haveHeader = true;
  }
  if (!haveHeader)
    throw config::ConfigError(inPath, "", "expected the header x,y,z, got an empty file");

  OutputFile out(outPath);
  out.buffer() += "x,y,z,ex,ey,ez,ea,eb,ec,ox,oy,oz\n";
  const bool progress = isatty(STDERR_FILENO) == 1;
  model::Workspace ws;
  model::OffsetOptions offsetOptions;
  offsetOptions.mode = mode;
  PointsSummary summary;
  while (std::getline(in, line)) {
    ++lineNumber;
    if (trim(line).empty()) continue;
    const std::vector<std::string_view> fields = splitFields(line);
    double q[3] = {0, 0, 0};
    bool ok = fields.size() == 3;
    for (std::size_t i = 0; ok && i < 3; ++i) ok = parseDouble(fields[i], q[i]);
    if (!ok) {
      throw config::ConfigError(inPath, lineKey(lineNumber),
                                "expected three finite numbers x,y,z (mm), got " + shown(line));
    }
    const Eigen::Vector3d qMm(q[0], q[1], q[2]);
    const model::PointError e = model::evaluate(model, ws, qMm, directions, mode);
    const model::OffsetSolution o = model::solveOffset(model, ws, qMm, directions, offsetOptions);
    ++summary.rows;
    if (e.clampedAxes != 0 && summary.clampedRows++ == 0) summary.firstClampedLine = lineNumber;
    if (!o.converged && summary.notConvergedRows++ == 0) {
      summary.firstNotConvergedLine = lineNumber;
    }
    std::string& b = out.buffer();
    for (double v : {q[0], q[1], q[2], e.errorMm.x(), e.errorMm.y(), e.errorMm.z(),
                     e.angularErrorRad.x(), e.angularErrorRad.y(), e.angularErrorRad.z(),
                     o.offsetMm.x(), o.offsetMm.y(), o.offsetMm.z()}) {
      appendDouble(b, v + 0.0);  // + 0.0 turns -0 into 0
      b += ',';
    }
    b.back() = '\n';
    out.flushIfLarge();
    if (progress && summary.rows % kProgressEvery == 0) {
      std::cerr << "\rvolcomp eval: " << summary.rows << " rows" << std::flush;
    }
  }
  if (in.bad()) throw config::ConfigError(inPath, lineKey(lineNumber + 1), "read failed");
  out.commit();
  if (progress && summary.rows >= kProgressEvery) {
    std::cerr << "\rvolcomp eval: " << summary.rows << " rows, done\n";
  }
  return summary;
}

}  // namespace volcomp::cli
