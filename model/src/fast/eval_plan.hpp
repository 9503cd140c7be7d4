#pragma once
// Flattened, immutable evaluation data of a MachineModel, laid out for the per-point hot path:
// per axis the travel limits and the constant components, and the tables grouped by their node
// positions so that one lookup (interval index and fraction) serves every table of the group,
// with the group's coefficients interleaved per interval so that they are read from one place.

#include <array>
#include <memory>
#include <vector>

#include "piecewise.hpp"
#include "volcomp/model/machine_model.hpp"

namespace volcomp::model::detail {

/// The per-point entry points of one instruction set (machine_model.cpp, eval_kernels.inc), with
/// the semantics of evaluateMotion, composeError, evaluate (with a tool offset) and solveOffset.
struct Kernels {
  std::uint8_t (*motion)(const MachineModel&, const Eigen::Vector3d&, const Directions&,
                         MotionValues&) noexcept;
  PointError (*compose)(const MachineModel&, Workspace&, const Eigen::Vector3d&,
                        const MotionValues&, const Eigen::Vector3d&, EvalMode) noexcept;
  PointError (*evaluate)(const MachineModel&, Workspace&, const Eigen::Vector3d&,
                         const Eigen::Vector3d&, const Directions&, EvalMode) noexcept;
  OffsetSolution (*solve)(const MachineModel&, Workspace&, const Eigen::Vector3d&,
                          const Directions&, const OffsetOptions&) noexcept;
  /// evaluateBatch: points, directions (the first `directionCount` given), results, count.
  void (*many)(const MachineModel&, Workspace&, const Eigen::Vector3d*, const Directions*,
               std::size_t, PointError*, std::size_t, EvalMode) noexcept;
  /// solveOffsetBatch, with the arguments of `many`.
  void (*solveMany)(const MachineModel&, Workspace&, const Eigen::Vector3d*, const Directions*,
                    std::size_t, OffsetSolution*, std::size_t, const OffsetOptions&) noexcept;
};

struct EvalPlan {
  /// Tables of one axis over the same node positions.
  struct Group {
    TableAxis axis;  // positions point into `data`
    int entryCount = 0;
    bool full = false;           // six entries holding slots 0..5 in order
    std::array<int, 6> slots{};  // MotionKind of each entry
    /// Per curve (Positive, Negative, Unknown): coefficient c_p of entry e on interval i at
    /// [(4 i + p) entryCount + e]. One-directional groups share one block for all three.
    std::array<const double*, 3> coefficients{};
  };
  struct Polynomial {
    int slot = 0;
    const double* coefficients = nullptr;  // c0 first
    int count = 0;
  };
  struct AxisPlan {
    double lowerMm = 0.0, upperMm = 0.0;  // travel, +-inf when unbounded
    std::array<double, 6> constants{};    // constant components (0 where a table/polynomial is)
    int groupBegin = 0, groupEnd = 0;
    bool allTabulated = false;      // one full group: `constants` need not be copied
    bool uniformTabulated = false;  // and its positions are uniform, no polynomials
    int polynomialBegin = 0, polynomialEnd = 0;
    double sign = 1.0;                           // +1 tool side, -1 workpiece side
    std::array<double, 3> direction{};           // d_K
    std::array<double, 3> directionMinusUnit{};  // d_K - e_K, full precision
  };

  /// The O(1) lookup of an axis whose six components are tables over one uniform grid, with
  /// everything it needs side by side (see `allUniform`).
  struct UniformAxis {
    double lowerMm = 0.0, upperMm = 0.0;  // travel, +-inf when unbounded
    double first = 0.0, invStep = 0.0;    // first node, intervals per mm
    double top = 0.0;                     // number of intervals
    int lastInterval = 0;
    std::array<const double*, 3> coefficients{};  // per curve, as in Group
  };

  std::array<AxisPlan, 3> axes;
  /// Every axis is uniformTabulated (the usual measured model): evaluation takes the unrolled
  /// lookup over `uniform`.
  bool allUniform = false;
  std::array<UniformAxis, 3> uniform{};
  /// Positions and coefficients; never resized after the build (the pointers above refer to it).
  std::vector<double> data;
  std::vector<Group> groups;
  std::vector<Polynomial> polynomials;
  /// Tool-side axes from the frame outward, and workpiece-side axes from the frame outward.
  std::array<int, 3> toolChain{};
  int toolCount = 0;
  std::array<int, 3> workpieceChain{};
  int workpieceCount = 0;
  /// The order of the three axes (tool side, then workpiece side, both from the frame outward)
  /// as a permutation index 2 A0 + (A1 < A0 ? A1 : A1 - 1), selecting the composition code
  /// compiled for this topology.
  int chainPermutation = 0;
  /// The kernels for the CPU the model was built on (AVX2 + FMA where available).
  const Kernels* kernels = nullptr;
};

/// The kernels for this CPU (kernels.cpp): AVX2 + FMA where the CPU has them and they were
/// compiled in, the baseline otherwise.
const Kernels& selectKernels() noexcept;

/// The kernels compiled for the compiler's baseline (SSE2 on x86-64, NEON on AArch64, scalar
/// code elsewhere), whatever the CPU: what CPUs without AVX2 run, exposed so that a test can
/// compare them with the dispatched set.
const Kernels& genericKernels() noexcept;

/// The plan of a model: tables grouped per axis, travel limits, the chain order; plan->kernels
/// is selectKernels(). d_K and d_K - e_K are the axis directions (the second at full precision).
std::shared_ptr<const EvalPlan> buildPlan(const MachineModelSpec& spec, const Topology& topology,
                                          const std::array<Eigen::Vector3d, 3>& direction,
                                          const std::array<Eigen::Vector3d, 3>& directionMinusUnit);

struct PlanAccess {
  static const EvalPlan& plan(const MachineModel& model) noexcept { return *model.plan_; }
};

}  // namespace volcomp::model::detail
