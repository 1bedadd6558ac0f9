// SlidingFace: a face contact (ContactFace) kept in the frame of the body the face belongs to, and how its
// points are carried along when the other body slides over it: the same corners, pressed onto the same face
// plane at their new places. The body-pair cache uses it to skip the shape test of a box sliding on a floor.
// Plain data and pure functions; any thread.
#pragma once

#include <span>

#include "physics/math/Math.h"
#include "physics/narrowphase/ContactManifold.h"

namespace strata {

/// A ContactFace in its body's frame (from the body's centre of mass), with half the shortest edge of the
/// face whose corners are the points: pressed in deeper than that, another pair of faces could be the
/// contact.
struct SlidingFace {
  Vec3 centre;
  Vec3 u;
  Vec3 v;
  Vec3 normal;
  float half_u = 0.0f;
  float half_v = 0.0f;
  float corner_face_half = 0.0f;
  bool on_a = false;  ///< the face is A's and the corners are B's, or the other way round
  /// B's rotation relative to A's when the face was found: a caller carrying the corners along checks that
  /// the bodies have not turned far from it since (other corners could touch the face by then).
  Quat found_turn = Quat::Identity();
};

/// Where a body is: its centre of mass and its rotation as a matrix, viewed where the caller keeps them (a
/// copy stored field by field just before the call is re-read in wider loads, which stall on the stores).
struct PosedBody {
  const Vec3& center_of_mass;
  const Mat3& rotation;
};

/// The face of `manifold` (which must have a valid ContactFace) in the frame of its body, posed at
/// `face_body`, found with B turned by `turn` relative to A.
SlidingFace MakeSlidingFace(const ContactManifold& manifold, const PosedBody& face_body, const Quat& turn);

/// The contact of `corners` (the points' places on their body, from its centre of mass, in its frame, in the
/// order they were found) with `face`, the bodies now at `face_body` and `corner_body`: the corners pressed
/// onto the face plane, normal from A to B. False, leaving `out` as it was, if a fresh shape test must
/// decide: a corner beyond `max_separation` or off the face, or pressed in deeper than it is from the face's
/// sides or than `face.corner_face_half`. The caller also makes sure the bodies turned little since the face
/// was found (`found_turn`).
bool SlideCorners(const SlidingFace& face, const PosedBody& face_body, const PosedBody& corner_body,
                  std::span<const Vec3> corners, float max_separation, ContactManifold& out);

}  // namespace strata
