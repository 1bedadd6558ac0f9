// BenchRunner: runs a BenchScene in Strata (and, through BulletPeer, in Bullet) and measures it. Each
// engine can run in a forked child so its peak memory is its own. Call from the main thread only.
#pragma once

#include <cstdint>
#include <functional>

#include "physics/world/PhysicsSystem.h"
#include "tools/bench/BenchScenes.h"

namespace strata::bench {

/// One stage of Strata's step, averaged over a run (ms per step).
struct StageFigures {
  char name[32] = {};
  double wall_ms = 0.0;    ///< from its first job's start to its last job's end
  double busy_ms = 0.0;    ///< summed over its jobs (spinning for a split island's next round included)
  std::uint32_t jobs = 0;  ///< jobs it ran as in the last step
  bool parallel = false;   ///< a stage that may run as several jobs
};

/// Which job system Strata runs on.
enum class JobSystemKind { kDefault, kThreadPool };

/// Figures of one engine on one scene. Plain data so it can cross a pipe from a child process.
struct EngineResult {
  bool ok = false;
  int bodies = 0;
  int steps = 0;
  double total_seconds = 0.0;
  double median_step_ms = 0.0;
  double max_step_ms = 0.0;
  long peak_memory_kb = 0;       ///< peak resident set of the process that ran it
  int bodies_in_footprint = 0;   ///< pyramid: boxes still over the floor area; mesh: bodies above y = 0
  std::uint64_t state_hash = 0;  ///< FNV-1a of final dynamic positions and rotations
  int threads = 1;
  double mean_step_ms = 0.0;
  static constexpr int kMaxStages = 16;
  int stage_count = 0;  ///< Strata only
  StageFigures stages[kMaxStages];
  double replayed_pair_share = 0.0;      ///< Strata: pairs that reused last step's manifolds / all pairs
  double kept_apart_pair_share = 0.0;    ///< Strata: pairs last step's separating axis held apart / all pairs
  double contact_events_per_step = 0.0;  ///< Strata: contact begin + persist + end events, mean
  /// How far apart each joint's anchor is, seen from its two bodies, after the last step (mm): how much a
  /// chain stretched. 0 for a scene without joints.
  double max_joint_gap_mm = 0.0;
  double mean_joint_gap_mm = 0.0;
  /// The widest any joint's anchor opened over the run, read every kJointGapSampleSteps steps and after the
  /// last, between the timed steps (mm): a swinging chain's gap after one chosen step says little.
  double widest_joint_gap_mm = 0.0;

  double StepsPerSecond() const { return total_seconds > 0.0 ? steps / total_seconds : 0.0; }
};

/// Final pose of one dynamic body, for the footprint count and the hash.
struct FinalPose {
  Vec3 position;
  Quat rotation;
};

/// Fills the footprint count, hash and joint gaps of `result` from the final dynamic poses (in the scene's
/// order of its dynamic bodies).
void Summarize(const BenchScene& scene, const std::vector<FinalPose>& poses, EngineResult& result);
/// Steps between two readings of the joint gaps over a run.
constexpr int kJointGapSampleSteps = 10;
/// Whether the joint gaps are read after step `step` (0-based): a scene with joints, every
/// kJointGapSampleSteps steps and after the last.
bool ReadsJointGapsAfter(const BenchScene& scene, int step);
/// Widens `result.widest_joint_gap_mm` to the widest joint gap of `poses` (as Summarize takes them).
void WidenJointGap(const BenchScene& scene, const std::vector<FinalPose>& poses, EngineResult& result);
/// Median and max of per-step times (seconds) into `result`.
void SummarizeTimes(std::vector<double> step_seconds, EngineResult& result);
/// Peak resident set size of this process (kB), from /proc/self/status.
long PeakMemoryKb();

/// Mass (kg) of a dynamic benchmark body at Strata's default density, so every engine moves the same mass.
float BenchMass(const BenchScene& scene, const BodyDescription& body);

/// A Strata world holding a scene's bodies and joints.
struct StrataScene {
  std::unique_ptr<PhysicsSystem> world;
  std::vector<BodyID> dynamic_bodies;  ///< in the scene's order
};
/// Builds `scene` in a world made with `config` (max_bodies is set from the scene); nullopt if anything
/// in it is refused.
std::optional<StrataScene> BuildStrataScene(const BenchScene& scene, PhysicsSystemConfig config);

/// Strata on `threads` worker threads (0 = all cores).
EngineResult RunStrata(const BenchScene& scene, int threads,
                       JobSystemKind job_system = JobSystemKind::kDefault);
/// Runs `run` in a forked child and returns what it reported (ok = false if the child failed).
EngineResult RunIsolated(const std::function<EngineResult()>& run);

#ifdef STRATA_HAVE_BULLET
/// The same scene in Bullet's btDiscreteDynamicsWorld (DBVT broad phase, sequential impulses).
EngineResult RunBullet(const BenchScene& scene);
#endif

}  // namespace strata::bench
