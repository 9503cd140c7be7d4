#include "volcomp/model/machine_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>

#include "eval_plan.hpp"
#include "piecewise.hpp"
#include "simd.hpp"
#include "small_angle.hpp"
#include "volcomp/model/so3.hpp"

namespace volcomp::model {

namespace {

using detail::EvalPlan;

void requireFinite(const Eigen::Vector3d& v, const char* what) {
  if (!v.allFinite()) throw ModelError(std::string(what) + " holds a non-finite number");
}

std::shared_ptr<const EvalPlan> buildPlan(
    const MachineModelSpec& spec, const Topology& topology,
    const std::array<Eigen::Vector3d, 3>& direction,
    const std::array<Eigen::Vector3d, 3>& directionMinusUnit) {
  auto plan = std::make_shared<EvalPlan>();
  // Offsets into plan->data while it grows; turned into pointers once it is complete.
  struct GroupOffsets {
    int positions = 0;
    std::array<int, 3> coefficients{};
  };
  std::vector<GroupOffsets> groupOffsets;
  std::vector<int> polynomialOffsets;

  for (int k = 0; k < 3; ++k) {
    EvalPlan::AxisPlan& axis = plan->axes[k];
    axis.sign = topology.isWorkpieceSide(static_cast<Axis>(k)) ? -1.0 : 1.0;
    for (int i = 0; i < 3; ++i) {
      axis.direction[i] = direction[k][i];
      axis.directionMinusUnit[i] = directionMinusUnit[k][i];
    }
    axis.lowerMm = -std::numeric_limits<double>::infinity();
    axis.upperMm = std::numeric_limits<double>::infinity();
    if (spec.travelMm[k]) {
      axis.lowerMm = (*spec.travelMm[k])[0];
      axis.upperMm = (*spec.travelMm[k])[1];
    }

    axis.groupBegin = static_cast<int>(plan->groups.size());
    axis.polynomialBegin = static_cast<int>(plan->polynomials.size());
    std::array<bool, 6> done{};
    for (int slot = 0; slot < 6; ++slot) {
      const ErrorFunctionSpec& fs = spec.motion[k * 6 + slot];
      if (const double* constant = std::get_if<double>(&fs)) {
        axis.constants[slot] = *constant;
        done[slot] = true;
      } else if (const PolynomialSpec* poly = std::get_if<PolynomialSpec>(&fs)) {
        EvalPlan::Polynomial p;
        p.slot = slot;
        p.count = static_cast<int>(poly->coefficients.size());
        polynomialOffsets.push_back(static_cast<int>(plan->data.size()));
        plan->data.insert(plan->data.end(), poly->coefficients.begin(), poly->coefficients.end());
        plan->polynomials.push_back(p);
        done[slot] = true;
      }
    }
    // Tables over identical positions form one group.
    for (int slot = 0; slot < 6; ++slot) {
      if (done[slot]) continue;
      const std::vector<double>& positions =
          std::get<TableSpec>(spec.motion[k * 6 + slot]).positionsMm;
      EvalPlan::Group group;
      std::vector<std::array<std::vector<double>, 3>> curves;
      bool bidirectional = false;
      for (int other = slot; other < 6; ++other) {
        if (done[other]) continue;
        const TableSpec& table = std::get<TableSpec>(spec.motion[k * 6 + other]);
        if (table.positionsMm != positions) continue;
        done[other] = true;
        group.slots[group.entryCount++] = other;
        curves.push_back(detail::buildCurves(table));
        bidirectional = bidirectional || !table.valuesNegative.empty();
      }
      group.full = group.entryCount == 6;  // slots were taken in increasing order
      group.axis.count = static_cast<int>(positions.size());
      group.axis.uniform = detail::isUniform(positions);
      group.axis.first = positions.front();
      group.axis.last = positions.back();
      group.axis.invStep =
          static_cast<double>(positions.size() - 1) / (group.axis.last - group.axis.first);
      GroupOffsets offsets;
      offsets.positions = static_cast<int>(plan->data.size());
      plan->data.insert(plan->data.end(), positions.begin(), positions.end());
      const std::size_t n = static_cast<std::size_t>(group.entryCount);
      const std::size_t intervals = positions.size() - 1;
      for (int c = 0; c < 3; ++c) {
        if (c > 0 && !bidirectional) {
          offsets.coefficients[c] = offsets.coefficients[0];
          continue;
        }
        offsets.coefficients[c] = static_cast<int>(plan->data.size());
        std::vector<double> block(intervals * 4 * n);
        for (std::size_t e = 0; e < n; ++e) {
          for (std::size_t i = 0; i < intervals; ++i) {
            for (std::size_t p = 0; p < 4; ++p) {
              block[(4 * i + p) * n + e] = curves[e][c][4 * i + p];
            }
          }
        }
        plan->data.insert(plan->data.end(), block.begin(), block.end());
      }
      groupOffsets.push_back(offsets);
      plan->groups.push_back(group);
    }
    axis.groupEnd = static_cast<int>(plan->groups.size());
    axis.allTabulated = axis.groupEnd - axis.groupBegin == 1 && plan->groups.back().full;
    axis.uniformTabulated = axis.allTabulated && plan->groups.back().axis.uniform &&
                            axis.polynomialBegin == axis.polynomialEnd;
    axis.polynomialEnd = static_cast<int>(plan->polynomials.size());
  }
  const double* data = plan->data.data();
  for (std::size_t g = 0; g < plan->groups.size(); ++g) {
    plan->groups[g].axis.positions = data + groupOffsets[g].positions;
    for (int c = 0; c < 3; ++c) {
      plan->groups[g].coefficients[c] = data + groupOffsets[g].coefficients[c];
    }
  }
  for (std::size_t p = 0; p < plan->polynomials.size(); ++p) {
    plan->polynomials[p].coefficients = data + polynomialOffsets[p];
  }
  plan->allUniform = true;
  for (int k = 0; k < 3; ++k) {
    const EvalPlan::AxisPlan& axis = plan->axes[k];
    plan->allUniform = plan->allUniform && axis.uniformTabulated;
    if (!axis.uniformTabulated) continue;
    const EvalPlan::Group& group = plan->groups[axis.groupBegin];
    EvalPlan::UniformAxis& u = plan->uniform[k];
    u.lowerMm = axis.lowerMm;
    u.upperMm = axis.upperMm;
    u.first = group.axis.first;
    u.invStep = group.axis.invStep;
    u.top = static_cast<double>(group.axis.count - 1);
    u.lastInterval = group.axis.count - 2;
    u.coefficients = group.coefficients;
  }
  for (const Axis a : topology.toolSideFromFrame()) {
    plan->toolChain[plan->toolCount++] = static_cast<int>(a);
  }
  for (const Axis a : topology.workpieceSideFromFrame()) {
    plan->workpieceChain[plan->workpieceCount++] = static_cast<int>(a);
  }
  std::array<int, 3> chain{};
  for (int i = 0; i < 3; ++i) {
    chain[i] = i < plan->toolCount ? plan->toolChain[i] : plan->workpieceChain[i - plan->toolCount];
  }
  plan->chainPermutation = 2 * chain[0] + (chain[1] < chain[0] ? chain[1] : chain[1] - 1);
  return plan;
}

// sin and cos - 1 of the nine error angles (EA, EB, EC of X, Y, Z, at 3 k + 0, 1, 2; lane 9 is
// padding), from which every carriage rotation is built: no library trigonometry per point.
struct AngleSet {
  alignas(16) double s[10];  // sin(x)
  alignas(16) double m[10];  // cos(x) - 1
};

// The short series of detail::sinCosm1 on one lane pair, exact to double rounding when both
// |x| < 1e-2 rad (the caller checks).
[[gnu::always_inline]] inline void seriesSinCosm1(detail::Double2 v, double* s,
                                                  double* m) noexcept {
  using detail::Double2;
  using detail::splat2;
  // Split into independent halves (Estrin) so the chain of dependent operations stays short:
  // sin = x + x^3 (-1/6) + x^5 (1/120 - x^2/5040), cos - 1 = x^2 (-1/2) + x^4 (1/24 - x^2/720).
  const Double2 v2 = v * v;
  const Double2 v3 = v * v2;
  const Double2 v4 = v2 * v2;
  const Double2 sv =
      (v + v3 * splat2(-1.0 / 6)) + (v3 * v2) * (splat2(1.0 / 120) + v2 * splat2(-1.0 / 5040));
  const Double2 mv = v2 * splat2(-0.5) + v4 * (splat2(1.0 / 24) + v2 * splat2(-1.0 / 720));
  detail::store2(s, sv);
  detail::store2(m, mv);
}

// Lanes of all ones where |v| < 1e-2 rad (none for NaN).
[[gnu::always_inline]] inline auto small(detail::Double2 v) noexcept {
  const detail::Double2 limit = detail::splat2(detail::kSmallAngleRad);
  return (v < limit) & (-v < limit);
}

// The angles are paired straight from the component values with scalar loads: each lies inside
// one store of evaluateMotion, so the loads are forwarded from the store buffer, where a 16-byte
// load straddling two stores would stall until they retire.
// Returns true when every angle is below kSmallAngleRad (the series path).
[[gnu::always_inline]] inline bool computeAngles(const MotionValues& v, AngleSet& a) noexcept {
  using detail::Double2;
  const Double2 p0{v[3], v[4]}, p1{v[5], v[9]}, p2{v[10], v[11]}, p3{v[15], v[16]}, p4{v[17], 0.0};
  const auto all = small(p0) & small(p1) & small(p2) & small(p3) & small(p4);
  if ((all[0] & all[1]) != 0) {
    seriesSinCosm1(p0, a.s, a.m);
    seriesSinCosm1(p1, a.s + 2, a.m + 2);
    seriesSinCosm1(p2, a.s + 4, a.m + 4);
    seriesSinCosm1(p3, a.s + 6, a.m + 6);
    seriesSinCosm1(p4, a.s + 8, a.m + 8);
    return true;
  }
  const double x[9] = {v[3], v[4], v[5], v[9], v[10], v[11], v[15], v[16], v[17]};
  for (int i = 0; i < 9; ++i) detail::sinCosm1(x[i], a.s[i], a.m[i]);
  return false;
}

struct Vec {
  double x, y, z;
};

// R_K - I of one carriage, row-major, built from the sines and cosines - 1 so that its small
// entries keep full relative precision (see detail::rotationZYXMinusIdentity).
struct Mat3 {
  double a[9];
};

[[gnu::always_inline]] inline Mat3 carriageMinusIdentity(const AngleSet& t, int k) noexcept {
  const int i = 3 * k;
  const double sa = t.s[i], sb = t.s[i + 1], sc = t.s[i + 2];
  const double ma = t.m[i], mb = t.m[i + 1], mc = t.m[i + 2];
  const double ca = 1.0 + ma, cb = 1.0 + mb, cc = 1.0 + mc;
  const double sbsa = sb * sa, sbca = sb * ca;
  return {{(mc + mb) + mc * mb, cc * sbsa - sc * ca, cc * sbca + sc * sa,    //
           sc * cb, sc * sbsa + ((mc + ma) + mc * ma), sc * sbca - cc * sa,  //
           -sb, cb * sa, (mb + ma) + mb * ma}};
}

[[gnu::always_inline]] inline Vec apply(const Mat3& m, double x, double y, double z) noexcept {
  return {m.a[0] * x + m.a[1] * y + m.a[2] * z, m.a[3] * x + m.a[4] * y + m.a[5] * z,
          m.a[6] * x + m.a[7] * y + m.a[8] * z};
}

[[gnu::always_inline]] inline Vec applyTransposed(const Mat3& m, double x, double y,
                                                  double z) noexcept {
  return {m.a[0] * x + m.a[3] * y + m.a[6] * z, m.a[1] * x + m.a[4] * y + m.a[7] * z,
          m.a[2] * x + m.a[5] * y + m.a[8] * z};
}

// d + m d + c, grouped so that the terms waiting for d take three dependent additions.
[[gnu::always_inline]] inline Vec step(const Mat3& m, const Vec& d, const Vec& c) noexcept {
  return {(m.a[0] * d.x + m.a[1] * d.y) + (m.a[2] * d.z + (d.x + c.x)),
          (m.a[3] * d.x + m.a[4] * d.y) + (m.a[5] * d.z + (d.y + c.y)),
          (m.a[6] * d.x + m.a[7] * d.y) + (m.a[8] * d.z + (d.z + c.z))};
}

[[gnu::always_inline]] inline Mat3 transposed(const Mat3& m) noexcept {
  return {{m.a[0], m.a[3], m.a[6], m.a[1], m.a[4], m.a[7], m.a[2], m.a[5], m.a[8]}};
}

// One tool-side carriage K (known at compile time, so `nominal` stays in registers). The
// rotation is split as (R - I)(p0 + d) = (R - I) p0 + (R - I) d: only the second part waits for
// the deviation of the carriages before, which keeps the chain of dependent operations (the
// latency of an evaluation) short.
template <int K>
[[gnu::always_inline]] inline void toolStep(const EvalPlan& plan, const Mat3* mats,
                                            const Eigen::Vector3d& q, const MotionValues& v,
                                            double (&nominal)[3], Vec& d) noexcept {
  const double* e = v.data() + 6 * K;
  const double* dme = plan.axes[K].directionMinusUnit.data();
  const Vec fixed = apply(mats[K], nominal[0], nominal[1], nominal[2]);
  const Vec c{fixed.x + e[0] + q[K] * dme[0], fixed.y + e[1] + q[K] * dme[1],
              fixed.z + e[2] + q[K] * dme[2]};
  d = step(mats[K], d, c);
  nominal[K] += q[K];
}

// One workpiece-side carriage K, split the same way.
template <int K>
[[gnu::always_inline]] inline void workpieceStep(const EvalPlan& plan, const Mat3* mats,
                                                 const Eigen::Vector3d& q, const MotionValues& v,
                                                 double (&nominal)[3], Vec& d) noexcept {
  const double* e = v.data() + 6 * K;
  const double* dme = plan.axes[K].directionMinusUnit.data();
  nominal[K] += q[K];
  const Vec fixed = applyTransposed(mats[K], nominal[0], nominal[1], nominal[2]);
  const Vec c{q[K] * dme[0] - e[0], q[K] * dme[1] - e[1], q[K] * dme[2] - e[2]};
  // D = d + c, then D + (R^T - I) D + fixed, i.e. step(M^T, D, fixed); d + c is formed first
  // because everything after it depends on it.
  d = step(transposed(mats[K]), {d.x + c.x, d.y + c.y, d.z + c.z}, fixed);
}

// The chain of one topology: axes A0 A1 A2 are the NT tool-side axes from the frame outward
// followed by the workpiece-side axes from the frame outward. Tool side first, from the tool
// inward (H_FT applied to t), then H_FW^-1 from the frame outward (C_Wn^-1 first).
template <int NT, int A0, int A1, int A2>
Vec chainDeviation(const EvalPlan& plan, const Mat3* mats, const Eigen::Vector3d& q,
                   const MotionValues& v, const Eigen::Vector3d& tool) noexcept {
  double nominal[3] = {tool.x(), tool.y(), tool.z()};
  Vec d{0.0, 0.0, 0.0};
  if constexpr (NT > 2) toolStep<A2>(plan, mats, q, v, nominal, d);
  if constexpr (NT > 1) toolStep<A1>(plan, mats, q, v, nominal, d);
  if constexpr (NT > 0) toolStep<A0>(plan, mats, q, v, nominal, d);
  if constexpr (NT < 1) workpieceStep<A0>(plan, mats, q, v, nominal, d);
  if constexpr (NT < 2) workpieceStep<A1>(plan, mats, q, v, nominal, d);
  if constexpr (NT < 3) workpieceStep<A2>(plan, mats, q, v, nominal, d);
  return d;
}

using ChainFunction = Vec (*)(const EvalPlan&, const Mat3*, const Eigen::Vector3d&,
                              const MotionValues&, const Eigen::Vector3d&) noexcept;

// Indexed by [NT][permutation], permutation = 2 A0 + (A1 < A0 ? A1 : A1 - 1).
template <int NT>
constexpr std::array<ChainFunction, 6> kChainsWith = {
    &chainDeviation<NT, 0, 1, 2>, &chainDeviation<NT, 0, 2, 1>, &chainDeviation<NT, 1, 0, 2>,
    &chainDeviation<NT, 1, 2, 0>, &chainDeviation<NT, 2, 0, 1>, &chainDeviation<NT, 2, 1, 0>};
constexpr std::array<std::array<ChainFunction, 6>, 4> kChains = {kChainsWith<0>, kChainsWith<1>,
                                                                 kChainsWith<2>, kChainsWith<3>};

// Entry (r, c) of B = R - I (T false) or of R^T - I (T true).
template <bool T>
[[gnu::always_inline]] inline double entry(const Mat3& m, int r, int c) noexcept {
  return T ? m.a[3 * c + r] : m.a[3 * r + c];
}

// (I + X)(I + Y) - I = X + Y + X Y, all nine entries; X, Y are R - I or R^T - I of a carriage
// (transposed when TX, TY), read in place.
template <bool TX, bool TY>
[[gnu::always_inline]] inline Mat3 productMinusIdentity(const Mat3& xm, const Mat3& ym) noexcept {
  const auto x = [&xm](int r, int c) { return entry<TX>(xm, r, c); };
  const auto y = [&ym](int r, int c) { return entry<TY>(ym, r, c); };
  const auto p = [&](int r, int c) {
    return (x(r, c) + y(r, c)) + (x(r, 0) * y(0, c) + x(r, 1) * y(1, c) + x(r, 2) * y(2, c));
  };
  return {{p(0, 0), p(0, 1), p(0, 2), p(1, 0), p(1, 1), p(1, 2), p(2, 0), p(2, 1), p(2, 2)}};
}

// Skew part s = (R32 - R23, R13 - R31, R21 - R12) / 2 of rot(H_WT) = R_W1^T ... R_Wn^T R_T1 ...
// R_Tn, which is sin(angle) times the rotation axis: the three factors are the workpiece-side
// axes from the carriage of the workpiece inward (A2 down to A_NT, transposed), then the tool-side
// axes from the frame outward (A0 up to A_NT-1). Formed from the R - I matrices, so that only the
// six off-diagonal entries of the last product are needed.
template <int NT, int A0, int A1, int A2>
Vec chainSkew(const Mat3* mats) noexcept {
  constexpr int kAxes[3] = {A0, A1, A2};
  // Factor j (left to right) is carriage kAxes[kIndex[j]], transposed when it is workpiece side.
  constexpr int kIndex[3] = {NT == 3 ? 0 : 2,
                             NT == 3   ? 1
                             : NT == 2 ? 0
                                       : 1,
                             NT == 3   ? 2
                             : NT == 2 ? 1
                                       : 0};
  constexpr bool kT0 = kIndex[0] >= NT, kT1 = kIndex[1] >= NT, kT2 = kIndex[2] >= NT;
  const Mat3 p = productMinusIdentity<kT0, kT1>(mats[kAxes[kIndex[0]]], mats[kAxes[kIndex[1]]]);
  const Mat3& ym = mats[kAxes[kIndex[2]]];
  const auto y = [&ym](int r, int c) { return entry<kT2>(ym, r, c); };
  // Entry (r, c) of (I + P)(I + Y) - I.
  const auto last = [&](int r, int c) {
    return (p.a[3 * r + c] + y(r, c)) +
           (p.a[3 * r] * y(0, c) + p.a[3 * r + 1] * y(1, c) + p.a[3 * r + 2] * y(2, c));
  };
  return {0.5 * (last(2, 1) - last(1, 2)), 0.5 * (last(0, 2) - last(2, 0)),
          0.5 * (last(1, 0) - last(0, 1))};
}

using SkewFunction = Vec (*)(const Mat3*) noexcept;

template <int NT>
constexpr std::array<SkewFunction, 6> kSkewsWith = {
    &chainSkew<NT, 0, 1, 2>, &chainSkew<NT, 0, 2, 1>, &chainSkew<NT, 1, 0, 2>,
    &chainSkew<NT, 1, 2, 0>, &chainSkew<NT, 2, 0, 1>, &chainSkew<NT, 2, 1, 0>};
constexpr std::array<std::array<SkewFunction, 6>, 4> kSkews = {kSkewsWith<0>, kSkewsWith<1>,
                                                               kSkewsWith<2>, kSkewsWith<3>};

// E(q) without grids, composed in deviation form: every partial product is carried as its
// nominal value plus a deviation, and only deviations are accumulated, so that E keeps full
// relative precision instead of being the difference of two positions of ~1e3 mm.
// Tool side, carriage K applied to p = p0 + dp (p0 the nominal partial point):
//   R p + e + q d = (p0 + q e_K) + [dp + (R - I) p + e + q (d - e_K)].
// Workpiece side, C_K^-1 x = R^T (x - e + q d) with x = x0 + dx:
//   x - e + q d = (x0 + q e_K) + D,  D = dx - e + q (d - e_K),
//   R^T (x0 + q e_K + D) = (x0 + q e_K) + [D + (R^T - I)(x0 + q e_K + D)].
// The nominal result is q + t (and -w on both), so E is the final deviation.
[[gnu::always_inline]] inline Vec positionDeviation(const EvalPlan& plan, const Mat3* mats,
                                                    const Eigen::Vector3d& q, const MotionValues& v,
                                                    const Eigen::Vector3d& tool) noexcept {
  return kChains[plan.toolCount][plan.chainPermutation](plan, mats, q, v, tool);
}

// R = Rz(c) Ry(b) Rx(a) of carriage k from the sines and cosines the position already needed.
[[gnu::always_inline]] inline Eigen::Matrix3d carriageRotation(const AngleSet& t, int k) noexcept {
  const int i = 3 * k;
  const double sa = t.s[i], sb = t.s[i + 1], sc = t.s[i + 2];
  const double ca = 1.0 + t.m[i], cb = 1.0 + t.m[i + 1], cc = 1.0 + t.m[i + 2];
  Eigen::Matrix3d r;
  r(0, 0) = cc * cb;
  r(0, 1) = cc * sb * sa - sc * ca;
  r(0, 2) = cc * sb * ca + sc * sa;
  r(1, 0) = sc * cb;
  r(1, 1) = sc * sb * sa + cc * ca;
  r(1, 2) = sc * sb * ca - cc * sa;
  r(2, 0) = -sb;
  r(2, 1) = cb * sa;
  r(2, 2) = cb * ca;
  return r;
}

// Rotation vector of rot(H_WT) = R_W1^T ... R_Wn^T R_T1 ... R_Tn (workpieceChain runs from the
// frame outward, Wn first).
Eigen::Vector3d angularError(const EvalPlan& plan, const AngleSet& angles) noexcept {
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  if (plan.toolCount > 0) {
    r = carriageRotation(angles, plan.toolChain[plan.toolCount - 1]);
    for (int i = plan.toolCount - 1; i-- > 0;) {
      r = (carriageRotation(angles, plan.toolChain[i]) * r).eval();
    }
  }
  for (int i = 0; i < plan.workpieceCount; ++i) {
    r = (carriageRotation(angles, plan.workpieceChain[i]).transpose() * r).eval();
  }
  return rotationVector(r);
}

// The carriage matrices R_K - I the position was composed with, and whether every error angle
// took the small-angle series.
struct Carriages {
  Mat3 mats[3];
  bool small = false;
};

[[gnu::always_inline]] inline Eigen::Vector3d positionError(
    const MachineModel& model, const EvalPlan& plan, AngleSet& angles, Carriages& carriages,
    const Eigen::Vector3d& q, const MotionValues& values, const Eigen::Vector3d& tool) noexcept {
  carriages.small = computeAngles(values, angles);
  Mat3* mats = carriages.mats;
  mats[0] = carriageMinusIdentity(angles, 0);
  mats[1] = carriageMinusIdentity(angles, 1);
  mats[2] = carriageMinusIdentity(angles, 2);
  const Vec d = positionDeviation(plan, mats, q, values, tool);
  Eigen::Vector3d error(d.x, d.y, d.z);
  for (const Grid& grid : model.grids()) error[grid.component()] += grid.valueMm(q.data());
  return error;
}

}  // namespace

MachineModel::MachineModel(MachineModelSpec spec)
    : spec_(std::move(spec)), topology_(Topology::parse(spec_.topology)) {
  for (int i = 0; i < 18; ++i) {
    try {
      motion_[i] = ErrorFunction(spec_.motion[i]);
    } catch (const ModelError& e) {
      throw ModelError(motionName(i) + ": " + e.what());
    }
  }
  for (int i = 0; i < 9; ++i) {
    if (!std::isfinite(spec_.locationRad[i])) {
      throw ModelError(locationName(i) + " is not a finite number");
    }
  }
  for (int k = 0; k < 3; ++k) {
    if (const auto& travel = spec_.travelMm[k]) {
      const double lo = (*travel)[0], hi = (*travel)[1];
      if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo <= hi)) {
        throw ModelError(std::string("travel of ") + "XYZ"[k] +
                         ": expected finite [min, max] with min <= max");
      }
    }
  }
  requireFinite(spec_.toolMm, "tool");
  requireFinite(spec_.workpieceMm, "workpiece");
  grids_.reserve(spec_.grids.size());
  for (std::size_t g = 0; g < spec_.grids.size(); ++g) {
    try {
      grids_.emplace_back(spec_.grids[g]);
    } catch (const ModelError& e) {
      throw ModelError("grids[" + std::to_string(g) + "]: " + e.what());
    }
  }
  // d_K - e_K is the K-th column of Rz Ry Rx - I, kept separately for full precision.
  std::array<Eigen::Vector3d, 3> directionMinusUnit;
  for (int k = 0; k < 3; ++k) {
    directionMinusUnit[k] =
        detail::rotationZYXMinusIdentity(spec_.locationRad[3 * k], spec_.locationRad[3 * k + 1],
                                         spec_.locationRad[3 * k + 2])
            .col(k);
    direction_[k] = directionMinusUnit[k];
    direction_[k][k] += 1.0;
  }
  plan_ = buildPlan(spec_, topology_, direction_, directionMinusUnit);
}

const Eigen::Vector3d& MachineModel::axisDirection(Axis axis) const noexcept {
  return direction_[static_cast<int>(axis)];
}

namespace {

// Two lanes of c0 + c1 t + c2 t^2 + c3 t^3 for a group of six interleaved tables (c points at
// c0 of the lane pair; the powers are 6 apart), in Estrin's form (c0 + c1 t) + t^2 (c2 + c3 t):
// two independent halves, so a shorter chain of dependent operations than Horner's.
[[gnu::always_inline]] inline detail::Double2 cubic6(const double* c, detail::Double2 t,
                                                     detail::Double2 t2) noexcept {
  return (detail::load2(c) + t * detail::load2(c + 6)) +
         t2 * (detail::load2(c + 12) + t * detail::load2(c + 18));
}

// One axis of an allUniform plan: q clamped to the travel (a NaN stays NaN and is not flagged),
// then into the table, index and fraction, three lane pairs. Branch-free.
template <int K>
[[gnu::always_inline]] inline unsigned uniformAxis(const EvalPlan& plan, const Eigen::Vector3d& qMm,
                                                   const Directions& directions,
                                                   double* values) noexcept {
  const EvalPlan::UniformAxis& axis = plan.uniform[K];
  const double q0 = qMm[K];
  const unsigned clamped = static_cast<unsigned>((q0 < axis.lowerMm) | (q0 > axis.upperMm)) << K;
  const double q = std::min(std::max(q0, axis.lowerMm), axis.upperMm);
  // Written so that a NaN position lands on the first node instead of indexing anywhere.
  double scaled = (q - axis.first) * axis.invStep;
  scaled = scaled > 0.0 ? scaled : 0.0;
  scaled = scaled < axis.top ? scaled : axis.top;
  const int i = std::min(static_cast<int>(scaled), axis.lastInterval);
  const detail::Double2 tt = detail::splat2(scaled - i);
  const double* c = axis.coefficients[detail::curveIndex(directions[K])] + 24 * i;
  const detail::Double2 t2 = tt * tt;
  double* out = values + 6 * K;
  detail::store2(out, cubic6(c, tt, t2));
  detail::store2(out + 2, cubic6(c + 2, tt, t2));
  detail::store2(out + 4, cubic6(c + 4, tt, t2));
  return clamped;
}

[[gnu::always_inline]] inline std::uint8_t uniformMotion(const EvalPlan& plan,
                                                         const Eigen::Vector3d& qMm,
                                                         const Directions& directions,
                                                         MotionValues& values) noexcept {
  return static_cast<std::uint8_t>(uniformAxis<0>(plan, qMm, directions, values.data()) |
                                   uniformAxis<1>(plan, qMm, directions, values.data()) |
                                   uniformAxis<2>(plan, qMm, directions, values.data()));
}

}  // namespace

std::uint8_t evaluateMotion(const MachineModel& model, const Eigen::Vector3d& qMm,
                            const Directions& directions, MotionValues& values) noexcept {
  const EvalPlan& plan = detail::PlanAccess::plan(model);
  if (plan.allUniform) return uniformMotion(plan, qMm, directions, values);
  std::uint8_t clamped = 0;
  for (int k = 0; k < 3; ++k) {
    const EvalPlan::AxisPlan& axis = plan.axes[k];
    double q = qMm[k];
    if (q < axis.lowerMm) {
      q = axis.lowerMm;
      clamped = static_cast<std::uint8_t>(clamped | (1u << k));
    } else if (q > axis.upperMm) {
      q = axis.upperMm;
      clamped = static_cast<std::uint8_t>(clamped | (1u << k));
    }
    double* out = values.data() + 6 * k;
    const int curve = detail::curveIndex(directions[k]);
    if (axis.uniformTabulated) {
      // The usual measured axis: six tables over one uniform grid. Branch-free O(1) lookup
      // (the position clamped into the table, then index and fraction) and three lane pairs.
      const EvalPlan::Group& group = plan.groups[axis.groupBegin];
      const detail::TableAxis& grid = group.axis;
      // Written so that a NaN position lands on the first node instead of indexing anywhere.
      double scaled = (q - grid.first) * grid.invStep;
      scaled = scaled > 0.0 ? scaled : 0.0;
      const double top = static_cast<double>(grid.count - 1);
      scaled = scaled < top ? scaled : top;
      const int i = std::min(static_cast<int>(scaled), grid.count - 2);
      const detail::Double2 tt = detail::splat2(scaled - i);
      const double* c = group.coefficients[curve] + 24 * i;
      const detail::Double2 t2 = tt * tt;
      for (int e = 0; e < 6; e += 2) detail::store2(out + e, cubic6(c + e, tt, t2));
      continue;
    }
    if (!axis.allTabulated) std::memcpy(out, axis.constants.data(), sizeof axis.constants);
    for (int g = axis.groupBegin; g < axis.groupEnd; ++g) {
      const EvalPlan::Group& group = plan.groups[g];
      const detail::TableLocation at = group.axis.locate(q);
      const double t = at.t;
      const int n = group.entryCount;
      const double* c = group.coefficients[curve] + 4 * n * at.index;
      if (group.full) {
        // The common case (every component of the axis tabulated over the same positions): six
        // contiguous coefficients per power, a fixed-length loop the compiler can vectorise.
        const detail::Double2 tt = detail::splat2(t);
        const detail::Double2 t2 = tt * tt;
        for (int e = 0; e < 6; e += 2) detail::store2(out + e, cubic6(c + e, tt, t2));
      } else {
        for (int e = 0; e < n; ++e) {
          out[group.slots[e]] = c[e] + t * (c[n + e] + t * (c[2 * n + e] + t * c[3 * n + e]));
        }
      }
    }
    for (int p = axis.polynomialBegin; p < axis.polynomialEnd; ++p) {
      const EvalPlan::Polynomial& poly = plan.polynomials[p];
      double sum = 0.0;
      for (int i = poly.count; i-- > 0;) sum = sum * q + poly.coefficients[i];
      out[poly.slot] = sum;
    }
  }
  return clamped;
}

PointError composeError(const MachineModel& model, Workspace& ws, const Eigen::Vector3d& qMm,
                        const MotionValues& values, const Eigen::Vector3d& toolMm,
                        EvalMode mode) noexcept {
  (void)ws;  // everything fits in registers and on the stack
  const EvalPlan& plan = detail::PlanAccess::plan(model);
  AngleSet angles;
  Carriages carriages;
  PointError result;
  result.errorMm = positionError(model, plan, angles, carriages, qMm, values, toolMm);
  if (mode == EvalMode::Exact) {
    const Vec sk = kSkews[plan.toolCount][plan.chainPermutation](carriages.mats);
    const double s2 = sk.x * sk.x + sk.y * sk.y + sk.z * sk.z;
    if (carriages.small && s2 < 1e-4) {
      // The series branch of rotationVector: with every error angle below 1e-2 rad the rotation
      // is below 0.1 rad, so cos(angle) > 0 holds without forming the trace.
      const double f =
          1.0 + s2 * (1.0 / 6.0 + s2 * (3.0 / 40.0 + s2 * (5.0 / 112.0 + s2 * (35.0 / 1152.0))));
      result.angularErrorRad = Eigen::Vector3d(f * sk.x, f * sk.y, f * sk.z);
    } else {
      result.angularErrorRad = angularError(plan, angles);
    }
  } else {
    // First order the small rotations simply add: tool side +w, workpiece side -w.
    const double* v = values.data();
    const double sx = plan.axes[0].sign, sy = plan.axes[1].sign, sz = plan.axes[2].sign;
    result.angularErrorRad =
        Eigen::Vector3d(sx * v[3] + sy * v[9] + sz * v[15], sx * v[4] + sy * v[10] + sz * v[16],
                        sx * v[5] + sy * v[11] + sz * v[17]);
  }
  return result;
}

PointError evaluate(const MachineModel& model, Workspace& ws, const Eigen::Vector3d& qMm,
                    const Directions& directions, EvalMode mode) noexcept {
  return evaluate(model, ws, qMm, model.toolMm(), directions, mode);
}

PointError evaluate(const MachineModel& model, Workspace& ws, const Eigen::Vector3d& qMm,
                    const Eigen::Vector3d& toolMm, const Directions& directions,
                    EvalMode mode) noexcept {
  const std::uint8_t clamped = evaluateMotion(model, qMm, directions, ws.motion);
  PointError result = composeError(model, ws, qMm, ws.motion, toolMm, mode);
  result.clampedAxes = clamped;
  return result;
}

OffsetSolution solveOffset(const MachineModel& model, Workspace& ws, const Eigen::Vector3d& qMm,
                           const Directions& directions, const OffsetOptions& options) noexcept {
  const EvalPlan& plan = detail::PlanAccess::plan(model);
  const Eigen::Vector3d& tool = model.toolMm();
  OffsetSolution solution;
  // Both modes compose the position the same way (see EvalMode), so options.mode changes nothing.
  AngleSet angles;
  Carriages carriages;
  std::uint8_t clamped = evaluateMotion(model, qMm, directions, ws.motion);
  Eigen::Vector3d offset = -positionError(model, plan, angles, carriages, qMm, ws.motion, tool);
  double residualNorm = std::numeric_limits<double>::infinity();
  int iteration = 0;
  while (iteration < options.maxIterations) {
    ++iteration;
    const Eigen::Vector3d commanded = qMm + offset;
    clamped = evaluateMotion(model, commanded, directions, ws.motion);
    // p(q + o) - p0(q) = E(q + o) + o, formed without subtracting two large positions.
    const Eigen::Vector3d residual =
        positionError(model, plan, angles, carriages, commanded, ws.motion, tool) + offset;
    residualNorm = residual.norm();
    if (!std::isfinite(residualNorm)) break;
    if (residualNorm < options.toleranceMm) {
      solution.converged = true;
      break;
    }
    if (iteration == options.maxIterations) break;  // keep the offset the residual belongs to
    offset -= residual;
  }
  solution.offsetMm = offset;
  solution.iterations = iteration;
  solution.residualMm = residualNorm;
  solution.clampedAxes = clamped;
  return solution;
}

}  // namespace volcomp::model
