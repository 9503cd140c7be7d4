#pragma once
/// Checking and splitting of a planned feed move: its sections are joined
/// greedily into the longest pieces whose deviation from the ideal compensated
/// curve, plus the curvature allowance, stays within the tolerance; a section
/// that fails on its own is replaced by finer sections, solved then. The pieces
/// (and the reversal moves between them) go to the printed path.

#include <cstddef>
#include <vector>

#include "move_planner.hpp"
#include "printed_path.hpp"
#include "volcomp/nc/offset_field.hpp"
#include "volcomp/nc/program_lines.hpp"
#include "volcomp/nc/report.hpp"

namespace volcomp::nc::detail {

class MoveRefiner {
 public:
  MoveRefiner(OffsetField& field, double toleranceMm, double checkStepMm, NcReport& report);

  /// Writes the pieces of planned feed move `p` (solved in `plan`) to `path`.
  void assemble(const MotionWork& w, const Planned& p, const ChunkPlan& plan, PrintedPath& path);

 private:
  struct WorkSample {
    double u = 0.0;
    Vec3 c = Vec3::Zero();  // exact compensated point
    OffsetSample offset;
  };
  struct WorkSection {
    std::uint32_t first = 0;  // samples [first, last] in `work_`
    std::uint32_t last = 0;
    model::Directions dirs{};
    bool hardStart = false;
    int depth = 0;
    double allowanceMm = 0.0;
  };
  /// The longest piece from section i that passes, or none.
  struct Candidate {
    std::size_t best;  // last section of the piece; the number of sections when
                       // none passes
    Printed printed;
    double deviation = 0.0;
    double bound = 0.0;
    double failedBound = 0.0;  // of the first candidate that failed
    long checks = 0;
  };

  double allowanceOf(const WorkSection& s) const;
  void loadSections(const Planned& p, const ChunkPlan& plan);
  double chordDeviation(std::size_t a, std::size_t b, const Vec3& vFrom, const Vec3& vTo,
                        long& checks) const;
  Candidate longestPiece(const MotionWork& w, std::size_t i, const PrintedPath& path) const;
  void subdivide(const MotionWork& w, std::size_t i, double bound);
  void accept(double deviation, double bound, long checks);

  OffsetField& field_;
  double tolerance_;
  double checkStep_;
  NcReport& report_;
  std::vector<WorkSample> work_;
  std::vector<WorkSection> workSections_;
  std::vector<WorkSection> finer_;
  std::vector<Vec3> refineQ_;
  std::vector<model::Directions> refineDirs_;
  std::vector<OffsetSample> refineOut_;
  std::vector<double> refineU_;
};

}  // namespace volcomp::nc::detail
