#pragma once
// Commissioning tools of volcompd: `--probe` reads one consistent sample and prints every decoded
// value with its register or signal and raw bytes (writes nothing); `--test-offset X:5um` then
// writes one small offset on one axis through the limiter, reads it back, holds it, ramps it out
// and reports, for the sign check of each axis (docs/commissioning.md).

#include <iosfwd>
#include <memory>
#include <optional>
#include <string>

#include "volcomp/config/daemon_config.hpp"
#include "volcomp/loop/ports.hpp"

namespace volcomp::volcompd {

/// The raw side of a driver: what its last read and write looked like on the wire.
class RawView {
 public:
  virtual ~RawView() = default;
  /// One line per input: name, register or signal, raw bytes, decoded value.
  virtual void printInputs(std::ostream& out) const = 0;
  /// One line per output of the last write.
  virtual void printOutputs(std::ostream& out) const = 0;
  /// One line on how a read is made ("one FC03 of holding 0-13").
  virtual std::string readDescription() const = 0;
};

/// A port with its raw view (the view reads the port's buffers).
struct ProbeTransport {
  std::unique_ptr<loop::ControllerPort> port;
  std::unique_ptr<RawView> raw;
};

/// Builds the driver named in the transport section with its raw view. Throws ConfigError.
ProbeTransport makeProbeTransport(const config::TransportSettings& settings,
                                  const std::string& file);

/// `--test-offset AXIS:VALUE[unit]`, e.g. "X:5um", "z:-0.004mm", "Y:2.5 um" (um, mm or nm;
/// default um).
struct TestOffset {
  int axis = 0;
  double offsetMm = 0.0;
};
/// Throws std::invalid_argument with what was expected.
TestOffset parseTestOffset(const std::string& text);

struct ProbeOptions {
  std::optional<TestOffset> testOffset;
  double holdS = 2.0;  ///< how long the test offset is held before the ramp-out
};

/// Runs the probe (and the test offset) against the controller of `config`. Returns the exit
/// status: 0 done (and the read-back agreed), 1 the controller could not be reached or read, the
/// test could not run or the read-back disagreed, 2 a bad request (offset beyond the limiter).
int runProbe(const config::DaemonConfig& config, const ProbeOptions& options, std::ostream& out);

}  // namespace volcomp::volcompd
