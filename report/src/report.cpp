#include "volcomp/report/report.hpp"

#include <variant>

#include "sections.hpp"

namespace volcomp::report {

RenderedReport renderReport(const ReportInputs& inputs, const ReportOptions& options) {
  std::optional<model::MachineModel> machine;
  if (const auto* spec = std::get_if<model::MachineModelSpec>(&inputs.model.spec)) {
    machine.emplace(*spec);
  }
  detail::Context context{inputs, options, machine ? &*machine : nullptr, {}, {}, {}, {}};
  if (machine) {
    context.volume = workingVolume(*machine);
    model::Workspace ws;
    context.volumeStats = volumeStatistics(*machine, ws, context.volume);
  }
  if (machine && inputs.measurements) {
    std::optional<model::MachineModel> before;
    if (inputs.calibrationTemplate) {
      if (const auto* spec =
              std::get_if<model::MachineModelSpec>(&inputs.calibrationTemplate->spec)) {
        before.emplace(*spec);
      }
    }
    context.residuals = pointResiduals(before ? &*before : nullptr, *machine, *inputs.measurements);
  }

  detail::Page page;
  detail::modelSection(page, context);
  detail::mapsSection(page, context);
  detail::calibrationSection(page, context);
  detail::isoSection(page, context);
  detail::runSection(page, context);
  detail::inputsSection(page, context);

  RenderedReport rendered;
  rendered.html = page.document(options.title + " — " + detail::machineName(context),
                                detail::headerHtml(context), detail::summaryHtml(context),
                                detail::footerHtml(context));
  rendered.sections = page.sectionList();
  rendered.charts = page.charts();
  rendered.notes = inputs.notes;
  rendered.notes.insert(rendered.notes.end(), context.notes.begin(), context.notes.end());
  return rendered;
}

}  // namespace volcomp::report
