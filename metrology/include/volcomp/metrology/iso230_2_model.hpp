#pragma once
/// The model table an ISO 230-2 evaluation gives: the positioning component EKK of the measured
/// axis K as a bidirectional table (`values` from x̄_i↑, `values_negative` from x̄_i↓, linear
/// interpolation between the targets).
///
/// Sign (the model file's definition, docs/iso230-2.md "From the evaluation to a model"): EKK is
/// the translation error of axis K's own carriage along K. A laser reading set to count with the
/// commanded coordinate measures the tool relative to the workpiece, which is what the volumetric
/// error E = p - p0 is. A tool-side carriage displaced by EKK moves the tool by +EKK, so there
/// EKK = +x̄. A workpiece-side carriage (the table) displaced by EKK moves the workpiece by +EKK,
/// which moves the tool relative to the workpiece by -EKK, so there EKK = -x̄. With only this
/// component in a model, evaluate() along axis K returns E_K = x̄ at the targets in both cases (a
/// test checks it for every topology). The measured deviation also holds the Abbe effect of the
/// axis' angular errors at the line where the laser beam ran: put it in a model without those
/// angles, or with angles measured at that same line, not on top of angles that already explain it.

#include "volcomp/metrology/iso230_2.hpp"
#include "volcomp/model/error_function.hpp"
#include "volcomp/model/topology.hpp"

namespace volcomp::metrology {

/// +1 when `axis` carries the tool side of `topology`, -1 when it carries the workpiece side:
/// the factor from a measured deviation x̄ (tool relative to workpiece) to the axis' own EKK.
double deviationToComponentSign(const model::Topology& topology, model::Axis axis) noexcept;

/// EKK of the evaluated axis as a table in mm: positions = targets, values = sign · x̄_i↑,
/// valuesNegative = sign · x̄_i↓, linear, where sign = deviationToComponentSign(topology, axis).
model::TableSpec positioningComponent(const Iso230Result& result, const model::Topology& topology,
                                      model::Axis axis);

}  // namespace volcomp::metrology
