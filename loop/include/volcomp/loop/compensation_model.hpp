#pragma once
/// What the loop needs from a model: the compensation offset at a position, and the travel.
/// The loop holds a std::shared_ptr<CompensationModel>; a reload builds a new one off the hot
/// path and swaps the pointer between cycles. One instance is used by one thread at a time (it
/// owns its evaluation workspace).

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "volcomp/model/machine_model.hpp"
#include "volcomp/model/types.hpp"

namespace volcomp::loop {

/// Result of one offset evaluation.
struct ModelOffset {
  std::array<double, 3> offsetMm{};  ///< o(q) with p(q + o) = p0(q), mm, machine axes
  bool converged = false;
  std::uint8_t clampedAxes = 0;  ///< bit K: axis K outside travel, evaluated at the travel end
};

class CompensationModel {
 public:
  virtual ~CompensationModel() = default;
  /// Offset at positions qMm (mm) for the given directions. noexcept, allocation-free.
  virtual ModelOffset offset(const std::array<double, 3>& qMm,
                             const model::Directions& directions) noexcept = 0;
  /// Travel [min, max] per axis, mm; nullopt = unbounded.
  virtual const std::array<std::optional<std::array<double, 2>>, 3>& travelMm() const noexcept = 0;
  /// Human-readable name (the model's "name", else its file).
  virtual const std::string& name() const noexcept = 0;
};

/// A CompensationModel over volcomp::model::MachineModel and solveOffset (exact composition).
class MachineModelCompensation final : public CompensationModel {
 public:
  MachineModelCompensation(model::MachineModel model, std::string name);
  ModelOffset offset(const std::array<double, 3>& qMm,
                     const model::Directions& directions) noexcept override;
  const std::array<std::optional<std::array<double, 2>>, 3>& travelMm() const noexcept override {
    return model_.spec().travelMm;
  }
  const std::string& name() const noexcept override { return name_; }

 private:
  model::MachineModel model_;
  model::Workspace workspace_;
  std::string name_;
};

}  // namespace volcomp::loop
