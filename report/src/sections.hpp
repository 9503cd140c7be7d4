#pragma once
// The report's sections, each from the inputs it needs; report.cpp calls them in page order.

#include <optional>
#include <string>

#include "page.hpp"
#include "volcomp/report/calibration_views.hpp"
#include "volcomp/report/model_views.hpp"
#include "volcomp/report/report.hpp"

namespace volcomp::report::detail {

struct Context {
  const ReportInputs& inputs;
  const ReportOptions& options;
  /// The 3-axis model, or null for a D-H chain.
  const model::MachineModel* model = nullptr;
  WorkingVolume volume;
  std::optional<VolumeStatistics> volumeStats;
  std::optional<PointResiduals> residuals;
  /// What a section could not show (added to the inputs' notes in the appendix).
  Notes notes;
};

/// The machine's name as the report shows it.
std::string machineName(const Context& context);
/// "850 × 500 × 500 mm" (the working volume), with "(no travel given)" where it is not the travel.
std::string volumeText(const Context& context);

std::string headerHtml(const Context& context);
/// The summary a manager reads first: a few sentences, the headline figures, the facts.
std::string summaryHtml(const Context& context);
std::string footerHtml(const Context& context);

void modelSection(Page& page, Context& context);
void mapsSection(Page& page, Context& context);
void calibrationSection(Page& page, Context& context);
void isoSection(Page& page, Context& context);
void runSection(Page& page, Context& context);
void inputsSection(Page& page, Context& context);

}  // namespace volcomp::report::detail
