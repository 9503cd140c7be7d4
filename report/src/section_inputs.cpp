// Appendix "Inputs and method": the files, how the figures were computed, and what could not be
// shown.

#include "sections.hpp"
#include "volcomp/report/assets.hpp"

namespace volcomp::report::detail {

void inputsSection(Page& page, Context& context) {
  Table files({text("input"), text("file"), numberHtml("size"), text("modified")},
              "The files this report was built from.");
  for (const InputFile& f : context.inputs.files) {
    files.row({text(f.role), Cell{"<code>" + escape(f.path) + "</code>", false, {}},
               numberHtml(std::to_string(f.bytes) + "&#8239;B"), text(f.modified)});
  }
  std::string body = files.html();
  std::string method =
      "Errors are evaluated with the exact rigid-body model of volcomp (ISO 230-1 components, "
      "E = actual − nominal tool-tip position in the workpiece frame), in µm and µrad.";
  if (context.model != nullptr) {
    method += " Component curves: " + std::to_string(context.options.curveSamples) +
              " points per axis. Maps: about " + std::to_string(context.options.mapResolution) +
              " cells along the longer side of each plane, evaluated at the cell centres. Volume "
              "figures: an 11 × 11 × 11 grid over the working volume, corners included.";
  }
  method += " Charts are drawn in the browser by Vega " + escape(std::string(vegaVersion())) +
            ", which this file contains: it needs no network.";
  body += paragraph(method);
  Notes all = context.inputs.notes;
  all.insert(all.end(), context.notes.begin(), context.notes.end());
  if (!context.inputs.calibration) all.push_back("no calibration report given (--calibration)");
  if (context.inputs.iso.empty()) all.push_back("no ISO 230-2 result given (--iso230-2)");
  if (!context.inputs.run) all.push_back("no compensation run given (--run)");
  body += "<h3 id=\"inputs-notes\">Not shown</h3>\n<ul>";
  for (const std::string& n : all) body += "<li>" + escape(n) + "</li>";
  body += "</ul>\n";
  page.section("inputs", "Inputs and method", std::move(body));
}

}  // namespace volcomp::report::detail
