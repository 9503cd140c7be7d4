#pragma once
/// Planning of the compensation of a chunk of moves: where along each move the
/// offset is solved (its end, the kinks of the offset along it, points at most
/// the check step apart, the pieces an arc needs for its sagitta), with the
/// direction of travel of every point; all points of a chunk are then solved in
/// one batch.

#include <cstdint>
#include <string>
#include <vector>

#include "volcomp/nc/offset_field.hpp"
#include "volcomp/nc/program_lines.hpp"

namespace volcomp::nc::detail {

/// A section of a move between two boundaries (kinks, quadrant points of arcs,
/// pieces of an arc): its samples are [first, last] in the motion's sample
/// list, uniformly spaced in u.
struct Section {
  std::uint32_t first = 0;
  std::uint32_t last = 0;
  model::Directions dirs{};
  bool hardStart = false;  ///< directions change here: always a vertex, maybe a reversal
};

/// One motion of the chunk: its samples and sections.
struct Planned {
  std::uint32_t sampleBegin = 0;
  std::uint32_t sampleEnd = 0;
  std::uint32_t sectionBegin = 0;
  std::uint32_t sectionEnd = 0;
  bool split = false;  ///< a feed move planned in sections (else only its end point)
};

/// The points of a chunk to solve, their results, and each motion's samples and
/// sections.
struct ChunkPlan {
  std::vector<Vec3> solveQ;
  std::vector<model::Directions> solveDirs;
  std::vector<long> solveLine;
  std::vector<OffsetSample> solveOut;
  std::vector<double> sampleU;
  std::vector<std::uint32_t> sampleRef;  ///< index of the sample's point in solveQ
  std::vector<Section> sections;
  std::vector<Planned> planned;  ///< one per motion of the chunk

  /// The exact compensated point of solved point `ref`.
  Vec3 compensated(std::uint32_t ref) const { return solveQ[ref] + solveOut[ref].offsetMm; }
};

class MovePlanner {
 public:
  /// `file` names the program in messages; it is read when a move is refused.
  MovePlanner(const OffsetField& field, double toleranceMm, double checkStepMm,
              std::size_t maxCheckPointsPerMove, const std::string& file);

  /// Empties `plan` for a new chunk (the direction of travel carries over).
  void startChunk(ChunkPlan& plan);
  /// Plans one motion into `plan`. Throws NcError for a move beyond
  /// kMaxPositionMm or one needing more check points than allowed.
  void plan(const MotionWork& w, ChunkPlan& plan);

 private:
  model::Directions masked(model::Directions d) const;
  model::Directions lineDirections(const Move& m) const;
  model::Directions arcDirections(const Move& m, double u, const model::Directions& previous) const;
  void addLineKinks(const Move& m);
  void addAngles(const ArcGeometry& a, double phi);
  void addArcKinks(const Move& m);
  void dropCloseBoundaries(const Move& m);
  void refuseOutOfRange(const MotionWork& w) const;
  void refuseOversized(const MotionWork& w) const;
  /// Appends the samples and sections of a feed move whose start and end are
  /// known.
  void planSections(const MotionWork& w, ChunkPlan& plan, Planned& p);

  const OffsetField& field_;
  double tolerance_;
  double checkStep_;
  std::size_t maxCheckPoints_;
  const std::string& file_;
  std::uint8_t bidirectional_ = 0;
  model::Directions lastDirs_{};
  std::int64_t prevEndRef_ = -1;
  model::Directions prevEndDirs_{};
  std::vector<double> boundaries_;
};

}  // namespace volcomp::nc::detail
