// Carrying a box's face contact along a slide (SlidingFace) against a fresh box-box test at the new place:
// random boxes on random floors, moved and turned a little (fixed seed), must give the same four contacts
// wherever the carry says it holds; and it must refuse where it would not (off the face, pressed deep).
#include <random>

#include "TestWorld.h"
#include "physics/narrowphase/BoxBoxCollider.h"
#include "physics/narrowphase/SlidingFace.h"

namespace strata::test {
namespace {

struct Placed {
  BoxShape floor, box;
  Pose floor_pose, box_pose;
};

// A box lying on a floor box (both turned about the floor's up axis by any angle, the box tipped by at most
// a hundredth of a degree, so that the faces meet flat), `depth` into it, somewhere over its top face.
Placed RandomBoxOnFloor(std::mt19937& random) {
  std::uniform_real_distribution<float> floor_extent(1.0f, 30.0f), box_extent(0.05f, 1.5f), unit(-1.0f, 1.0f),
      angle(-kPi, kPi), depth(-0.01f, 0.015f);
  const Vec3 floor_half(floor_extent(random), floor_extent(random), floor_extent(random));
  const Vec3 box_half(box_extent(random), box_extent(random), box_extent(random));
  const Quat floor_turn(Eigen::AngleAxisf(angle(random), Vec3::UnitY()));
  const Quat box_turn = floor_turn * Quat(Eigen::AngleAxisf(angle(random), Vec3::UnitY())) *
                        Quat(Eigen::AngleAxisf(1.7e-4f * unit(random), Vec3::UnitX()));
  const Vec3 floor_centre(200.0f * unit(random), 50.0f * unit(random), 200.0f * unit(random));
  const Vec3 across(0.9f * floor_half.x() * unit(random), 0, 0.9f * floor_half.z() * unit(random));
  const Vec3 box_centre =
      floor_centre + floor_turn * (across + Vec3(0, floor_half.y() + box_half.y() - depth(random), 0));
  return {BoxShape(floor_half, 0.0f), BoxShape(box_half, 0.0f), Pose{floor_centre, floor_turn},
          Pose{box_centre, box_turn}};
}

// A pose with its rotation as a matrix, for PosedBody to view.
struct PoseWithMatrix {
  explicit PoseWithMatrix(const Pose& pose)
      : position(pose.position), rotation(pose.rotation.toRotationMatrix()) {}
  operator PosedBody() const { return {position, rotation}; }  // NOLINT: implicit, where a PosedBody is taken
  Vec3 position;
  Mat3 rotation;
};

PoseWithMatrix Posed(const Pose& pose) {
  return PoseWithMatrix(pose);
}

// The manifold of the pair in the order asked (floor as A or as B).
bool Collide(const Placed& placed, bool floor_first, float max_separation, ContactManifold& manifold) {
  return floor_first ? CollideBoxes(placed.floor, placed.floor_pose, placed.box, placed.box_pose,
                                    max_separation, manifold)
                     : CollideBoxes(placed.box, placed.box_pose, placed.floor, placed.floor_pose,
                                    max_separation, manifold);
}

// Each point of `carried` has a point of `fresh` within `tolerance` on both bodies, with the same separation.
::testing::AssertionResult SameContacts(const ContactManifold& carried, const ContactManifold& fresh,
                                        float tolerance) {
  if (carried.count != fresh.count)
    return ::testing::AssertionFailure() << carried.count << " points against " << fresh.count;
  for (int i = 0; i < carried.count; ++i) {
    float nearest = kLargeFloat;
    int match = 0;
    for (int j = 0; j < fresh.count; ++j) {
      const float apart = (carried.points[i].position_a - fresh.points[j].position_a).norm() +
                          (carried.points[i].position_b - fresh.points[j].position_b).norm();
      if (apart < nearest) nearest = apart, match = j;
    }
    if (nearest > tolerance)
      return ::testing::AssertionFailure() << "point " << i << " is " << nearest << " off";
    if (std::abs(carried.points[i].separation - fresh.points[match].separation) > tolerance)
      return ::testing::AssertionFailure() << "point " << i << " separation " << carried.points[i].separation
                                           << " against " << fresh.points[match].separation;
  }
  return ::testing::AssertionSuccess();
}

TEST(SlidingFace, CarriedCornersAreTheContactsAFreshTestFindsWhereverTheCarryHolds) {
  std::mt19937 random(20261126);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), slide(0.0f, 3.0f), lift(-0.012f, 0.012f);
  constexpr float kMaxSeparation = 0.03f;
  int faces = 0, carried = 0, refused = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    Placed placed = RandomBoxOnFloor(random);
    const bool floor_first = trial % 2 == 0;
    ContactManifold before;
    if (!Collide(placed, floor_first, kMaxSeparation, before) || !before.face.valid) continue;
    ++faces;
    // The face is the floor's and the corners are the box's.
    ASSERT_EQ(before.face.on_a, floor_first) << "trial " << trial;
    ASSERT_EQ(before.count, 4) << "trial " << trial;
    const Pose& face_pose = placed.floor_pose;
    const SlidingFace face = MakeSlidingFace(before, Posed(face_pose), Quat::Identity());
    Vec3 corners[4];
    const auto to_box = placed.box_pose.rotation.conjugate();
    for (int i = 0; i < 4; ++i)
      corners[i] = to_box * ((floor_first ? before.points[i].position_b : before.points[i].position_a) -
                             placed.box_pose.position);

    // Slide the box up to 3 m over the floor, a centimetre up or down, and turn it by up to 0.9 degrees.
    const Vec3 up = face_pose.rotation * Vec3::UnitY();
    const Vec3 sideways = face_pose.rotation * Vec3(unit(random), 0, unit(random)).normalized();
    placed.box_pose.position += slide(random) * sideways + lift(random) * up;
    const Vec3 axis = Vec3(unit(random), unit(random), unit(random)).normalized();
    placed.box_pose.rotation =
        Quat(Eigen::AngleAxisf(0.9f * kPi / 180.0f * unit(random), axis)) * placed.box_pose.rotation;

    ContactManifold slid;
    if (!SlideCorners(face, Posed(face_pose), Posed(placed.box_pose), corners, kMaxSeparation, slid)) {
      ++refused;
      continue;
    }
    ++carried;
    ContactManifold fresh;
    ASSERT_TRUE(Collide(placed, floor_first, kMaxSeparation, fresh)) << "trial " << trial;
    EXPECT_GT(slid.normal.dot(fresh.normal), std::cos(1.0f * kPi / 180.0f)) << "trial " << trial;
    EXPECT_TRUE(SameContacts(slid, fresh, 2e-4f)) << "trial " << trial;
  }
  // Both answers came in quantity.
  EXPECT_GT(faces, 2000);
  EXPECT_GT(carried, faces / 3);
  EXPECT_GT(refused, faces / 10);
}

TEST(SlidingFace, ACornerOffTheFaceOrPressedDeepIsLeftToTheShapeTest) {
  const BoxShape floor(Vec3(5, 1, 5), 0.0f), box(Vec3(0.5f, 0.5f, 0.5f), 0.0f);
  const Pose floor_pose{Vec3(0, -1, 0), Quat::Identity()};
  const Pose box_pose{Vec3(0, 0.49f, 0), Quat::Identity()};
  ContactManifold before;
  ASSERT_TRUE(CollideBoxes(floor, floor_pose, box, box_pose, 0.02f, before));
  ASSERT_TRUE(before.face.valid);
  const SlidingFace face = MakeSlidingFace(before, Posed(floor_pose), Quat::Identity());
  EXPECT_NEAR(face.corner_face_half, 0.5f, 1e-5f);
  Vec3 corners[4];
  for (int i = 0; i < 4; ++i) corners[i] = before.points[i].position_b - box_pose.position;
  auto slide_to = [&](const Vec3& centre, ContactManifold& out) {
    return SlideCorners(face, Posed(floor_pose), Posed(Pose{centre, Quat::Identity()}), corners, 0.02f, out);
  };
  ContactManifold slid;
  // 4.4 m along: every corner is still over the floor, 1 cm in.
  ASSERT_TRUE(slide_to(Vec3(4.4f, 0.49f, 0), slid));
  ASSERT_EQ(slid.count, 4);
  EXPECT_TRUE(slid.normal.isApprox(Vec3::UnitY(), 1e-6f));
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(slid.points[i].separation, -0.01f, 1e-5f);
    EXPECT_NEAR(slid.points[i].position_a.y(), 0.0f, 1e-5f);
    EXPECT_NEAR(std::abs(slid.points[i].position_b.x() - 4.4f), 0.5f, 1e-5f);
  }
  const ContactManifold untouched = slid;
  // 4.6 m along: two corners hang over the edge (the test would cut the face). Out of the margin above. 1 cm
  // from the edge but 2 cm in (a side could be the way out).
  for (const Vec3& centre : {Vec3(4.6f, 0.49f, 0), Vec3(0, 0.53f, 0), Vec3(4.49f, 0.48f, 0)}) {
    EXPECT_FALSE(slide_to(centre, slid)) << centre.transpose();
    EXPECT_EQ(slid.points[0].position_b, untouched.points[0].position_b);
  }
  // 2 cm in, 3 cm from the edge: still the face.
  EXPECT_TRUE(slide_to(Vec3(4.47f, 0.48f, 0), slid));
}

}  // namespace
}  // namespace strata::test
