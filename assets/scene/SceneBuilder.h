// SceneBuilder: Strata's settings, shapes, bodies and joints from a SceneDescription, the one way the scene
// loader, the benchmarks and the accuracy cases turn their engine-neutral scenes into Strata's. Pure
// functions; any thread.
#pragma once

#include <span>
#include <vector>

#include "assets/scene/SceneDescription.h"
#include "physics/body/BodyCreationSettings.h"
#include "physics/constraints/ConstraintManager.h"

namespace strata {

/// The world settings of `scene`: gravity, iterations, contact tuning, sleeping.
PhysicsSettings ToPhysicsSettings(const SceneDescription& scene);
/// The shape of `body`; a hull, mesh or height field from `scene`'s geometry. Fails on degenerate data or a
/// geometry index past the scene's list.
Result<ShapeRef> MakeShape(const SceneDescription& scene, const BodyDescription& body);
/// Every body's shape, in order; bodies naming the same hull, mesh or height field share one shape, as a
/// game would. The error names the first body whose shape fails.
Result<std::vector<ShapeRef>> MakeShapes(const SceneDescription& scene);
/// Strata's settings for `body` with `shape`: motion (and its layer; a sensor's is always the moving one),
/// pose, material, mass (given, or from the density), velocities and the tunings that are set.
BodyCreationSettings ToBodySettings(const BodyDescription& body, ShapeRef shape);
/// Strata's settings for `joint` between the bodies `ids` (the scene's bodies in order).
JointSettings ToJointSettings(const JointDescription& joint, std::span<const BodyID> ids);

}  // namespace strata
