#pragma once
// Vega 5 specifications of the report's charts, built from the numbers of model_views,
// calibration_views and the inputs. Shared look (fonts, colours of axis lines) comes from the
// config in report.js; every axis carries its unit. Values are rounded for the page (positions
// to 1 µm, errors to 0.1 nm or 1e-4 µrad), far below what a chart can show.

#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "volcomp/model/grid.hpp"
#include "volcomp/report/calibration_views.hpp"
#include "volcomp/report/inputs.hpp"
#include "volcomp/report/model_views.hpp"

namespace volcomp::report::charts {

using Json = nlohmann::json;

/// `value` rounded to a multiple of `quantum` (a JSON number).
Json rounded(double value, double quantum);

/// The colour of an error direction: X and rotations about X blue, Y orange, Z green.
const char* axisColour(int axis);

/// The components of one axis and one kind (translations in µm or rotations in µrad) against the
/// axis position; bidirectional tables as two curves (↑ solid, ↓ dashed); table nodes marked.
Json componentChart(std::span<const ComponentView* const> components, const std::string& axis,
                    bool angular);

/// Colour and arrow scales shared by every map of a report, so that planes compare at a glance.
struct MapScales {
  double magnitudeMaxUm = 1.0;
  double outOfPlaneMaxUm = 1.0;
  double inPlaneMaxUm = 1.0;
  double arrowPxPerUm = 1.0;  ///< arrow length per µm of in-plane error
};
/// Size of a map's smallest cell on the page (px), to choose arrowPxPerUm.
double mapCellPx(const ErrorMap& map);
/// |E| as colour with the in-plane part of E as arrows.
Json magnitudeMap(const ErrorMap& map, const MapScales& scales);
/// The component of E normal to the plane (Bulla Ramos et al.'s deflection-over-the-table view).
Json outOfPlaneMap(const ErrorMap& map, const MapScales& scales);
/// A 2-D grid of the model (values in µm over its two axes, node-centred cells).
Json gridChart(const model::GridSpec& grid);

/// |r| per measured point before and after the fit (log scale).
Json residualsChart(const PointResiduals& residuals);
/// Histogram of `valuesUm`, about 30 bins.
Json histogramChart(std::span<const double> valuesUm, const std::string& title,
                    const std::string& colour);
/// The correlation matrix (row-major n x n, NaN where undefined) as a heat map, lower triangle.
Json correlationChart(const std::vector<std::string>& names, std::span<const double> matrix);

/// ISO 230-2: x̄↑ and x̄↓ with ±2s bands, x̄ and the runs against target position.
Json isoChart(const IsoAxis& evaluated);
/// RMS of the tool-tip error without and with compensation per axis and for |e|.
Json runBarChart(const RunSummary& run);
/// Offsets the controller received over time (µm per axis), violations marked.
Json offsetsChart(std::span<const RecordedWrite> writes);

}  // namespace volcomp::report::charts
