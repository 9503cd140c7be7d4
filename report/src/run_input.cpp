// Readers of a compensation run: volcomp-sim's report line, its --record CSV, and JSON files.

#include <cmath>
#include <fstream>
#include <sstream>

#include "json_fields.hpp"
#include "volcomp/config/config_error.hpp"
#include "volcomp/report/inputs.hpp"

namespace volcomp::report {
namespace {

using detail::Fields;
using nlohmann::json;

ErrorStats readStats(Fields& fields) {
  ErrorStats stats;
  stats.rmsBefore = fields.number("rms_uncompensated_um");
  stats.rmsAfter = fields.number("rms_compensated_um");
  stats.maxBefore = fields.number("max_uncompensated_um");
  stats.maxAfter = fields.number("max_compensated_um");
  return stats;
}

void readErrorStatistics(const json& source, const std::string& file, const std::string& path,
                         RunSummary& run, Notes& notes) {
  Fields fields(source, file, path, notes);
  run.total = readStats(fields);
  if (const json* axes = fields.object("axes")) {
    const char* names[3] = {"X", "Y", "Z"};
    Fields perAxis(*axes, file, fields.path("axes"), notes);
    for (int k = 0; k < 3; ++k) {
      if (const json* axis = perAxis.object(names[k])) {
        Fields a(*axis, file, perAxis.path(names[k]), notes);
        run.axes[static_cast<std::size_t>(k)] = readStats(a);
      }
    }
  }
  if (const auto duration = fields.number("duration_s")) run.durationS = duration;
  if (const auto samples = fields.integer("samples")) run.samples = samples;
}

}  // namespace

json readJsonFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw config::ConfigError(path, "", "cannot open the file");
  std::ostringstream text;
  text << in.rdbuf();
  try {
    return json::parse(text.str());
  } catch (const json::parse_error& e) {
    throw config::ConfigError(path, "", std::string("not valid JSON: ") + e.what());
  }
}

RunSummary readRunSummary(const json& document, const std::string& file, Notes& notes) {
  if (!document.is_object()) throw config::ConfigError(file, "", "expected a JSON object");
  if (!document.contains("rms_uncompensated_um") && !document.contains("compensating")) {
    throw config::ConfigError(file, "rms_uncompensated_um",
                              "expected the report line of volcomp-sim (rms_uncompensated_um, "
                              "rms_compensated_um, ...)");
  }
  RunSummary run;
  run.file = file;
  Fields top(document, file, "", notes);
  // Shown through readErrorStatistics.
  for (const char* key : {"rms_uncompensated_um", "rms_compensated_um", "max_uncompensated_um",
                          "max_compensated_um", "axes", "duration_s", "samples"}) {
    top.skip(key);
  }
  readErrorStatistics(document, file, "", run, notes);
  if (const json* compensating = top.object("compensating")) {
    // The demo's snapshot before the daemon's ramp-out: the error while compensating.
    readErrorStatistics(*compensating, file, "compensating", run, notes);
    run.whileCompensating = true;
  }
  run.writes = top.integer("writes");
  run.partialWrites = top.integer("partial_writes");
  run.limiterViolations = top.integer("limiter_violations");
  run.sessions = top.integer("sessions");
  run.positionSemantics = top.text("position_semantics");
  const std::vector<double> applied = top.numbers("applied_offset_mm");
  if (applied.size() == 3) run.appliedOffsetMm = {applied[0], applied[1], applied[2]};
  if (const json* daemon = top.object("daemon")) {
    Fields d(*daemon, file, "daemon", notes);
    run.daemonCycles = d.integer("cycles");
    run.daemonOverruns = d.integer("overruns");
    run.daemonExitStatus = d.integer("exit_status");
  }
  run.otherFields = top.unread();
  return run;
}

RunSummary loadRunSummary(const std::string& path, Notes& notes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw config::ConfigError(path, "", "cannot open the file");
  std::string line, last, all;
  while (std::getline(in, line)) {
    all += line + '\n';
    if (!line.empty() && line.front() == '{') last = line;
  }
  // One JSON document (pretty-printed or not), or the last report line of a captured stdout.
  json document = json::parse(all, nullptr, false);
  if (document.is_discarded()) {
    document = json::parse(last, nullptr, false);
    if (last.empty() || document.is_discarded()) {
      throw config::ConfigError(path, "", "expected volcomp-sim's JSON report line");
    }
  }
  return readRunSummary(document, path, notes);
}

std::vector<RecordedWrite> loadRecordedWrites(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw config::ConfigError(path, "", "cannot open the file");
  std::string line;
  if (!std::getline(in, line) || line.rfind("t_s,offset_x_mm,offset_y_mm,offset_z_mm", 0) != 0) {
    throw config::ConfigError(path, "line 1",
                              "expected the header of volcomp-sim --record "
                              "(t_s,offset_x_mm,offset_y_mm,offset_z_mm,...,violation)");
  }
  std::vector<std::string> header;
  {
    std::stringstream fields(line);
    for (std::string field; std::getline(fields, field, ',');) header.push_back(field);
  }
  std::size_t violationColumn = header.size();
  for (std::size_t i = 0; i < header.size(); ++i) {
    if (header[i] == "violation") violationColumn = i;
  }
  std::vector<RecordedWrite> writes;
  for (int number = 2; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    std::vector<std::string> fields;
    std::stringstream row(line);
    for (std::string field; std::getline(row, field, ',');) fields.push_back(field);
    RecordedWrite write;
    try {
      if (fields.size() < 4) throw std::invalid_argument("short row");
      write.tS = std::stod(fields[0]);
      for (std::size_t k = 0; k < 3; ++k) write.offsetMm[k] = std::stod(fields[k + 1]);
      if (violationColumn < fields.size()) write.violation = fields[violationColumn] != "0";
    } catch (const std::exception&) {
      throw config::ConfigError(path, "line " + std::to_string(number),
                                "expected t_s and three offsets (numbers)");
    }
    writes.push_back(write);
  }
  return writes;
}

}  // namespace volcomp::report
