#include "tools/accuracy/AccuracyCases.h"

#include <array>
#include <cmath>
#include <limits>

#include "physics/PhysicsSettings.h"

namespace strata::accuracy {

namespace {

constexpr float kGravity = 9.81f;
constexpr double kInfinite = std::numeric_limits<double>::infinity();

bool IsFiniteState(const AccuracyBodyState& s) {
  return s.position.allFinite() && IsFinite(s.linear_velocity) && IsFinite(s.angular_velocity) &&
         IsFinite(s.rotation);
}

// Builds `scene`, steps it for `seconds` and calls `observe(time)` after every step. Fails on an engine
// error; a non-finite state of any body ends the run with finite = false.
Result<bool> Run(AccuracyEngine& engine, const SceneDescription& scene, const AccuracySetting& setting,
                 double seconds, const std::function<void(double)>& observe = {}) {
  if (Status built = engine.Build(scene, setting); !built) return built.error();
  const int steps = static_cast<int>(std::ceil(seconds / setting.dt - 1e-6));
  for (int step = 1; step <= steps; ++step) {
    if (Status stepped = engine.Step(); !stepped) return stepped.error();
    for (std::size_t body = 0; body < scene.bodies.size(); ++body)
      if (scene.bodies[body].IsDynamic() && !IsFiniteState(engine.State(body))) return false;
    if (observe) observe(step * static_cast<double>(setting.dt));
  }
  return true;
}

Result<CaseOutcome> Outcome(const Result<bool>& ran, double error) {
  if (!ran) return ran.error();
  if (!*ran) return CaseOutcome{kInfinite, false};
  if (!std::isfinite(error)) return CaseOutcome{kInfinite, true};  // e.g. a box that fell off its support
  return CaseOutcome{error, true};
}

BodyDescription StaticBox(const Vec3& half_extents, const Vec3& position,
                          const Quat& rotation = Quat::Identity(), float friction = 0.5f) {
  BodyDescription body;
  body.half_extents = half_extents;
  body.position = position;
  body.rotation = rotation;
  body.motion = SceneMotion::kStatic;
  body.friction = friction;
  return body;
}

BodyDescription Floor(float friction = 0.5f, const Vec3& at = Vec3::Zero()) {
  return StaticBox(Vec3(50, 1, 50), at + Vec3(0, -1, 0), Quat::Identity(), friction);
}

BodyDescription DynamicBox(const Vec3& half_extents, const Vec3& position, float friction = 0.5f) {
  BodyDescription body;
  body.half_extents = half_extents;
  body.position = position;
  body.friction = friction;
  return body;
}

BodyDescription DynamicSphere(float radius, const Vec3& position, float friction = 0.5f) {
  BodyDescription body;
  body.shape = SceneShape::kSphere;
  body.radius = radius;
  body.position = position;
  body.friction = friction;
  return body;
}

Result<CaseOutcome> FreeFall(AccuracyEngine& engine, const AccuracySetting& setting) {
  SceneDescription scene;
  scene.bodies.push_back(DynamicSphere(0.5f, Vec3::Zero()));
  constexpr double kSeconds = 2.0;
  const Result<bool> ran = Run(engine, scene, setting, kSeconds);
  const double drop = 0.5 * kGravity * kSeconds * kSeconds;
  return Outcome(ran, ran && *ran ? std::abs(-engine.State(0).position.y() - drop) / drop : 0.0);
}

// A box on a floor tilted by `degrees` about z: returns how far it moved along the slope in `seconds`.
Result<CaseOutcome> Incline(AccuracyEngine& engine, const AccuracySetting& setting, float degrees,
                            float friction, bool sphere, double expected_acceleration, bool relative) {
  const Quat tilt(Eigen::AngleAxisf(degrees * kPi / 180.0f, Vec3::UnitZ()));
  const Vec3 up = tilt * Vec3::UnitY();
  SceneDescription scene;
  scene.bodies.push_back(StaticBox(Vec3(50, 1, 50), -up, tilt, friction));
  BodyDescription body = sphere ? DynamicSphere(0.5f, 0.5f * up, friction)
                                : DynamicBox(Vec3::Constant(0.5f), 0.5f * up, friction);
  body.rotation = tilt;
  scene.bodies.push_back(body);
  constexpr double kSeconds = 2.0;
  const Result<bool> ran = Run(engine, scene, setting, kSeconds);
  if (!ran || !*ran) return Outcome(ran, 0.0);
  const double moved = (engine.State(1).position - body.position.cast<double>()).norm();
  const double expected = 0.5 * expected_acceleration * kSeconds * kSeconds;
  return Outcome(ran, relative ? std::abs(moved - expected) / expected : std::abs(moved - expected));
}

// Balls with restitution 0.8 dropped from 1.3, 1.7 and 2 m side by side: the worst rebound against e^2 h.
// Three heights, because where in a step the impact falls moves one drop's error by several percent either
// way (one height measures that phase as much as the engine).
Result<CaseOutcome> RestitutionApex(AccuracyEngine& engine, const AccuracySetting& setting) {
  constexpr float kRestitution = 0.8f;
  constexpr std::array<float, 3> kDrops = {1.3f, 1.7f, 2.0f};
  SceneDescription scene;
  scene.bodies.push_back(Floor());
  for (std::size_t i = 0; i < kDrops.size(); ++i) {
    BodyDescription ball = DynamicSphere(0.5f, Vec3(3.0f * static_cast<float>(i), 0.5f + kDrops[i], 0));
    ball.restitution = kRestitution;
    scene.bodies.push_back(ball);
  }
  std::array<bool, 3> bounced{}, falling_again{};
  std::array<double, 3> apex{};
  const Result<bool> ran = Run(engine, scene, setting, 2.0, [&](double) {
    for (std::size_t i = 0; i < kDrops.size(); ++i) {
      const AccuracyBodyState s = engine.State(i + 1);
      if (!bounced[i] && s.linear_velocity.y() > 0.0f) bounced[i] = true;
      if (bounced[i] && !falling_again[i]) {
        apex[i] = std::max(apex[i], s.position.y() - 0.5);
        falling_again[i] = s.linear_velocity.y() < 0.0f;
      }
    }
  });
  double worst = 0.0;
  for (std::size_t i = 0; i < kDrops.size(); ++i) {
    const double expected = kRestitution * kRestitution * kDrops[i];
    worst = std::max(worst, bounced[i] ? std::abs(apex[i] - expected) / expected : kInfinite);
  }
  return Outcome(ran, worst);
}

// Two spheres meet head on in zero gravity; the error is the largest velocity error after, over the
// approach speed.
Result<CaseOutcome> Collision(AccuracyEngine& engine, const AccuracySetting& setting, float restitution) {
  constexpr float kMassA = 1.0f, kMassB = 3.0f, kSpeed = 2.0f;
  SceneDescription scene;
  scene.gravity = Vec3::Zero();
  BodyDescription a = DynamicSphere(0.5f, Vec3(0, 0, 0), 0.0f), b = DynamicSphere(0.5f, Vec3(2, 0, 0), 0.0f);
  a.mass = kMassA, b.mass = kMassB;
  a.restitution = b.restitution = restitution;
  a.linear_velocity = Vec3(kSpeed, 0, 0);
  scene.bodies = {a, b};
  const Result<bool> ran = Run(engine, scene, setting, 2.0);
  if (!ran || !*ran) return Outcome(ran, 0.0);
  // Restitution e: v_a' = (m_a v - e m_b v) / (m_a + m_b), v_b' = m_a v (1 + e) / (m_a + m_b).
  const double va = (kMassA - restitution * kMassB) * kSpeed / (kMassA + kMassB);
  const double vb = kMassA * (1.0 + restitution) * kSpeed / (kMassA + kMassB);
  const Vec3 got_a = engine.State(0).linear_velocity, got_b = engine.State(1).linear_velocity;
  const double error = std::max((got_a - Vec3(static_cast<float>(va), 0, 0)).norm(),
                                (got_b - Vec3(static_cast<float>(vb), 0, 0)).norm());
  return Outcome(ran, error / kSpeed);
}

Vec3 AngularMomentum(const AccuracyBodyState& s, const Vec3& inertia) {
  const Vec3 local = s.rotation.conjugate() * s.angular_velocity;
  return s.rotation * Vec3(inertia.cwiseProduct(local));
}

// A box spinning about a non-principal axis in zero gravity for 10 s: largest |L(t) - L(0)| / |L(0)|.
Result<CaseOutcome> AngularMomentumDrift(AccuracyEngine& engine, const AccuracySetting& setting) {
  SceneDescription scene;
  scene.gravity = Vec3::Zero();
  BodyDescription box = DynamicBox(Vec3(0.5f, 0.3f, 0.1f), Vec3::Zero());
  box.rotation = Quat(Eigen::AngleAxisf(0.7f, Vec3(1, 2, 3).normalized()));
  box.angular_velocity = Vec3(1.0f, 2.0f, 3.0f);
  scene.bodies.push_back(box);
  Vec3 start = Vec3::Zero(), inertia = Vec3::Zero();
  double worst = 0.0;
  bool first = true;
  const Result<bool> ran = Run(engine, scene, setting, 10.0, [&](double) {
    if (first) {
      inertia = engine.PrincipalInertia(0);
      AccuracyBodyState initial;
      initial.rotation = box.rotation;
      initial.angular_velocity = box.angular_velocity;
      start = AngularMomentum(initial, inertia);
      first = false;
    }
    worst = std::max(worst, static_cast<double>((AngularMomentum(engine.State(0), inertia) - start).norm() /
                                                start.norm()));
  });
  return Outcome(ran, worst);
}

// Spin about the intermediate axis with a small perturbation: when does it first flip, against RK4?
Result<CaseOutcome> IntermediateAxisFlip(AccuracyEngine& engine, const AccuracySetting& setting) {
  SceneDescription scene;
  scene.gravity = Vec3::Zero();
  BodyDescription box = DynamicBox(Vec3(0.5f, 0.3f, 0.1f), Vec3::Zero());
  const Vec3 spin(0.02f, 4.0f, 0.02f);  // body frame = world frame at the start
  box.angular_velocity = spin;
  scene.bodies.push_back(box);
  double flipped = -1.0;
  Vec3 inertia = Vec3::Zero();
  const Result<bool> ran = Run(engine, scene, setting, 6.0, [&](double time) {
    if (inertia.isZero()) inertia = engine.PrincipalInertia(0);
    const AccuracyBodyState s = engine.State(0);
    if (flipped < 0.0 && (s.rotation.conjugate() * s.angular_velocity).y() < 0.0f) flipped = time;
  });
  if (!ran || !*ran) return Outcome(ran, 0.0);
  const double reference = IntermediateAxisFlipTime(inertia, spin, 6.0);
  if (reference <= 0.0) return MakeError(ErrorCode::kInvalidArgument, "the RK4 reference never flips");
  return Outcome(ran, flipped < 0.0 ? 1.0 : std::abs(flipped - reference) / reference);
}

double KineticEnergy(const AccuracyBodyState& s, float mass, const Vec3& inertia) {
  const Vec3 local = s.rotation.conjugate() * s.angular_velocity;
  return 0.5 * mass * s.linear_velocity.squaredNorm() + 0.5 * local.dot(inertia.cwiseProduct(local));
}

// A frictionless box sliding between two walls with restitution 1 for 60 s: the largest relative change of
// its mechanical energy (kinetic plus potential) at any step. Every step counts, not just the last: a box
// that a wall hit sets tumbling and hopping trades kinetic for potential energy and back, so the end alone
// can look right after a run that gained several times its energy on the way.
Result<CaseOutcome> EnergyDrift(AccuracyEngine& engine, const AccuracySetting& setting) {
  const SceneDescription scene = SlidingBoxScene();
  const std::size_t slider = 3;
  const BodyDescription& box = scene.bodies[slider];
  const double start = 0.5 * box.mass * box.linear_velocity.squaredNorm();  // it starts without spin
  double worst = 0.0;
  const Result<bool> ran = Run(engine, scene, setting, 60.0, [&](double) {
    const AccuracyBodyState now = engine.State(slider);
    const double potential_per_kg =
        -(now.position - box.position.cast<double>()).dot(scene.gravity.cast<double>());
    const double energy =
        KineticEnergy(now, box.mass, engine.PrincipalInertia(slider)) + box.mass * potential_per_kg;
    worst = std::max(worst, std::abs(energy - start) / start);
  });
  if (!ran || !*ran) return Outcome(ran, 0.0);
  return Outcome(ran, worst);
}

// A tower of `count` unit boxes for 10 s: how far the top box moved (m).
Result<CaseOutcome> Tower(AccuracyEngine& engine, const AccuracySetting& setting, int count) {
  SceneDescription scene;
  scene.bodies.push_back(Floor());
  for (int i = 0; i < count; ++i)
    scene.bodies.push_back(DynamicBox(Vec3::Constant(0.5f), Vec3(0, 0.5f + static_cast<float>(i), 0)));
  const Result<bool> ran = Run(engine, scene, setting, 10.0);
  if (!ran || !*ran) return Outcome(ran, 0.0);
  const std::size_t top = scene.bodies.size() - 1;
  return Outcome(ran, (engine.State(top).position - scene.bodies[top].position.cast<double>()).norm());
}

// A heavy unit box resting on a 1 kg one for 5 s: how far the heavy one got from where it rests, after the
// first second (m): sinking, or sliding off.
Result<CaseOutcome> MassRatio(AccuracyEngine& engine, const AccuracySetting& setting, float ratio) {
  const SceneDescription scene = HeavyOnLightScene(ratio);
  const BodyDescription& heavy = scene.bodies[2];
  double farthest = 0.0;
  const Result<bool> ran = Run(engine, scene, setting, 5.0, [&](double time) {
    if (time > 1.0)
      farthest = std::max(farthest, (engine.State(2).position - heavy.position.cast<double>()).norm());
  });
  return Outcome(ran, farthest);
}

// A 5 cm sphere at 500 m/s against a 10 cm static wall: how far past the wall's face it got (m).
Result<CaseOutcome> FastBodyThinWall(AccuracyEngine& engine, const AccuracySetting& setting) {
  SceneDescription scene;
  scene.gravity = Vec3::Zero();
  scene.bodies.push_back(StaticBox(Vec3(0.05f, 2, 2), Vec3(10, 0, 0)));
  BodyDescription bullet = DynamicSphere(0.05f, Vec3::Zero());
  bullet.linear_velocity = Vec3(500, 0, 0);
  scene.bodies.push_back(bullet);
  double farthest = 0.0;
  const double face = 10.0 - 0.05 - 0.05;  // where the sphere's centre is when it touches
  const Result<bool> ran = Run(engine, scene, setting, 0.2, [&](double) {
    farthest = std::max(farthest, engine.State(1).position.x() - face);
  });
  return Outcome(ran, farthest);
}

// A frictionless box sliding at 2 cm/s on a floor 10 km from the origin: relative error of its travel.
Result<CaseOutcome> FarFromOrigin(AccuracyEngine& engine, const AccuracySetting& setting) {
  const Vec3 far(10000.0f, 0.0f, 10000.0f);
  SceneDescription scene;
  scene.bodies.push_back(Floor(0.0f, far));
  BodyDescription box = DynamicBox(Vec3::Constant(0.5f), far + Vec3(0, 0.5f, 0), 0.0f);
  box.linear_velocity = Vec3(0.02f, 0, 0);
  scene.bodies.push_back(box);
  constexpr double kSeconds = 2.0;
  const Result<bool> ran = Run(engine, scene, setting, kSeconds);
  if (!ran || !*ran) return Outcome(ran, 0.0);
  const double travelled = engine.State(1).position.x() - box.position.x();
  const double expected = 0.02 * kSeconds;
  return Outcome(ran, std::abs(travelled - expected) / expected);
}

}  // namespace

SceneDescription SlidingBoxScene() {
  SceneDescription scene;
  BodyDescription left = StaticBox(Vec3(0.5f, 2, 5), Vec3(-5, 1, 0), Quat::Identity(), 0.0f);
  BodyDescription right = StaticBox(Vec3(0.5f, 2, 5), Vec3(5, 1, 0), Quat::Identity(), 0.0f);
  BodyDescription slider = DynamicBox(Vec3::Constant(0.5f), Vec3(0, 0.5f, 0), 0.0f);
  slider.mass = 1.0f;
  slider.restitution = 1.0f;
  slider.linear_velocity = Vec3(3, 0, 0);
  scene.bodies = {Floor(0.0f), left, right, slider};
  return scene;
}

SceneDescription HeavyOnLightScene(float ratio) {
  SceneDescription scene;
  scene.bodies.push_back(Floor());
  BodyDescription light = DynamicBox(Vec3::Constant(0.5f), Vec3(0, 0.5f, 0));
  light.mass = 1.0f;
  BodyDescription heavy = DynamicBox(Vec3::Constant(0.5f), Vec3(0, 1.5f, 0));
  heavy.mass = ratio;
  scene.bodies.push_back(light);
  scene.bodies.push_back(heavy);
  return scene;
}

double IntermediateAxisFlipTime(const Vec3& inertia, const Vec3& spin, double limit) {
  const double i1 = inertia.x(), i2 = inertia.y(), i3 = inertia.z();
  auto derivative = [&](const std::array<double, 3>& w) {
    return std::array<double, 3>{(i2 - i3) / i1 * w[1] * w[2], (i3 - i1) / i2 * w[2] * w[0],
                                 (i1 - i2) / i3 * w[0] * w[1]};
  };
  std::array<double, 3> w{spin.x(), spin.y(), spin.z()};
  constexpr double kStep = 1e-5;
  for (double time = 0.0; time < limit; time += kStep) {
    auto add = [](const std::array<double, 3>& a, const std::array<double, 3>& b, double s) {
      return std::array<double, 3>{a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]};
    };
    const auto k1 = derivative(w);
    const auto k2 = derivative(add(w, k1, 0.5 * kStep));
    const auto k3 = derivative(add(w, k2, 0.5 * kStep));
    const auto k4 = derivative(add(w, k3, kStep));
    const double previous = w[1];
    for (int i = 0; i < 3; ++i) w[i] += kStep / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    if (previous > 0.0 && w[1] <= 0.0) return time + kStep * previous / (previous - w[1]);
  }
  return -1.0;
}

std::vector<AccuracyCase> AccuracyCases() {
  const double slide = kGravity * (std::sin(35.0 * kPi / 180.0) - 0.3 * std::cos(35.0 * kPi / 180.0));
  const double roll = 5.0 / 7.0 * kGravity * std::sin(20.0 * kPi / 180.0);
  std::vector<AccuracyCase> cases = {
      {"free_fall", "a sphere falls for 2 s: drop against g t^2 / 2", "relative", 0.01, FreeFall},
      {"incline_slide", "a box slides down 35 degrees with friction 0.3: travel in 2 s", "relative", 0.05,
       [slide](AccuracyEngine& e, const AccuracySetting& s) {
         return Incline(e, s, 35.0f, 0.3f, false, slide, true);
       }},
      {"incline_stick", "a box rests on 25 degrees with friction 0.6: creep in 2 s", "m", 0.01,
       [](AccuracyEngine& e, const AccuracySetting& s) {
         return Incline(e, s, 25.0f, 0.6f, false, 0.0, false);
       }},
      {"rolling_sphere", "a sphere rolls down 20 degrees: travel against 5/7 g sin(a)", "relative", 0.03,
       [roll](AccuracyEngine& e, const AccuracySetting& s) {
         return Incline(e, s, 20.0f, 0.8f, true, roll, true);
       }},
      {"restitution_apex", "balls with restitution 0.8 dropped 1.3, 1.7, 2 m: worst rebound against e^2 h",
       "relative", 0.05, RestitutionApex},
      {"elastic_collision", "spheres of 1 and 3 kg meet at 2 m/s, e = 1: velocities after", "relative", 0.02,
       [](AccuracyEngine& e, const AccuracySetting& s) { return Collision(e, s, 1.0f); }},
      {"inelastic_collision", "the same with e = 0: one common velocity", "relative", 0.02,
       [](AccuracyEngine& e, const AccuracySetting& s) { return Collision(e, s, 0.0f); }},
      {"angular_momentum", "a box spins about a non-principal axis for 10 s: largest |L - L0| / |L0|",
       "relative", 0.01, AngularMomentumDrift},
      {"intermediate_axis_flip", "spin about the middle axis: first flip time against RK4", "relative", 0.05,
       IntermediateAxisFlip},
      {"energy_drift", "a frictionless box between walls with e = 1 for 60 s: largest energy change",
       "relative", 0.05, EnergyDrift},
      {"tower_30", "30 unit boxes stacked for 10 s: top box displacement", "m", 0.1,
       [](AccuracyEngine& e, const AccuracySetting& s) { return Tower(e, s, 30); }},
  };
  for (const float ratio : {10.0f, 100.0f, 1000.0f})
    cases.push_back(
        {"mass_ratio_" + std::to_string(static_cast<int>(ratio)),
         "a " + std::to_string(static_cast<int>(ratio)) +
             " kg box on a 1 kg box for 5 s: how far it sinks or slides",
         "m", 0.02, [ratio](AccuracyEngine& e, const AccuracySetting& s) { return MassRatio(e, s, ratio); }});
  cases.push_back({"fast_thin_wall", "a 5 cm sphere at 500 m/s against a 10 cm wall: distance past its face",
                   "m", 0.01, FastBodyThinWall});
  cases.push_back({"far_from_origin", "a box slides at 2 cm/s 10 km from the origin: travel in 2 s",
                   "relative", 0.01, FarFromOrigin});
  return cases;
}

std::vector<AccuracySetting> AccuracySettings() {
  std::vector<AccuracySetting> settings;
  for (const int rate : {30, 60, 120})
    for (const int substeps : {1, 2, 4, 8})
      settings.push_back({"dt1/" + std::to_string(rate) + " sub" + std::to_string(substeps),
                          1.0f / static_cast<float>(rate), substeps, 1, 1, true});
  settings.push_back({"dt1/60 10 passes", 1.0f / 60.0f, 1, 10, 2, true});
  settings.push_back({"dt1/30 sub4 discrete", 1.0f / 30.0f, 4, 1, 1, false});
  // What the exact solve of small resting islands buys: the default without it, and the cheapest setting
  // without it (Strata only: Bullet has no such switch).
  settings.push_back({"dt1/60 sub4 passes only", 1.0f / 60.0f, 4, 1, 1, true, false});
  settings.push_back({"dt1/30 sub1 passes only", 1.0f / 30.0f, 1, 1, 1, true, false});
  return settings;
}

AccuracySetting DefaultAccuracySetting() {
  const PhysicsSettings defaults;
  return {"default",
          1.0f / 60.0f,
          defaults.substeps,
          defaults.velocity_iterations,
          defaults.relax_iterations,
          true,
          defaults.exact_small_islands};
}

}  // namespace strata::accuracy
