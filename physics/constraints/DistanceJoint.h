// DistanceJoint: keeps an anchor on A and one on B at a distance: rigid (a rod), within a range (a rope
// when the least distance is 0), or pulled towards a rest length by a spring of a given frequency and
// damping ratio, within the range. Threading as Constraint.
#pragma once

#include <memory>

#include "physics/constraints/AxisConstraintPart.h"
#include "physics/constraints/Constraint.h"

namespace strata {

struct DistanceJointSettings : JointSettingsBase {
  Vec3 anchor_a = Vec3::Zero();  ///< world
  Vec3 anchor_b = Vec3::Zero();  ///< world
  /// Negative: the distance between the anchors when the joint is added.
  float rest_length = -1.0f;
  float min_distance = -1.0f;  ///< negative: the rest length
  float max_distance = -1.0f;  ///< negative: the rest length
  float spring_hertz = 0.0f;   ///< 0: no spring (rigid at the rest length, or free within the range)
  float spring_damping_ratio = 1.0f;
};

class DistanceJoint final : public Constraint {
 public:
  static Result<std::unique_ptr<DistanceJoint>> Create(const DistanceJointSettings& settings,
                                                       const BodyFrame& a, const BodyFrame& b);

  std::string Describe() const override;
  void WarmStart(ConstraintBodies& bodies, const ConstraintPassContext& pass) override;
  void SolveVelocity(ConstraintBodies& bodies, const ConstraintPassContext& pass, bool rigid_rows) override;
  int RigidRowCount() const override;
  void RigidRows(const ConstraintBodies& bodies, JointRow* rows) override;
  int FreeRows(const ConstraintBodies& bodies, const ConstraintPassContext& pass, JointRow* rows) override;
  int FreeRowPasses(const ConstraintPassContext& pass, FreeRowPass* rows) override;

  float rest_length() const { return rest_length_; }
  float min_distance() const { return min_distance_; }
  float max_distance() const { return max_distance_; }

 private:
  DistanceJoint(const DistanceJointSettings& settings, const LocalFrames& frames, float rest, float least,
                float most);
  Impulses AccumulatedImpulses() const override;
  void ScaleImpulses(float ratio) override;
  // The unit axis from A's anchor to B's and the distance, keeping the last axis when the anchors meet.
  float Axis(const Vec3& separation);
  // The rows and the distance at the pass's poses (see NeedsSetUp).
  void SetUp(const ConstraintBodies& bodies, const ConstraintPassContext& pass);
  // The rows of a distance that is not rigid a pass solves (spring, lower and upper limit) and their parts;
  // returns how many.
  int SoftRows(const ConstraintPassContext& pass, FreeRowPass* rows, AxisConstraintPart** parts);
  bool rigid() const { return spring_hertz_ <= 0.0f && min_distance_ == max_distance_; }

  float rest_length_;
  float min_distance_;
  float max_distance_;
  float spring_hertz_;
  float spring_damping_ratio_;
  Vec3 axis_ = Vec3::UnitY();
  float distance_ = 0.0f;      // m, at the set-up poses
  AxisConstraintPart spring_;  // the rigid row, or the spring
  AxisConstraintPart lower_;
  AxisConstraintPart upper_;
};

}  // namespace strata
