// Section "Compensation run": the true tool-tip error without and with live compensation, as
// volcomp-sim measured it, and the offsets the controller received.

#include "charts.hpp"
#include "sections.hpp"

namespace volcomp::report::detail {
namespace {

Cell optionalUm(const std::optional<double>& value, int decimals = 2) {
  return value ? number(*value, decimals, "µm") : text("–");
}

// The simulator's other counters in words; a key it adds later is shown as it is.
std::string figureName(const std::string& key) {
  static const std::pair<const char*, const char*> names[] = {
      {"offset_violations", "writes beyond max_offset"},
      {"rate_violations", "writes beyond max_rate"},
      {"first_violation", "first violation"},
      {"requests", "requests received"},
      {"requests_unanswered", "requests not answered"},
      {"exceptions_sent", "exception replies sent"},
      {"watchdog_trips", "controller watchdog trips"}};
  for (const auto& [k, name] : names) {
    if (key == k) return name;
  }
  return key;
}

Cell reductionCell(const ErrorStats& stats) {
  if (!stats.rmsBefore || !stats.rmsAfter || *stats.rmsBefore <= 0.0) return text("–");
  return number(100.0 * (1.0 - *stats.rmsAfter / *stats.rmsBefore), 1, "%");
}

}  // namespace

void runSection(Page& page, Context& context) {
  if (!context.inputs.run) return;
  const RunSummary& run = *context.inputs.run;
  std::string intro =
      "The tool-tip error of the simulated machine (its true error model) while "
      "the daemon compensated it live, from <code>" +
      escape(run.file) + "</code>";
  if (run.durationS) intro += ", " + fixed(*run.durationS, 1) + " s";
  if (run.samples) intro += ", " + std::to_string(*run.samples) + " samples";
  if (!run.positionSemantics.empty()) {
    intro += ", position semantics " + escape(run.positionSemantics);
  }
  intro += ".";
  if (run.whileCompensating) {
    intro +=
        " The error statistics were taken while compensating, before the daemon's stop "
        "ramped the offsets out.";
  }
  std::string body = paragraph(intro);
  body += page.chart("run-rms", charts::runBarChart(run),
                     "<b>RMS tool-tip error</b> without and with compensation, per direction and "
                     "for the 3-D error vector.");
  Table table({text(""), numberHtml("RMS without"), numberHtml("RMS with"),
               numberHtml("max without"), numberHtml("max with"), numberHtml("reduction (RMS)")},
              "True tool-tip error, µm.");
  const char* names[3] = {"X", "Y", "Z"};
  for (std::size_t k = 0; k < 3; ++k) {
    const ErrorStats& s = run.axes[k];
    if (!s.rmsBefore && !s.rmsAfter) continue;
    table.row({text(names[k]), optionalUm(s.rmsBefore), optionalUm(s.rmsAfter),
               optionalUm(s.maxBefore), optionalUm(s.maxAfter), reductionCell(s)});
  }
  table.row({text("|e| (3-D)"), optionalUm(run.total.rmsBefore), optionalUm(run.total.rmsAfter),
             optionalUm(run.total.maxBefore), optionalUm(run.total.maxAfter),
             reductionCell(run.total)});
  body += table.html();

  Table facts({text("figure"), numberHtml("value")}, "The run.");
  const auto count = [&](const char* name, const std::optional<std::int64_t>& value,
                         bool zeroIsGood = false) {
    if (!value) return;
    Cell cell = numberHtml(std::to_string(*value));
    if (zeroIsGood) cell.cssClass = *value == 0 ? "good" : "bad";
    facts.row({text(name), cell});
  };
  count("writes received by the controller", run.writes);
  count("partial writes", run.partialWrites);
  count("limiter violations", run.limiterViolations, true);
  count("client sessions", run.sessions);
  count("daemon cycles", run.daemonCycles);
  count("daemon overruns", run.daemonOverruns);
  count("daemon exit status", run.daemonExitStatus, true);
  if (run.appliedOffsetMm) {
    const auto& o = *run.appliedOffsetMm;
    facts.row({text("offsets applied at the end"),
               numberHtml(fixed(o[0] * kUmPerMm, 2) + ", " + fixed(o[1] * kUmPerMm, 2) + ", " +
                          fixed(o[2] * kUmPerMm, 2) + "&#8239;µm")});
  }
  for (const Figure& f : run.otherFields) {
    if (f.text.empty()) continue;
    facts.row({text(figureName(f.key)), numberHtml(escape(f.text))});
  }
  if (!facts.empty()) body += facts.html();

  if (!context.inputs.writes.empty()) {
    body += page.chart("run-offsets", charts::offsetsChart(context.inputs.writes),
                       "<b>Offsets written</b> to the controller over the run, µm per axis "
                       "(red lines: writes that broke the limits, if any).");
  }
  page.section("run", "Compensation run", std::move(body));
}

}  // namespace volcomp::report::detail
