// The sensitivity matrix of the 3-axis identification on the model's batch path.
//
// The same maths as observationJacobian() (sensitivities of the predicted rows to each motion
// value that carries parameters, times the basis values; location errors through the translations
// of their axis), but the sensitivities come from whole models evaluated at all points of one
// tool at once: the identified model at p, and for each such motion value a copy whose function
// is shifted by a constant step (+-h for angles, central; +h for translations, on which the
// position depends affinely). evaluateBatch composes four points per SIMD register, which is
// where a linear identification spent a fifth of its time point by point.

#include <algorithm>
#include <cmath>

#include "machine_identification.hpp"
#include "volcomp/model/so3.hpp"

namespace volcomp::calibration::detail {
namespace {

// The function plus a constant: every basis the model has is exact under it.
void shift(model::ErrorFunctionSpec& function, double step) {
  if (double* constant = std::get_if<double>(&function)) {
    *constant += step;
  } else if (auto* polynomial = std::get_if<model::PolynomialSpec>(&function)) {
    if (polynomial->coefficients.empty()) polynomial->coefficients.push_back(0.0);
    polynomial->coefficients[0] += step;
  } else {
    auto& table = std::get<model::TableSpec>(function);
    for (double& v : table.values) v += step;
    for (double& v : table.valuesNegative) v += step;
  }
}

}  // namespace

void MachineIdentification::jacobian(const Eigen::VectorXd& p, Eigen::MatrixXd& jacobian) const {
  // The instrument frame turns every predicted row; the point-by-point path handles it.
  if (frameFirst_ >= 0) {
    ResidualProblem::jacobian(p, jacobian);
    return;
  }
  const int n = parameterCount_;
  const int rows = residualsPerObservation();
  jacobian.setZero(rowCount(), n);
  const model::MachineModelSpec identified = identifiedSpec(p);

  // Per location parameter: d(direction of its axis)/d(angle), the same for every point.
  std::vector<Eigen::Vector3d> locationDerivative;
  for (const LocationParameter& location : locations_) {
    locationDerivative.push_back(locationDirectionDerivative(location, p.data()));
  }

  model::Workspace ws;
  for (const ToolGroup& group : toolGroups_) {
    const std::size_t count = group.points.size();
    std::vector<model::PointError> centre(count), plus(count), minus(count);
    model::MachineModelSpec spec = identified;
    spec.toolMm = group.toolMm;
    const auto evaluate = [&](const model::MachineModelSpec& s,
                              std::vector<model::PointError>& out) {
      const model::MachineModel m(s);
      model::evaluateBatch(m, ws, group.qMm, out, model::EvalMode::Exact, group.directions);
    };
    evaluate(spec, centre);
    for (int c : needed_) {
      const bool rotation = c % 6 >= 3;
      const double step = rotation ? kRotationStepRad : kTranslationStepMm;
      model::MachineModelSpec shifted = spec;
      shift(shifted.motion[static_cast<std::size_t>(c)], step);
      evaluate(shifted, plus);
      if (rotation) {
        shifted = spec;
        shift(shifted.motion[static_cast<std::size_t>(c)], -step);
        evaluate(shifted, minus);
      }
      const Component* component = nullptr;
      int basisColumn = 0;
      for (const Component& k : components_) {
        if (k.motion == c) {
          component = &k;
          break;
        }
        basisColumn += k.count;
      }
      for (std::size_t g = 0; g < count; ++g) {
        const int i = group.points[g];
        std::array<double, 6> sensitivity{};
        const model::PointError& low = rotation ? minus[g] : centre[g];
        const double width = rotation ? 2.0 * step : step;
        for (int t = 0; t < 3; ++t) {
          sensitivity[static_cast<std::size_t>(t)] = (plus[g].errorMm[t] - low.errorMm[t]) / width;
          sensitivity[static_cast<std::size_t>(3 + t)] =
              (plus[g].angularErrorRad[t] - low.angularErrorRad[t]) / width;
        }
        const Eigen::Index firstRow = static_cast<Eigen::Index>(i) * rows;
        if (component != nullptr) {
          const double* basis =
              basis_.data() + static_cast<std::size_t>(i) * basisWidth_ + basisColumn;
          for (int j = 0; j < component->count; ++j) {
            for (int row = 0; row < rows; ++row) {
              jacobian(firstRow + row, component->first + j) =
                  sensitivity[static_cast<std::size_t>(row)] * basis[j];
            }
          }
        }
        if (rotation) continue;
        // A location error of this axis moves the carriage along q_K (d_K(angles) - d_K).
        for (std::size_t l = 0; l < locations_.size(); ++l) {
          const int axis = locations_[l].index / 3;
          if (c / 6 != axis) continue;
          const double lever =
              locationDerivative[l][c % 6] * points_[static_cast<std::size_t>(i)].qMm[axis];
          for (int row = 0; row < rows; ++row) {
            jacobian(firstRow + row, locations_[l].parameter) +=
                sensitivity[static_cast<std::size_t>(row)] * lever;
          }
        }
      }
    }
  }
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const Eigen::Index firstRow = static_cast<Eigen::Index>(i) * rows;
    jacobian.middleRows(firstRow, 3) *= points_[i].sqrtWeight;
    if (rows > 3) {
      jacobian.middleRows(firstRow + 3, 3) *= points_[i].sqrtWeight * options_.angleScaleMm;
    }
  }
  if (priorRows_ > 0) {
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> prior(priorRows_, n);
    priorJacobian(p.data(), prior.data());
    jacobian.bottomRows(priorRows_) = prior;
  }
}

}  // namespace volcomp::calibration::detail
