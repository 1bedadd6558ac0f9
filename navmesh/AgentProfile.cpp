#include "navmesh/AgentProfile.h"

#include <algorithm>
#include <cctype>

namespace strata::navmesh {

namespace {

AgentProfile Make(const char* name, float radius, float height, float climb, float slope, float drop) {
  AgentProfile profile;
  profile.name = name;
  profile.radius = radius, profile.height = height, profile.max_climb = climb, profile.max_slope = slope;
  profile.max_drop = drop;
  return profile;
}

}  // namespace

AgentProfile AgentProfile::Person() {
  return Make("person", 0.4f, 1.8f, 0.5f, 45.0f, 2.0f);
}
AgentProfile AgentProfile::Machine() {
  return Make("machine", 2.5f, 6.0f, 1.0f, 35.0f, 3.0f);
}
AgentProfile AgentProfile::Critter() {
  return Make("critter", 0.25f, 0.5f, 0.25f, 50.0f, 1.0f);
}

Result<AgentProfile> AgentProfile::Named(const std::string& name) {
  for (const AgentProfile& profile : {Person(), Machine(), Critter()})
    if (profile.name == name) return profile;
  return MakeError(ErrorCode::kInvalidArgument,
                   "navmesh: no agent profile is named '" + name + "' (person, machine or critter)");
}

AgentProfile AgentProfile::FromSettings(const NavMeshSettings& settings, std::string name) {
  AgentProfile profile;
  profile.name = std::move(name);
  profile.height = settings.agent_height, profile.radius = settings.agent_radius;
  profile.max_climb = settings.agent_max_climb, profile.max_slope = settings.agent_max_slope;
  profile.max_drop = settings.agent_max_drop;
  return profile;
}

NavMeshSettings AgentProfile::Apply(NavMeshSettings shared) const {
  shared.agent_height = height, shared.agent_radius = radius;
  shared.agent_max_climb = max_climb, shared.agent_max_slope = max_slope;
  shared.agent_max_drop = max_drop;
  return shared;
}

Status AgentProfile::Validate(const NavMeshSettings& shared) const {
  const auto allowed = [](unsigned char c) { return std::isalnum(c) || c == '_' || c == '-'; };
  if (name.empty() || name.size() > 64 || !std::all_of(name.begin(), name.end(), allowed))
    return MakeError(
        ErrorCode::kInvalidArgument,
        "navmesh: an agent profile's name must be 1 to 64 letters, digits, '_' or '-' (got '" + name + "')");
  if (max_tiles < 0)
    return MakeError(ErrorCode::kInvalidArgument, "navmesh: profile '" + name + "': max_tiles < 0");
  if (Status valid = Apply(shared).Validate(); !valid)
    return MakeError(valid.error().code, "profile '" + name + "': " + valid.message());
  return Status::Ok();
}

}  // namespace strata::navmesh
