#include "physics/world/CollisionFinder.h"

#include <algorithm>
#include <cmath>
#include <span>

#include "physics/core/ForEachChunk.h"
#include "physics/narrowphase/CollideShapes.h"

namespace strata {

namespace {

// Active bodies per claimed batch: small enough to balance the jobs, large enough that claiming and
// pinning the broad phase are a small share of the work.
constexpr std::uint32_t kBodyBatch = 8;

// One pair's shape test writes its manifolds into a job buffer that is reused from step to step. A convex
// on a mesh yields one per distinct triangle normal it touches, and a body that rolls onto a crease for the
// first time can set a new record; starting every buffer at this size keeps such a step off the heap.
constexpr std::size_t kMinManifoldsPerJob = 32;

// Reserves for `count` with half again as much to spare, so that a count that creeps up from step to step
// (a pile settling into more contacts) grows the buffer once in a while instead of every step.
template <typename T>
void ReserveWithSlack(std::vector<T>& buffer, std::size_t count) {
  if (buffer.capacity() < count) buffer.reserve(count + count / 2);
}

}  // namespace

void CollisionFinder::BeginStep(const Input& input, std::uint32_t job_count) {
  // Any job may take any share of the work: size every job's buffers for all of last step's. One job alone
  // already holds all of it, and matching its capacities with itself is a fair share of a small world's step.
  const bool several_jobs = job_count > 1 || jobs_.size() > 1;
  const CollisionStats last = stats();
  std::size_t most_pairs = 0, most_manifolds = kMinManifoldsPerJob, most_triangles = 0, most_epa_vertices = 0,
              most_epa_faces = 0, most_horizon = 0, most_wake_keys = 0;
  for (const Job& job : several_jobs ? std::span<const Job>(jobs_) : std::span<const Job>()) {
    most_pairs = std::max(most_pairs, job.pairs.capacity());
    most_manifolds = std::max(most_manifolds, job.manifolds.capacity());
    most_triangles = std::max(most_triangles, job.scratch.triangles.capacity());
    most_epa_vertices = std::max(most_epa_vertices, job.scratch.epa.vertices.capacity());
    most_epa_faces = std::max(most_epa_faces, job.scratch.epa.faces.capacity());
    most_horizon = std::max(most_horizon, job.scratch.epa.horizon.capacity());
    most_wake_keys += job.wake_keys.size();
  }
  // Any job may find any reporting pair: each keeps room for all of last step's (none in a world without).
  std::size_t last_reported = 0;
  for (const Job& job : jobs_) last_reported += job.reported.size();
  input_ = input;
  job_count_ = job_count;
  const PhysicsSettings& settings = *input.settings;
  replay_max_distance_squared_ =
      settings.body_pair_cache_max_distance * settings.body_pair_cache_max_distance;
  slides_ = settings.body_pair_cache_slides && settings.body_pair_cache_max_distance > 0.0f;
  keeps_apart_ = settings.body_pair_cache_separating_axis && settings.body_pair_cache_max_distance > 0.0f;
  // A limit of 0 degrees allows no turn, but the product of two equal unit quaternions may round above 1.
  replays_ = settings.body_pair_cache_max_distance > 0.0f && settings.body_pair_cache_max_angle > 0.0f;
  // Quaternions measure half the angle. (A cosine is a fair share of a small world's step: only on a change.)
  if (settings.body_pair_cache_max_angle != replay_max_angle_) {
    replay_max_angle_ = settings.body_pair_cache_max_angle;
    replay_min_half_angle_cosine_ = std::cos(0.5f * replay_max_angle_ * kPi / 180.0f);
  }
  next_body_.store(0, std::memory_order_relaxed);
  pairs_claimed_.store(0, std::memory_order_relaxed);
  constraints_claimed_.store(0, std::memory_order_relaxed);
  if (jobs_.size() < job_count) {
    jobs_.resize(job_count);
    for (Job& job : jobs_) job.arena.SetPool(pool_);
  }
  for (Job& job : jobs_) {
    job.arena.Recycle();
    job.constraints.clear();
    job.island_body.clear();
    job.wake_keys.clear();
    job.reported.clear();
    job.reported_geometry.clear();
    ReserveWithSlack(job.reported, last_reported);
    ReserveWithSlack(job.reported_geometry, last_reported);
    // Counts from last step get slack; the largest capacity any job already holds is matched exactly (slack
    // on it would compound from job to job).
    ReserveWithSlack(job.constraints, last.constraints);
    ReserveWithSlack(job.island_body, last.constraints);
    ReserveWithSlack(job.pairs, last.pairs);
    job.stats = {};
    job.constraint_allowance = 0;
    if (!several_jobs) {
      job.manifolds.reserve(kMinManifoldsPerJob);
      continue;
    }
    ReserveWithSlack(job.wake_keys, most_wake_keys);
    job.pairs.reserve(most_pairs);
    job.manifolds.reserve(most_manifolds);
    job.scratch.triangles.reserve(most_triangles);
    job.scratch.epa.vertices.reserve(most_epa_vertices);
    job.scratch.epa.faces.reserve(most_epa_faces);
    job.scratch.epa.horizon.reserve(most_horizon);
  }
  body_contacts_.resize(input.active.size());
}

ContactSide CollisionFinder::ContactInputSide(const Side& side) const {
  ContactSide contact;
  contact.solver_index = side.solver_index;
  contact.dynamic = side.dynamic;
  contact.body = &input_.solver_bodies[side.solver_index];
  if (side.dynamic) contact.velocity_gain = ToVec3(input_.velocity_steps[side.solver_index].linear);
  contact.substep = input_.dt / static_cast<float>(input_.settings->substeps);
  return contact;
}

CollisionFinder::Side CollisionFinder::MakeSide(const Body& body) const {
  Side side;
  side.body = &body;
  side.solver_index = input_.solver_index[body.id().index];
  side.dynamic = side.solver_index != 0 && body.IsDynamic();
  if (side.solver_index != 0) {
    const SolverPose& pose = input_.solver_poses[side.solver_index];
    side.center_of_mass = ToVec3(pose.center_of_mass);
    side.rotation = pose.rotation;
    side.rotation_matrix = input_.solver_rotations[side.solver_index];
    return side;
  }
  side.center_of_mass = body.CenterOfMass();
  side.rotation = body.rotation();
  side.rotation_matrix = side.rotation.toRotationMatrix();
  return side;
}

void CollisionFinder::RunJob(std::uint32_t job_index, std::uint32_t width) {
  Job& job = jobs_[job_index];
  const auto active_count = static_cast<std::uint32_t>(input_.active.size());
  ForEachChunk(next_body_, active_count, kBodyBatch, width, [&](std::uint32_t begin, std::uint32_t end) {
    job.pairs.clear();
    // Once the pair budget is spent, the rest of the bodies' pairs are not even looked for: a pile of
    // thousands of bodies at one point would spend seconds a step finding pairs only to drop them.
    if (pairs_claimed_.load(std::memory_order_relaxed) >= input_.max_pairs) {
      job.stats.bodies_skipped += end - begin;
      for (std::uint32_t active = begin; active < end; ++active) {
        body_contacts_[active] = {job_index, static_cast<std::uint32_t>(job.constraints.size()),
                                  static_cast<std::uint32_t>(job.constraints.size())};
        input_.cache->BeginOwner(input_.active[active]);
      }
      return;
    }
    input_.broad_phase->FindPairs(input_.active.subspan(begin, end - begin), input_.active_flags,
                                  *input_.layers, job.pairs);
    // Tree order depends on which generation the query saw; pair order must not.
    std::sort(job.pairs.begin(), job.pairs.end());
    ClaimPairs(job);
    std::size_t next_pair = 0;
    for (std::uint32_t active = begin; active < end; ++active) {
      const BodyID owner = input_.active[active];
      BodyContacts& contacts = body_contacts_[active];
      contacts.job = job_index;
      contacts.begin = static_cast<std::uint32_t>(job.constraints.size());
      input_.cache->BeginOwner(owner);
      BodyPairCache::PreviousPairs previous = input_.cache->Previous(owner);
      while (next_pair < job.pairs.size() && job.pairs[next_pair].a == owner)
        CollidePair(job.pairs[next_pair++], previous, job_index);
      contacts.end = static_cast<std::uint32_t>(job.constraints.size());
    }
  });
}

void CollisionFinder::ClaimPairs(Job& job) {
  const std::size_t wanted = job.pairs.size();
  if (wanted == 0) return;
  const std::size_t before = pairs_claimed_.fetch_add(wanted, std::memory_order_relaxed);
  const std::size_t granted = before >= input_.max_pairs ? 0 : std::min(wanted, input_.max_pairs - before);
  if (granted == wanted) return;
  job.stats.pairs_dropped += wanted - granted;
  job.pairs.resize(granted);
}

bool CollisionFinder::ClaimConstraint(Job& job) {
  // Lots keep the shared counter off the per-manifold path; a job holds at most one lot unused.
  constexpr std::size_t kLot = 64;
  if (job.constraint_allowance == 0) {
    const std::size_t before = constraints_claimed_.fetch_add(kLot, std::memory_order_relaxed);
    if (before >= input_.max_constraints) {
      ++job.stats.constraints_dropped;
      return false;
    }
    job.constraint_allowance = std::min(kLot, input_.max_constraints - before);
  }
  --job.constraint_allowance;
  return true;
}

void CollisionFinder::CollidePair(BodyPair pair, BodyPairCache::PreviousPairs& previous_pairs,
                                  std::uint32_t job_index) {
  Job& job = jobs_[job_index];
  const Body& first = input_.bodies->BodyAt(pair.a.index);
  const Body& second = input_.bodies->BodyAt(pair.b.index);
  // The broad phase may briefly hold a body another thread is adding or removing.
  if (!second.in_world() || second.id() != pair.b) return;
  if (!first.IsDynamic() && !second.IsDynamic()) return;  // kinematic vs static or kinematic: no contact
  if (((first.event_flags() | second.event_flags()) & Body::kSensor) != 0) return;  // sensors never collide
  if (input_.jointed_pairs != nullptr && input_.jointed_pairs->Contains(pair.a.index, pair.b.index)) return;
  ++job.stats.pairs;
  // The owner is A; the dispatch table takes either order of shapes.
  const Side a = MakeSide(first);
  const Side b = MakeSide(second);

  const Quat inverse_a = a.rotation.conjugate();
  const Vec3 delta_position = a.rotation_matrix.transpose() * (b.center_of_mass - a.center_of_mass);
  const Quat delta_rotation = inverse_a * b.rotation;
  const CachedBodyPair* previous = previous_pairs.Find(pair.b);
  const bool replay =
      replays_ && previous != nullptr &&
      (delta_position - previous->delta_position).squaredNorm() < replay_max_distance_squared_ &&
      std::abs(delta_rotation.dot(previous->delta_rotation)) > replay_min_half_angle_cosine_;
  if (replay) {
    // A replayed pair keeps the pose its manifolds were made at, so slow drift still ends in a fresh test.
    CachedBodyPair& entry = *input_.cache->Create(job_index, pair.a, pair.b, a.body->id(), b.body->id(),
                                                  previous->delta_position, previous->delta_rotation);
    entry.separating_axis = previous->separating_axis;
    ++job.stats.pairs_replayed;
    ReplayManifolds(*previous, a, b, entry, job_index);
    return;
  }
  // Speculative contacts for what the bodies can close over the step: all round by their spin, and along
  // their relative travel.
  const ContactReach reach{
      input_.settings->speculative_distance + a.body->TurnBound(input_.dt) + b.body->TurnBound(input_.dt),
      b.body->LinearTravel(input_.dt) - a.body->LinearTravel(input_.dt)};
  if (previous != nullptr &&
      SlideManifold(pair, *previous, a, b, delta_position, delta_rotation, reach.Max(), job_index)) {
    ++job.stats.pairs_slid;
    return;
  }
  const bool convex_pair = keeps_apart_ && a.body->shape()->IsConvex() && b.body->shape()->IsConvex();
  if (convex_pair && previous != nullptr && KeptApart(*previous, a, b, reach.Max())) {
    CachedBodyPair& entry = *input_.cache->Create(job_index, pair.a, pair.b, a.body->id(), b.body->id(),
                                                  delta_position, delta_rotation);
    entry.separating_axis = previous->separating_axis;
    ++job.stats.pairs_kept_apart;
    return;
  }
  CachedBodyPair& entry = *input_.cache->Create(job_index, pair.a, pair.b, a.body->id(), b.body->id(),
                                                delta_position, delta_rotation);
  ContactManifold prototype;
  prototype.body_a = a.body->id();
  prototype.body_b = b.body->id();
  job.manifolds.clear();
  CollideShapes(*a.body->shape(), a.body->pose(), *b.body->shape(), b.body->pose(), reach, prototype,
                job.manifolds, job.scratch);
  if (convex_pair && job.manifolds.empty() && !job.scratch.separating_axis.isZero())
    entry.separating_axis = a.rotation_matrix.transpose() * job.scratch.separating_axis.normalized();
  for (const ContactManifold& manifold : job.manifolds) {
    const CachedManifold* match = nullptr;
    for (const CachedManifold* cached = previous ? previous->manifolds : nullptr; cached != nullptr && !match;
         cached = cached->next)
      if (cached->sub_shape_a == manifold.sub_shape_a && cached->sub_shape_b == manifold.sub_shape_b)
        match = cached;
    AddComputedManifold(manifold, a, b, entry, match, job_index);
  }
}

bool CollisionFinder::KeptApart(const CachedBodyPair& previous, const Side& a, const Side& b,
                                float max_separation) const {
  if (previous.separating_axis.isZero()) return false;
  // A margin over the contact test's own rounding, so that a pair passed over here is one it finds apart too.
  constexpr float kMargin = 1e-4f;
  const Pose& pose_a = a.body->pose();
  const Pose& pose_b = b.body->pose();
  return GapAlong(static_cast<const ConvexShape&>(*a.body->shape()), pose_a.position, a.rotation_matrix,
                  static_cast<const ConvexShape&>(*b.body->shape()), pose_b.position, b.rotation_matrix,
                  a.rotation_matrix * previous.separating_axis) > max_separation + kMargin;
}

void CollisionFinder::ReplayManifolds(const CachedBodyPair& previous, const Side& a, const Side& b,
                                      CachedBodyPair& entry, std::uint32_t job_index) {
  for (const CachedManifold* old = previous.manifolds; old != nullptr; old = old->next) {
    CachedManifold& cached = *input_.cache->AddManifold(job_index, entry, old->sub_shape_a, old->sub_shape_b,
                                                        old->normal_a, old->point_count, Reports(a, b));
    std::copy(old->points(), old->points() + old->point_count, cached.points());
    if (old->face != nullptr) input_.cache->SetFace(job_index, cached, *old->face);
    const Vec3 normal = a.rotation_matrix * old->normal_a;
    ContactArms arms[ContactManifold::kMaxPoints];
    for (std::uint32_t i = 0; i < old->point_count; ++i) {
      const CachedContactPoint& point = old->points()[i];
      const Vec3 r_a = a.rotation_matrix * point.local_a, r_b = b.rotation_matrix * point.local_b;
      arms[i] = {r_a, r_b, (b.center_of_mass + r_b - a.center_of_mass - r_a).dot(normal)};
    }
    AddConstraint(normal, std::span(arms, old->point_count), a, b, cached, job_index);
  }
}

bool CollisionFinder::SlideManifold(BodyPair pair, const CachedBodyPair& previous, const Side& a,
                                    const Side& b, const Vec3& delta_position, const Quat& delta_rotation,
                                    float max_separation, std::uint32_t job_index) {
  const CachedManifold* old = previous.manifolds;
  if (!slides_ || old == nullptr || old->next != nullptr || old->face == nullptr) return false;
  const SlidingFace& face = *old->face;
  // Turned since the face was found: other corners could be touching it.
  if (std::abs(delta_rotation.dot(face.found_turn)) <= replay_min_half_angle_cosine_) return false;
  Vec3 corners[ContactManifold::kMaxPoints];
  for (std::uint32_t i = 0; i < old->point_count; ++i)
    corners[i] = face.on_a ? old->points()[i].local_b : old->points()[i].local_a;
  ContactManifold slid;
  const PosedBody frame_a{a.center_of_mass, a.rotation_matrix}, frame_b{b.center_of_mass, b.rotation_matrix};
  if (!SlideCorners(face, face.on_a ? frame_a : frame_b, face.on_a ? frame_b : frame_a,
                    std::span<const Vec3>(corners, old->point_count), max_separation, slid))
    return false;

  // The face keeps the turn it was found at, so a slow turn still ends in a fresh test; the entry takes the
  // pose now, so a box that stops sliding replays from the next step on.
  CachedBodyPair& entry = *input_.cache->Create(job_index, pair.a, pair.b, a.body->id(), b.body->id(),
                                                delta_position, delta_rotation);
  const auto to_a = a.rotation_matrix.transpose();
  const auto to_b = b.rotation_matrix.transpose();
  CachedManifold& cached = *input_.cache->AddManifold(job_index, entry, old->sub_shape_a, old->sub_shape_b,
                                                      to_a * slid.normal, old->point_count, Reports(a, b));
  input_.cache->SetFace(job_index, cached, face);
  ContactArms arms[ContactManifold::kMaxPoints];
  for (int i = 0; i < slid.count; ++i) {
    const ContactPoint& contact = slid.points[i];
    // The arms from values in registers: read back from arms[i] right after it was stored (in pieces that
    // straddle r_a and r_b), they stall on the stores.
    const Vec3 r_a = contact.position_a - a.center_of_mass, r_b = contact.position_b - b.center_of_mass;
    arms[i] = {r_a, r_b, contact.separation};
    // The same corners as last step, in the same order: each keeps its impulses and its place on its body.
    CachedContactPoint& point = cached.points()[i];
    point = old->points()[i];
    if (face.on_a)
      point.local_a = to_a * r_a;
    else
      point.local_b = to_b * r_b;
  }
  AddConstraint(slid.normal, std::span(arms, old->point_count), a, b, cached, job_index);
  return true;
}

void CollisionFinder::AddComputedManifold(const ContactManifold& manifold, const Side& a, const Side& b,
                                          CachedBodyPair& entry, const CachedManifold* previous,
                                          std::uint32_t job_index) {
  // Inverse rotations applied as transposed products; no 3x3 copies (GCC's -O1 sanitizer builds also
  // flagged those copies as maybe-uninitialized).
  const auto to_a = a.rotation_matrix.transpose();
  const auto to_b = b.rotation_matrix.transpose();
  CachedManifold& cached = *input_.cache->AddManifold(
      job_index, entry, manifold.sub_shape_a, manifold.sub_shape_b, to_a * manifold.normal,
      static_cast<std::uint32_t>(manifold.count), Reports(a, b));
  if (manifold.face.valid) {
    const Side& owner = manifold.face.on_a ? a : b;
    input_.cache->SetFace(
        job_index, cached,
        MakeSlidingFace(manifold, {owner.center_of_mass, owner.rotation_matrix}, entry.delta_rotation));
  }
  const float match_distance_squared =
      input_.settings->contact_match_distance * input_.settings->contact_match_distance;
  ContactArms arms[ContactManifold::kMaxPoints];
  for (int i = 0; i < manifold.count; ++i) {
    const Vec3 r_a = manifold.points[i].position_a - a.center_of_mass,
               r_b = manifold.points[i].position_b - b.center_of_mass;
    arms[i] = {r_a, r_b, manifold.points[i].separation};
    CachedContactPoint& point = cached.points()[i];
    point.local_a = to_a * r_a;
    point.local_b = to_b * r_b;
    point.normal_impulse = 0.0f;
    point.friction_impulse = Vec3::Zero();
    // Warm start from last step's point at the same place on A, if any.
    for (std::uint32_t k = 0; previous != nullptr && k < previous->point_count; ++k) {
      const CachedContactPoint& old = previous->points()[k];
      if ((old.local_a - point.local_a).squaredNorm() > match_distance_squared) continue;
      point.normal_impulse = old.normal_impulse;
      point.friction_impulse = old.friction_impulse;
      break;
    }
  }
  AddConstraint(manifold.normal, std::span(arms, static_cast<std::size_t>(manifold.count)), a, b, cached,
                job_index);
}

void CollisionFinder::AddConstraint(const Vec3& normal, std::span<const ContactArms> arms, const Side& a,
                                    const Side& b, CachedManifold& cached, std::uint32_t job_index) {
  Job& job = jobs_[job_index];
  const PhysicsSettings& settings = *input_.settings;
  const std::uint8_t flags = a.body->event_flags() | b.body->event_flags();
  if ((flags & Body::kValidateContacts) != 0 && input_.validator != nullptr && !Validate(normal, arms, a, b))
    return;
  ++job.stats.manifolds;
  job.stats.contact_points += arms.size();
  // A sleeping body stays put (the fixed body) this step and wakes, with its island, for the next one.
  float closest = kLargeFloat;
  for (const ContactArms& point : arms) closest = std::min(closest, point.separation);
  if (closest <= settings.speculative_distance) {
    if (a.body->sleeping() && b.body->IsActive()) job.wake_keys.push_back(a.body->sleep_island());
    if (b.body->sleeping() && a.body->IsActive()) job.wake_keys.push_back(b.body->sleep_island());
  }
  if (!a.dynamic && !b.dynamic) {
    if (cached.reports) Report(normal, arms, a, b, nullptr, cached, job);
    return;
  }
  if (!ClaimConstraint(job)) return;
  ContactConstraint* constraint =
      BuildContactConstraint(job.arena, normal, arms, ContactInputSide(a), ContactInputSide(b),
                             std::sqrt(a.body->friction() * b.body->friction()),
                             std::max(a.body->restitution(), b.body->restitution()), &cached);
  job.constraints.push_back(constraint);
  ++job.stats.constraints;
  // The island is that of a body the solver moves; two moving bodies join their islands.
  const std::uint32_t island_a = a.solver_index - 1, island_b = b.solver_index - 1;
  job.island_body.push_back(a.dynamic ? island_a : island_b);
  if (a.dynamic && b.dynamic) {
    job.stats.link_hops += input_.islands->Link(island_a, island_b);
    ++job.stats.links;
  }
  if (cached.reports) Report(normal, arms, a, b, constraint, cached, job);
}

namespace {

// Where a manifold point's two surfaces meet, midway between the point on A and the point on B: the
// midpoint of the bodies' centres of mass plus the mean of the arms.
Vec3 MidPoint(const ContactArms& arms, const Vec3& centers_midpoint) {
  return centers_midpoint + 0.5f * (arms.r_a + arms.r_b);
}

}  // namespace

bool CollisionFinder::Validate(const Vec3& normal, std::span<const ContactArms> arms, const Side& a,
                               const Side& b) const {
  ContactCandidate candidate{*a.body, *b.body, normal, kLargeFloat, static_cast<int>(arms.size()), {}};
  const Vec3 centers_midpoint = 0.5f * (a.center_of_mass + b.center_of_mass);
  for (std::size_t i = 0; i < arms.size(); ++i) {
    candidate.separation = std::min(candidate.separation, arms[i].separation);
    candidate.points[i] = MidPoint(arms[i], centers_midpoint);
  }
  return (*input_.validator)(candidate);
}

bool CollisionFinder::Reports(const Side& a, const Side& b) {
  return ((a.body->event_flags() | b.body->event_flags()) & Body::kReportContacts) != 0;
}

void CollisionFinder::Report(const Vec3& normal, std::span<const ContactArms> arms, const Side& a,
                             const Side& b, const ContactConstraint* constraint, const CachedManifold& cached,
                             Job& job) const {
  ReportedManifold& reported = job.reported.emplace_back();
  ReportedGeometry& geometry = job.reported_geometry.emplace_back();
  reported.a = a.body->id();
  reported.b = b.body->id();
  reported.impulses = cached.reported_impulses();
  reported.point_count = static_cast<int>(arms.size());
  geometry.normal = normal;
  const Vec3 centers_midpoint = 0.5f * (a.center_of_mass + b.center_of_mass);
  float closest = kLargeFloat, fastest = 0.0f;
  for (std::size_t i = 0; i < arms.size(); ++i) {
    const Vec3 point = MidPoint(arms[i], centers_midpoint);
    geometry.points[i] = point;
    closest = std::min(closest, arms[i].separation);
    // The solver's approach at impact where it has the contact; else (neither side moves this step) the
    // bodies' velocities now.
    const float normal_velocity =
        constraint != nullptr ? constraint->points()[i].normal_velocity
                              : (b.body->PointVelocity(point) - a.body->PointVelocity(point)).dot(normal);
    fastest = std::max(fastest, -normal_velocity);
  }
  reported.separation = closest;
  reported.approach_speed = fastest;
}

void CollisionFinder::Gather(std::vector<ContactConstraint*>& constraints,
                             std::vector<std::uint32_t>& island_body) const {
  constraints.clear();
  island_body.clear();
  for (const BodyContacts& contacts : body_contacts_) {
    const Job& job = jobs_[contacts.job];
    constraints.insert(constraints.end(), job.constraints.begin() + contacts.begin,
                       job.constraints.begin() + contacts.end);
    island_body.insert(island_body.end(), job.island_body.begin() + contacts.begin,
                       job.island_body.begin() + contacts.end);
  }
}

void CollisionFinder::CollectWakeKeys(std::vector<std::uint32_t>& out) const {
  for (std::uint32_t j = 0; j < job_count_; ++j)
    out.insert(out.end(), jobs_[j].wake_keys.begin(), jobs_[j].wake_keys.end());
}

std::size_t CollisionFinder::arena_bytes() const {
  std::size_t total = 0;
  for (const Job& job : jobs_) total += job.arena.bytes_in_use();
  return total;
}

CollisionStats CollisionFinder::stats() const {
  CollisionStats total;
  for (std::uint32_t j = 0; j < job_count_; ++j) {
    const CollisionStats& s = jobs_[j].stats;
    total.pairs += s.pairs;
    total.pairs_replayed += s.pairs_replayed;
    total.pairs_slid += s.pairs_slid;
    total.pairs_kept_apart += s.pairs_kept_apart;
    total.pairs_dropped += s.pairs_dropped;
    total.bodies_skipped += s.bodies_skipped;
    total.constraints_dropped += s.constraints_dropped;
    total.manifolds += s.manifolds;
    total.contact_points += s.contact_points;
    total.constraints += s.constraints;
    total.link_hops += s.link_hops;
    total.links += s.links;
  }
  return total;
}

}  // namespace strata
