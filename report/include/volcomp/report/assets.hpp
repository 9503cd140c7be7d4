#pragma once
/// What every report inlines, embedded into the library at build time (report/embed_assets.py):
/// the stylesheet, the script that draws the charts, and the Vega 5 runtime built from Debian's
/// libjs-vega with its licence text.

#include <span>
#include <string>
#include <string_view>

namespace volcomp::report {

/// report/assets/report.css.
const std::string& stylesheet();
/// report/assets/report.js: draws the charts; window.volcompReport.ready resolves when done.
const std::string& reportScript();
/// Vega's packages wrapped in a small loader; defines the global `vega` (parse, View).
const std::string& vegaRuntime();
/// The Debian package version of the embedded Vega, e.g. "5.22.1+ds+~3.1.0-4".
std::string_view vegaVersion() noexcept;

}  // namespace volcomp::report
