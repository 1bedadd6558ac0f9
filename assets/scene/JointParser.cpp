#include "assets/scene/JointParser.h"

#include <algorithm>
#include <array>

#include "assets/scene/SceneBuilder.h"

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

Status ParseMotor(const Reader& reader, const Json& json, JointDescription& joint) {
  if (!json.contains("motor")) return Status::Ok();
  const Json& value = json["motor"];
  const Reader at = reader.At("motor");
  if (!value.is_object()) return reader.Fail("motor", "must be an object {speed, max_torque or max_force}");
  if (Status keys = at.OnlyKeys(value, {"speed", "max_torque", "max_force"}); !keys) return keys;
  joint.motor = true;
  if (Status s = at.Number(value, "speed", joint.motor_speed); !s) return s;
  if (Status s = at.Number(value, "max_torque", joint.motor_max); !s) return s;
  return at.Number(value, "max_force", joint.motor_max);
}

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
                   const std::vector<BodyDescription>& bodies, JointDescription& out) {
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
  auto moves = [&](int index) { return index >= 0 && bodies[index].IsDynamic(); };
  if (!moves(out.body_a) && !moves(out.body_b))
    return reader.Fail("body_b", "a joint needs at least one dynamic body");
  return Status::Ok();
}

// A joint of `kind` as the file format leaves it when no key says otherwise (Strata's defaults).
JointDescription FileDefaults(JointKind kind) {
  JointDescription joint;
  joint.kind = kind;
  joint.normal = Vec3::Zero();  // any
  if (kind == JointKind::kSlider || kind == JointKind::kSwingTwist) joint.axis = Vec3::UnitX();
  if (kind == JointKind::kSlider) joint.min_limit = joint.max_limit = 0.0f;
  return joint;
}

Status ParseAnchored(const Reader& reader, const Json& json, const std::string& type,
                     JointDescription& joint) {
  STRATA_TRY(OnlyJointKeys(reader, json, type, {"anchor"}));
  return reader.Vector(json, "anchor", joint.anchor);
}

Status ParseDistance(const Reader& reader, const Json& json, JointDescription& joint) {
  STRATA_TRY(OnlyJointKeys(reader, json, "distance",
                           {"anchor_a", "anchor_b", "rest_length", "min_distance", "max_distance",
                            "spring_hertz", "spring_damping_ratio"}));
  STRATA_TRY(reader.Vector(json, "anchor_a", joint.anchor));
  STRATA_TRY(reader.Vector(json, "anchor_b", joint.anchor_b));
  STRATA_TRY(reader.Number(json, "rest_length", joint.rest_length));
  STRATA_TRY(reader.Number(json, "min_distance", joint.min_distance));
  STRATA_TRY(reader.Number(json, "max_distance", joint.max_distance));
  STRATA_TRY(reader.Number(json, "spring_hertz", joint.spring_hertz));
  return reader.Number(json, "spring_damping_ratio", joint.spring_damping_ratio);
}

Status ParseHinge(const Reader& reader, const Json& json, JointDescription& joint) {
  STRATA_TRY(OnlyJointKeys(reader, json, "hinge",
                           {"anchor", "axis", "normal", "limits", "max_friction_torque", "motor"}));
  STRATA_TRY(reader.Vector(json, "anchor", joint.anchor));
  STRATA_TRY(reader.Vector(json, "axis", joint.axis));
  STRATA_TRY(reader.Vector(json, "normal", joint.normal));
  if (json.contains("limits")) {
    joint.limits = true;
    STRATA_TRY(ParseAngleLimits(reader, json, "limits", joint.min_limit, joint.max_limit));
  }
  STRATA_TRY(reader.Number(json, "max_friction_torque", joint.max_friction));
  return ParseMotor(reader, json, joint);
}

Status ParseSlider(const Reader& reader, const Json& json, JointDescription& joint) {
  STRATA_TRY(
      OnlyJointKeys(reader, json, "slider", {"anchor", "axis", "limits", "max_friction_force", "motor"}));
  STRATA_TRY(reader.Vector(json, "anchor", joint.anchor));
  STRATA_TRY(reader.Vector(json, "axis", joint.axis));
  if (json.contains("limits")) {
    joint.limits = true;
    STRATA_TRY(ParseRange(reader, json, "limits", joint.min_limit, joint.max_limit));
  }
  STRATA_TRY(reader.Number(json, "max_friction_force", joint.max_friction));
  return ParseMotor(reader, json, joint);
}

Status ParseSwingTwist(const Reader& reader, const Json& json, JointDescription& joint) {
  STRATA_TRY(OnlyJointKeys(reader, json, "swing_twist",
                           {"anchor", "twist_axis", "normal", "cone", "twist", "max_friction_torque"}));
  STRATA_TRY(reader.Vector(json, "anchor", joint.anchor));
  STRATA_TRY(reader.Vector(json, "twist_axis", joint.axis));
  STRATA_TRY(reader.Vector(json, "normal", joint.normal));
  float cone = joint.cone / kRadiansPerDegree;
  STRATA_TRY(reader.Number(json, "cone", cone));
  joint.cone = cone * kRadiansPerDegree;
  float low = -180.0f, high = 180.0f;
  if (json.contains("twist")) {
    STRATA_TRY(ParseAngleLimits(reader, json, "twist", low, high));
  } else {
    low *= kRadiansPerDegree;
    high *= kRadiansPerDegree;
  }
  joint.min_limit = low;
  joint.max_limit = high;
  return reader.Number(json, "max_friction_torque", joint.max_friction);
}

Status ParseKind(const Reader& reader, const std::string& type, JointKind& kind) {
  static const std::map<std::string, JointKind> kKinds = {
      {"fixed", JointKind::kFixed}, {"point", JointKind::kPoint},   {"distance", JointKind::kDistance},
      {"hinge", JointKind::kHinge}, {"slider", JointKind::kSlider}, {"swing_twist", JointKind::kSwingTwist}};
  if (type.empty())
    return reader.Fail("type", "is required: fixed, point, distance, hinge, slider or swing_twist");
  const auto found = kKinds.find(type);
  if (found == kKinds.end())
    return reader.Fail("type",
                       "must be fixed, point, distance, hinge, slider or swing_twist (got '" + type + "')");
  kind = found->second;
  return Status::Ok();
}

Status ParseTyped(const Reader& reader, const Json& json, const std::string& type, JointDescription& joint) {
  switch (joint.kind) {
    case JointKind::kFixed:
    case JointKind::kPoint:
      return ParseAnchored(reader, json, type, joint);
    case JointKind::kDistance:
      return ParseDistance(reader, json, joint);
    case JointKind::kHinge:
      return ParseHinge(reader, json, joint);
    case JointKind::kSlider:
      return ParseSlider(reader, json, joint);
    case JointKind::kSwingTwist:
      return ParseSwingTwist(reader, json, joint);
  }
  return Status::Ok();
}

// Checks the joint Strata would make from `joint`, pointing a bad value's error at its key.
Status CheckJoint(const Reader& reader, const Json& json, const JointDescription& joint) {
  // Placeholder ids in place of the world's: the check needs two distinct bodies, not which.
  const std::array<BodyID, 2> ids = {BodyID{0, 0}, BodyID{1, 0}};
  JointDescription local = joint;
  local.body_a = joint.body_a >= 0 ? 0 : -1;
  local.body_b = 1;
  Status valid = ValidateJointSettings(ToJointSettings(local, ids));
  if (valid) return valid;
  const bool limited =
      (joint.kind == JointKind::kHinge || joint.kind == JointKind::kSlider) && json.contains("limits");
  return reader.Fail(limited ? "limits" : "", valid.message());
}

}  // namespace

Result<JointDescription> ParseConstraint(const Reader& reader, const Json& json,
                                         const std::map<std::string, int>& body_index,
                                         const std::vector<BodyDescription>& bodies) {
  if (!json.is_object()) return reader.Fail("", "must be an object");
  std::string type;
  STRATA_TRY(reader.String(json, "type", type));
  JointKind kind = JointKind::kPoint;
  STRATA_TRY(ParseKind(reader, type, kind));
  JointDescription joint = FileDefaults(kind);
  STRATA_TRY(reader.String(json, "name", joint.name));
  STRATA_TRY(ParseBodies(reader, json, body_index, bodies, joint));
  STRATA_TRY(reader.Number(json, "max_force", joint.break_force));
  STRATA_TRY(reader.Number(json, "max_torque", joint.break_torque));
  STRATA_TRY(reader.Boolean(json, "collide_connected", joint.collide_connected));
  STRATA_TRY(ParseTyped(reader, json, type, joint));
  STRATA_TRY(CheckJoint(reader, json, joint));
  return joint;
}

}  // namespace strata
