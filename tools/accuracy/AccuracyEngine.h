// AccuracyEngine: one physics engine behind the accuracy suite, building its scenes (SceneDescription: the
// cases use boxes and spheres, static or dynamic) so the same analytic cases run on Strata and, side by side,
// on Bullet. One engine object per run; single-threaded use.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "assets/scene/SceneDescription.h"
#include "physics/PhysicsSettings.h"
#include "physics/core/Result.h"
#include "physics/math/Math.h"

namespace strata::accuracy {

/// How a run is stepped.
struct AccuracySetting {
  std::string name;
  float dt = 1.0f / 60.0f;
  int substeps = 4;
  int velocity_iterations = 1;      ///< per substep
  int relax_iterations = 1;         ///< per substep
  bool linear_cast = true;          ///< continuous collision for dynamic bodies
  bool exact_small_islands = true;  ///< Strata only: PhysicsSettings::exact_small_islands
};

struct AccuracyBodyState {
  Vec3d position = Vec3d::Zero();  ///< centre of mass, as precisely as the engine keeps it
  Quat rotation = Quat::Identity();
  Vec3 linear_velocity = Vec3::Zero();
  Vec3 angular_velocity = Vec3::Zero();
};

class AccuracyEngine {
 public:
  virtual ~AccuracyEngine() = default;
  virtual std::string name() const = 0;
  /// Whether the setting means something to this engine: a switch the engine does not have would only repeat
  /// another setting's run (Bullet has no exact small-island solve).
  virtual bool Runs(const AccuracySetting& setting) const {
    (void)setting;
    return true;
  }
  /// Creates the scene's bodies (in order) with the setting's solver parameters.
  virtual Status Build(const SceneDescription& scene, const AccuracySetting& setting) = 0;
  /// One step of the setting's dt; its wall time is added to step_ms().
  virtual Status Step() = 0;
  virtual AccuracyBodyState State(std::size_t body) const = 0;
  /// Local inertia tensor (principal, in the body's axes) of a dynamic body.
  virtual Vec3 PrincipalInertia(std::size_t body) const = 0;
  double step_ms() const { return step_ms_; }

 protected:
  double step_ms_ = 0.0;
};

/// Strata on one thread.
std::unique_ptr<AccuracyEngine> MakeStrataEngine();
/// Bullet, when the build found it (else null).
std::unique_ptr<AccuracyEngine> MakeBulletEngine();

}  // namespace strata::accuracy
