#pragma once
// Internal: what analyseCalibration computes after a fit for the report (predictions with their
// uncertainty, identified curves, what the data cover, held-out residuals).

#include <functional>
#include <memory>
#include <vector>

#include "volcomp/calibration/identification.hpp"
#include "volcomp/calibration/measurements.hpp"
#include "volcomp/calibration/report.hpp"

namespace volcomp::calibration::detail {

/// Builds the identification problem of a measurement set (same template and options).
using ProblemFactory =
    std::function<std::unique_ptr<IdentificationProblem>(const MeasurementSet& measurements)>;

/// Distinct tool offsets of the measurements (the template's tool when they give none).
std::vector<Eigen::Vector3d> distinctTools(const MeasurementSet& measurements,
                                           const Eigen::Vector3d& templateToolMm);

DataCoverage coverageOf(const MeasurementSet& measurements, const config::ModelDocument& document);

/// Fills errorMm, stdMm and determined of each point from the fit (qMm, toolMm, directions given).
void predictPoints(const IdentificationProblem& problem, const FitResult& fit,
                   std::vector<PointPrediction>& points);

/// The measured points as prediction points (tool: the measurement's or the template's).
std::vector<PointPrediction> measuredPoints(const MeasurementSet& measurements,
                                            const config::ModelDocument& document);

std::vector<SampledCurve> sampleCurves(const IdentificationProblem& problem, const FitResult& fit);

/// Residuals of `heldOut` with the fitted parameters.
ValidationResult validateWith(const ProblemFactory& factory, const MeasurementSet& heldOut,
                              const FitResult& fit);

/// k-fold cross-validation: the points are dealt into k folds (a fixed shuffle, so that runs
/// repeat), each fold is predicted by a fit to the others.
ValidationResult crossValidate(const ProblemFactory& factory, const MeasurementSet& measurements,
                               int folds, const SolveOptions& options);

}  // namespace volcomp::calibration::detail
