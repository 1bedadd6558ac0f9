#include "assets/scene/JointParser.h"

#include <algorithm>

namespace strata {

namespace {

using Json = SceneJson;
using Reader = SceneJsonReader;

constexpr float kRadiansPerDegree = kPi / 180.0f;

Status ParseRange(const Reader& reader, const Json& json, const std::string& key, float& low, float& high) {
  if (!json.contains(key)) return Status::Ok();
  const Json& value = json[key];
  if (!value.is_array() || value.size() != 2 || !value[0].is_number() || !value[1].is_number())
    return reader.Fail(key, "must be [low, high]");
  const double a = value[0].get<double>(), b = value[1].get<double>();
  if (!std::isfinite(a) || !std::isfinite(b) || std::abs(a) > 1e6 || std::abs(b) > 1e6)
    return reader.Fail(key, "must be finite numbers");
  low = static_cast<float>(a);
  high = static_cast<float>(b);
  return Status::Ok();
}

// An angle range in degrees, [-180, 0] to [0, 180], into radians.
Status ParseAngleLimits(const Reader& reader, const Json& json, const std::string& key, float& low,
                        float& high) {
  STRATA_TRY(ParseRange(reader, json, key, low, high));
  if (low < -180.0f || low > 0.0f || high < 0.0f || high > 180.0f)
    return reader.Fail(key, "must be [min, max] degrees, min in [-180, 0] and max in [0, 180]");
  low *= kRadiansPerDegree;
  high *= kRadiansPerDegree;
  return Status::Ok();
}

Status ParseMotor(const Reader& reader, const Json& json, JointMotor& motor) {
  if (!json.contains("motor")) return Status::Ok();
  const Json& value = json["motor"];
  const Reader at = reader.At("motor");
  if (!value.is_object()) return reader.Fail("motor", "must be an object {speed, max_torque or max_force}");
  if (Status keys = at.OnlyKeys(value, {"speed", "max_torque", "max_force"}); !keys) return keys;
  motor.enabled = true;
  if (Status s = at.Number(value, "speed", motor.target_speed); !s) return s;
  if (Status s = at.Number(value, "max_torque", motor.max_torque); !s) return s;
  return at.Number(value, "max_force", motor.max_torque);
}

// What every joint entry has: its type, name, bodies and breaking limits.
struct JointEntry {
  std::string type;
  JointSettingsBase base;
  std::string failing_key;  // where a settings error points
};

// The keys a joint of the entry's type may have: the common ones and its own.
Status OnlyJointKeys(const Reader& reader, const Json& json, const std::string& type,
                     std::initializer_list<const char*> own) {
  static constexpr const char* kCommon[] = {"type",      "name",       "body_a",           "body_b",
                                            "max_force", "max_torque", "collide_connected"};
  for (const auto& item : json.items()) {
    const std::string& key = item.key();
    const auto is_key = [&](const char* k) { return key == k; };
    if (std::none_of(std::begin(kCommon), std::end(kCommon), is_key) &&
        std::none_of(own.begin(), own.end(), is_key))
      return reader.Fail(key, "unknown key for a " + type + " joint");
  }
  return Status::Ok();
}

Status ParseBodies(const Reader& reader, const Json& json, const std::map<std::string, int>& body_index,
                   const std::vector<SceneBody>& bodies, SceneConstraint& out) {
  auto body = [&](const char* key, int& index) -> Status {
    if (!json.contains(key)) return Status::Ok();
    std::string name;
    if (Status s = reader.String(json, key, name); !s) return s;
    const auto found = body_index.find(name);
    if (found == body_index.end()) return reader.Fail(key, "no body is named '" + name + "'");
    index = found->second;
    return Status::Ok();
  };
  out.body_b = -1;
  if (Status s = body("body_a", out.body_a); !s) return s;
  if (Status s = body("body_b", out.body_b); !s) return s;
  if (out.body_b < 0) return reader.Fail("body_b", "is required (body_a may be left out: the world)");
  if (out.body_a == out.body_b) return reader.Fail("body_b", "is the same body as body_a");
  auto moves = [&](int index) {
    return index >= 0 && bodies[index].settings.motion_type == MotionType::kDynamic;
  };
  if (!moves(out.body_a) && !moves(out.body_b))
    return reader.Fail("body_b", "a joint needs at least one dynamic body");
  return Status::Ok();
}

template <class Settings>
Settings WithBase(const JointEntry& entry) {
  Settings joint;
  static_cast<JointSettingsBase&>(joint) = entry.base;
  return joint;
}

Result<JointSettings> ParseAnchored(const Reader& reader, const Json& json, const JointEntry& entry) {
  STRATA_TRY(OnlyJointKeys(reader, json, entry.type, {"anchor"}));
  Vec3 anchor = Vec3::Zero();
  STRATA_TRY(reader.Vector(json, "anchor", anchor));
  if (entry.type == "fixed") {
    auto joint = WithBase<FixedJointSettings>(entry);
    joint.anchor = anchor;
    return JointSettings(joint);
  }
  auto joint = WithBase<PointJointSettings>(entry);
  joint.anchor = anchor;
  return JointSettings(joint);
}

Result<JointSettings> ParseDistance(const Reader& reader, const Json& json, const JointEntry& entry) {
  STRATA_TRY(OnlyJointKeys(reader, json, entry.type,
                           {"anchor_a", "anchor_b", "rest_length", "min_distance", "max_distance",
                            "spring_hertz", "spring_damping_ratio"}));
  auto joint = WithBase<DistanceJointSettings>(entry);
  STRATA_TRY(reader.Vector(json, "anchor_a", joint.anchor_a));
  STRATA_TRY(reader.Vector(json, "anchor_b", joint.anchor_b));
  STRATA_TRY(reader.Number(json, "rest_length", joint.rest_length));
  STRATA_TRY(reader.Number(json, "min_distance", joint.min_distance));
  STRATA_TRY(reader.Number(json, "max_distance", joint.max_distance));
  STRATA_TRY(reader.Number(json, "spring_hertz", joint.spring_hertz));
  STRATA_TRY(reader.Number(json, "spring_damping_ratio", joint.spring_damping_ratio));
  return JointSettings(joint);
}

Result<JointSettings> ParseHinge(const Reader& reader, const Json& json, JointEntry& entry) {
  STRATA_TRY(OnlyJointKeys(reader, json, entry.type,
                           {"anchor", "axis", "normal", "limits", "max_friction_torque", "motor"}));
  auto joint = WithBase<HingeJointSettings>(entry);
  STRATA_TRY(reader.Vector(json, "anchor", joint.anchor));
  STRATA_TRY(reader.Vector(json, "axis", joint.axis));
  STRATA_TRY(reader.Vector(json, "normal", joint.normal));
  if (json.contains("limits")) {
    joint.limits = true;
    STRATA_TRY(ParseAngleLimits(reader, json, "limits", joint.min_angle, joint.max_angle));
    entry.failing_key = "limits";
  }
  STRATA_TRY(reader.Number(json, "max_friction_torque", joint.max_friction_torque));
  STRATA_TRY(ParseMotor(reader, json, joint.motor));
  return JointSettings(joint);
}

Result<JointSettings> ParseSlider(const Reader& reader, const Json& json, JointEntry& entry) {
  STRATA_TRY(
      OnlyJointKeys(reader, json, entry.type, {"anchor", "axis", "limits", "max_friction_force", "motor"}));
  auto joint = WithBase<SliderJointSettings>(entry);
  STRATA_TRY(reader.Vector(json, "anchor", joint.anchor));
  STRATA_TRY(reader.Vector(json, "axis", joint.axis));
  if (json.contains("limits")) {
    joint.limits = true;
    STRATA_TRY(ParseRange(reader, json, "limits", joint.min_position, joint.max_position));
    entry.failing_key = "limits";
  }
  STRATA_TRY(reader.Number(json, "max_friction_force", joint.max_friction_force));
  STRATA_TRY(ParseMotor(reader, json, joint.motor));
  return JointSettings(joint);
}

Result<JointSettings> ParseSwingTwist(const Reader& reader, const Json& json, const JointEntry& entry) {
  STRATA_TRY(OnlyJointKeys(reader, json, entry.type,
                           {"anchor", "twist_axis", "normal", "cone", "twist", "max_friction_torque"}));
  auto joint = WithBase<SwingTwistJointSettings>(entry);
  STRATA_TRY(reader.Vector(json, "anchor", joint.anchor));
  STRATA_TRY(reader.Vector(json, "twist_axis", joint.twist_axis));
  STRATA_TRY(reader.Vector(json, "normal", joint.normal));
  float cone = joint.cone_half_angle / kRadiansPerDegree;
  STRATA_TRY(reader.Number(json, "cone", cone));
  joint.cone_half_angle = cone * kRadiansPerDegree;
  float low = -180.0f, high = 180.0f;
  if (json.contains("twist")) {
    STRATA_TRY(ParseAngleLimits(reader, json, "twist", low, high));
  } else {
    low *= kRadiansPerDegree;
    high *= kRadiansPerDegree;
  }
  joint.min_twist = low;
  joint.max_twist = high;
  STRATA_TRY(reader.Number(json, "max_friction_torque", joint.max_friction_torque));
  return JointSettings(joint);
}

Result<JointSettings> ParseTyped(const Reader& reader, const Json& json, JointEntry& entry) {
  const std::string& type = entry.type;
  if (type == "fixed" || type == "point") return ParseAnchored(reader, json, entry);
  if (type == "distance") return ParseDistance(reader, json, entry);
  if (type == "hinge") return ParseHinge(reader, json, entry);
  if (type == "slider") return ParseSlider(reader, json, entry);
  if (type == "swing_twist") return ParseSwingTwist(reader, json, entry);
  return reader.Fail("type",
                     "must be fixed, point, distance, hinge, slider or swing_twist (got '" + type + "')");
}

}  // namespace

Result<SceneConstraint> ParseConstraint(const Reader& reader, const Json& json,
                                        const std::map<std::string, int>& body_index,
                                        const std::vector<SceneBody>& bodies) {
  if (!json.is_object()) return reader.Fail("", "must be an object");
  SceneConstraint out;
  JointEntry entry;
  STRATA_TRY(reader.String(json, "type", entry.type));
  if (entry.type.empty())
    return reader.Fail("type", "is required: fixed, point, distance, hinge, slider or swing_twist");
  STRATA_TRY(reader.String(json, "name", out.name));
  STRATA_TRY(ParseBodies(reader, json, body_index, bodies, out));
  // Placeholder ids for validation; BuildSceneWorld puts the real ones in.
  entry.base.body_a = out.body_a >= 0 ? BodyID{static_cast<std::uint32_t>(out.body_a), 0} : BodyID{};
  entry.base.body_b = BodyID{static_cast<std::uint32_t>(out.body_b), 0};
  STRATA_TRY(reader.Number(json, "max_force", entry.base.max_force));
  STRATA_TRY(reader.Number(json, "max_torque", entry.base.max_torque));
  STRATA_TRY(reader.Boolean(json, "collide_connected", entry.base.collide_connected));
  Result<JointSettings> settings = ParseTyped(reader, json, entry);
  if (!settings) return settings.error();
  out.settings = std::move(*settings);
  if (Status valid = ValidateJointSettings(out.settings); !valid)
    return reader.Fail(entry.failing_key, valid.message());
  return out;
}

}  // namespace strata
