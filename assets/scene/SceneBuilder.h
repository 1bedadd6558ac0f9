// SceneBuilder: Strata's shapes, bodies and joints from a SceneDescription, the one way the benchmarks and
// the accuracy cases turn their engine-neutral scenes into Strata's. Pure functions; any thread.
#pragma once

#include <span>

#include "assets/scene/SceneDescription.h"
#include "physics/body/BodyCreationSettings.h"
#include "physics/constraints/ConstraintManager.h"

namespace strata {

/// The shape of `body`; a hull, mesh or height field from `scene`'s geometry. Fails on degenerate data.
Result<ShapeRef> MakeShape(const SceneDescription& scene, const BodyDescription& body);
/// Strata's settings for `body` with `shape`: static or dynamic (and its layer), pose, material, mass (when
/// given; else the shape's at the default density) and velocities.
BodyCreationSettings ToBodySettings(const BodyDescription& body, ShapeRef shape);
/// Strata's settings for `joint` between the bodies `ids` (the scene's bodies in order).
JointSettings ToJointSettings(const JointDescription& joint, std::span<const BodyID> ids);

}  // namespace strata
