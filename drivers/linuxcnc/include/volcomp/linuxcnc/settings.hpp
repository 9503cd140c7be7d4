#pragma once
/// What the LinuxCNC adapter needs to join a running LinuxCNC: the name of its HAL component and
/// the scale of the external-offset counts. Plain data (config/linuxcnc_config.hpp reads it from
/// a transport section {"type": "linuxcnc", ...}).

#include <string>

namespace volcomp::linuxcnc {

struct HalSettings {
  /// Name of the HAL userspace component (its pins are `<component>.x.pos-cmd` ...) and the
  /// prefix of the HAL signals it joins (`<component>-x-pos-cmd` ...; see pins.hpp).
  std::string component = "volcomp";
  /// Counts of `axis.L.eoffset-counts` per mm; the adapter drives `axis.L.eoffset-scale` with
  /// 1 / countsPerMm (10000: one count = 0.1 um).
  double countsPerMm = 10000.0;
  bool operator==(const HalSettings&) const = default;
};

}  // namespace volcomp::linuxcnc
