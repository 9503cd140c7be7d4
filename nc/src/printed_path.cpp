#include "printed_path.hpp"

#include <cmath>

#include "volcomp/nc/numbers.hpp"

namespace volcomp::nc::detail {

Printed print(const PrintMode& mode, const Vec3& targetMm, const Vec3& controllerMm) {
  const double unit = mode.frame.unitMm;
  const Vec3 shift = mode.machineCoordinates ? Vec3::Zero() : mode.frame.shiftMm;
  const double scale = pow10(mode.decimals);
  Printed p;
  for (int k = 0; k < 3; ++k) {
    const double target = (targetMm[k] - shift[k]) / unit;
    double written = 0.0;
    if (mode.incremental) {
      // Increments of the written positions, so that rounding never
      // accumulates.
      const double current = (controllerMm[k] - shift[k]) / unit;
      const std::int64_t inc = std::llround((target - current) * scale);
      p.counts[static_cast<std::size_t>(k)] = inc;
      written = current + static_cast<double>(inc) / scale;
    } else {
      const std::int64_t c = std::llround(target * scale);
      p.counts[static_cast<std::size_t>(k)] = c;
      written = static_cast<double>(c) / scale;
    }
    p.machineMm[k] = written * unit + shift[k];
  }
  return p;
}

bool PrintedPath::moves(const PrintMode& mode, const Printed& p) const {
  if (mode.incremental) return p.counts != std::array<std::int64_t, 3>{};
  const Printed here = print(mode, controller, controller);
  return here.counts != p.counts;
}

bool PrintedPath::jumpTo(const PrintMode& mode, const Vec3& targetMm, bool alwaysReversal) {
  const Printed start = next(mode, targetMm);
  if (!moves(mode, start)) return false;
  const PieceKind kind =
      alwaysReversal || controllerCompensated ? PieceKind::Reversal : PieceKind::LeadIn;
  emit(mode, start, kind);
  return kind == PieceKind::Reversal;
}

}  // namespace volcomp::nc::detail
