#include "tools/view/Recording.h"
#include "assets/json/StrictJson.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "navmesh/Validation.h"
#include "physics/body/BodyInterface.h"
#include "physics/core/InputFile.h"
#include "physics/core/OutputFile.h"

namespace strata::view {

namespace {

constexpr int kFormatVersion = 2;
// Recordings of big worlds run to hundreds of megabytes; past this a file is not one we wrote.
// A recording's text, and what its parsed document may take: `strata view` holds it, a copy with the
// coordinates moved and the page's text at once, so the document gets a third of a 3 GB budget.
constexpr std::uint64_t kMaxRecordingBytes = std::uint64_t{512} << 20;
constexpr std::uint64_t kMaxRecordingMemory = std::uint64_t{1} << 30;

// Millimetres and ten-thousandths are all a viewer shows; fewer digits keep the file small.
double Rounded(float value) {
  return std::round(static_cast<double>(value) * 1e4) / 1e4;
}

void AppendPoint(nlohmann::json& out, const Vec3& point) {
  out.push_back(Rounded(point.x()));
  out.push_back(Rounded(point.y()));
  out.push_back(Rounded(point.z()));
}

nlohmann::json PointJson(const Vec3& point) {
  nlohmann::json out = nlohmann::json::array();
  AppendPoint(out, point);
  return out;
}

/// Triangles as positions (3 numbers a vertex, 3 vertices a triangle, unshared) and indices.
nlohmann::json MeshJson(const std::vector<Triangle>& triangles) {
  nlohmann::json positions = nlohmann::json::array(), indices = nlohmann::json::array();
  std::uint32_t next = 0;
  for (const Triangle& triangle : triangles)
    for (const Vec3& vertex : triangle.vertices) {
      AppendPoint(positions, vertex);
      indices.push_back(next++);
    }
  return {{"positions", std::move(positions)}, {"indices", std::move(indices)}};
}

/// All of the shape's triangles at `pose`.
std::vector<Triangle> ShapeTriangles(const Shape& shape, const Pose& pose) {
  std::vector<Triangle> triangles;
  shape.GetTrianglesInBox(shape.WorldBounds(pose).Expanded(1.0f), pose, triangles);
  return triangles;
}

const char* MotionName(MotionType motion) {
  return motion == MotionType::kStatic      ? "static"
         : motion == MotionType::kKinematic ? "kinematic"
                                            : "dynamic";
}

int StateCode(navmesh::TileState state) {
  return static_cast<int>(state);
}

}  // namespace

Recorder::Recorder(PhysicsSystem& world, std::string source, std::string title) : world_(world) {
  const BodyInterface& bodies = world.bodies();
  std::vector<Triangle> static_triangles;
  std::map<const Shape*, int> shape_index;
  nlohmann::json shapes = nlohmann::json::array(), moving = nlohmann::json::array();
  for (const BodyID id : world.BodiesInWorld()) {
    const Result<MotionType> motion = bodies.GetMotionType(id);
    const Result<ShapeRef> shape = bodies.GetShape(id);
    const Result<Vec3> position = bodies.GetPosition(id);
    const Result<Quat> rotation = bodies.GetRotation(id);
    const Result<bool> sensor = bodies.IsSensor(id);
    if (!motion || !shape || !position || !rotation || !sensor) continue;  // removed meanwhile
    if (*motion == MotionType::kStatic && !*sensor) {
      const std::vector<Triangle> placed = ShapeTriangles(**shape, Pose{*position, *rotation});
      static_triangles.insert(static_triangles.end(), placed.begin(), placed.end());
      continue;
    }
    const auto [it, added] = shape_index.try_emplace(shape->get(), static_cast<int>(shapes.size()));
    if (added) shapes.push_back(MeshJson(ShapeTriangles(**shape, Pose{})));
    nlohmann::json entry = {{"shape", it->second}, {"motion", MotionName(*motion)}};
    if (*sensor) entry["sensor"] = true;
    moving.push_back(std::move(entry));
    moving_.push_back(id);
    for (const float value : {position->x(), position->y(), position->z(), rotation->w(), rotation->x(),
                              rotation->y(), rotation->z()})
      last_poses_.push_back(value);
  }
  document_ = {{"format", "strata-recording"},         {"version", kFormatVersion},
               {"source", std::move(source)},          {"title", std::move(title)},
               {"static", MeshJson(static_triangles)}, {"shapes", std::move(shapes)},
               {"bodies", std::move(moving)},          {"frames", nlohmann::json::array()},
               {"agents", nlohmann::json::array()}};
}

void Recorder::TrackTiles(const navmesh::NavMeshService& service, const AABB& box) {
  service_ = &service;
  const navmesh::TileGrid& grid = service.grid();
  tiles_ = grid.TileCount(box) <= navmesh::TileGrid::kMaxListedTiles ? grid.TilesInBox(box)
                                                                     : std::vector<navmesh::TileCoord>{};
  nlohmann::json coords = nlohmann::json::array();
  for (const navmesh::TileCoord tile : tiles_) coords.push_back({tile.x, tile.z});
  document_["tiles"] = {
      {"size", grid.tile_size()}, {"y", Rounded(box.min.y())}, {"coords", std::move(coords)}};
  nlohmann::json profiles = nlohmann::json::array();
  for (int p = 0; p < service.profile_count(); ++p) {
    const navmesh::NavMeshSettings& settings = service.profile_settings(p);
    profiles.push_back({{"name", service.profile(p).name},
                        {"radius", Rounded(settings.agent_radius)},
                        {"height", Rounded(settings.agent_height)}});
  }
  document_["profiles"] = std::move(profiles);
}

void Recorder::TrackAgents(std::size_t count, std::function<std::vector<Vec3>()> positions) {
  agent_count_ = count;
  agent_positions_ = std::move(positions);
}

void Recorder::TrackCharacter(const Character& character, const std::string& name,
                              const std::vector<Vec3>& route) {
  characters_.push_back(&character);
  nlohmann::json points = nlohmann::json::array();
  for (const Vec3& point : route) points.push_back(PointJson(point));
  if (!document_.contains("characters")) document_["characters"] = nlohmann::json::array();
  document_["characters"].push_back({{"name", name},
                                     {"radius", Rounded(character.settings().radius)},
                                     {"height", Rounded(character.settings().height)},
                                     {"route", std::move(points)}});
}

Status Recorder::CheckFrameBudget(std::uint64_t frames) const {
  const std::uint64_t profiles = service_ ? static_cast<std::uint64_t>(service_->profile_count()) : 0;
  const std::uint64_t per_frame =
      2 + 7 * moving_.size() + 3 * characters_.size() + 3 * agent_count_ + profiles * tiles_.size();
  if (frames * per_frame <= kMaxFrameValues) return Status::Ok();
  return MakeError(
      ErrorCode::kInvalidArgument,
      "a recording of " + std::to_string(frames) + " frames of " + std::to_string(per_frame) +
          " numbers each would pass the " + std::to_string(kMaxFrameValues) +
          " numbers `strata view` reads; record fewer frames (fewer steps, or more steps a frame)");
}

void Recorder::Capture(int step, float time) {
  const BodyInterface& bodies = world_.bodies();
  nlohmann::json poses = nlohmann::json::array();
  for (std::size_t i = 0; i < moving_.size(); ++i) {
    const Result<Vec3> position = bodies.GetPosition(moving_[i]);
    const Result<Quat> rotation = bodies.GetRotation(moving_[i]);
    if (position && rotation) {
      const float values[7] = {position->x(), position->y(), position->z(), rotation->w(),
                               rotation->x(), rotation->y(), rotation->z()};
      std::copy(std::begin(values), std::end(values),
                last_poses_.begin() + static_cast<std::ptrdiff_t>(7 * i));
    }
    for (int k = 0; k < 7; ++k) poses.push_back(Rounded(last_poses_[7 * i + static_cast<std::size_t>(k)]));
  }
  nlohmann::json frame = {{"step", step}, {"time", Rounded(time)}, {"poses", std::move(poses)}};
  if (!characters_.empty()) {
    nlohmann::json feet = nlohmann::json::array();
    for (const Character* character : characters_) AppendPoint(feet, character->feet());
    frame["characters"] = std::move(feet);
  }
  if (agent_positions_) {
    nlohmann::json positions = nlohmann::json::array();
    for (const Vec3& position : agent_positions_()) AppendPoint(positions, position);
    frame["agents"] = std::move(positions);
  }
  if (service_) {
    // Profile by profile, each profile's tiles in `coords` order.
    nlohmann::json states = nlohmann::json::array();
    for (int p = 0; p < service_->profile_count(); ++p)
      for (const navmesh::TileCoord tile : tiles_)
        states.push_back(StateCode(service_->GetTileState(tile, p)));
    frame["tiles"] = std::move(states);
  }
  frames_.push_back(std::move(frame));
}

void Recorder::Finish(const navmesh::NavMeshService* service, const std::vector<RecordedAgent>& agents) {
  nlohmann::json agent_list = nlohmann::json::array();
  for (const RecordedAgent& agent : agents) {
    nlohmann::json path = nlohmann::json::array();
    for (const Vec3& point : agent.path) path.push_back(PointJson(point));
    agent_list.push_back({{"position", PointJson(agent.position)},
                          {"target", PointJson(agent.target)},
                          {"path", std::move(path)},
                          {"profile", agent.profile},
                          {"radius", Rounded(agent.radius)},
                          {"height", Rounded(agent.height)},
                          {"reached", agent.reached}});
  }
  document_["agents"] = std::move(agent_list);
  if (!service) return;
  nlohmann::json navmeshes = nlohmann::json::array();
  for (int p = 0; p < service->profile_count(); ++p) {
    const navmesh::NavMeshTriangles surface = navmesh::TrianglesByIsland(service->navmesh(p));
    nlohmann::json positions = nlohmann::json::array(), islands = nlohmann::json::array();
    for (const Vec3& vertex : surface.vertices) AppendPoint(positions, vertex);
    for (const int island : surface.island) islands.push_back(island);
    navmeshes.push_back(
        {{"positions", std::move(positions)}, {"island", std::move(islands)}, {"islands", surface.islands}});
  }
  document_["navmeshes"] = std::move(navmeshes);
}

Status Recorder::Write(const std::filesystem::path& path) const {
  nlohmann::json document = document_;
  document["frames"] = frames_;
  return WriteOutputFile(path, document.dump() + "\n");
}

namespace {

enum class Missing { kNull, kEmptyArray };

/// The member `key` of `object` (no copy of a large member), or a null or empty array that lives on.
const nlohmann::json& Member(const nlohmann::json& object, const std::string& key,
                             Missing missing = Missing::kNull) {
  static const nlohmann::json kNull;
  static const nlohmann::json kEmptyArray = nlohmann::json::array();
  const nlohmann::json& otherwise = missing == Missing::kNull ? kNull : kEmptyArray;
  if (!object.is_object()) return otherwise;
  const auto found = object.find(key);
  return found == object.end() ? otherwise : *found;
}

// Checks as the reader goes, so that an error names the field.
class RecordingChecker {
 public:
  explicit RecordingChecker(std::string file) : file_(std::move(file)) {}

  Status Fail(const std::string& field, const std::string& why) const {
    return MakeError(ErrorCode::kParseError, file_ + ": " + field + ": " + why);
  }
  Status Numbers(const nlohmann::json& value, const std::string& field, std::size_t multiple_of) const {
    if (!value.is_array()) return Fail(field, "must be an array of numbers");
    if (value.size() % multiple_of != 0)
      return Fail(field, "must hold a multiple of " + std::to_string(multiple_of) + " numbers");
    for (const nlohmann::json& number : value)
      if (!number.is_number() || !std::isfinite(number.get<double>()))
        return Fail(field, "holds a non-finite value");
    return Status::Ok();
  }
  Status Indices(const nlohmann::json& value, const std::string& field, std::size_t limit) const {
    if (!value.is_array() || value.size() % 3 != 0) return Fail(field, "must be whole triangles of indices");
    for (const nlohmann::json& index : value)
      if (!index.is_number_unsigned() || index.get<std::uint64_t>() >= limit)
        return Fail(field, "holds an index past the vertices");
    return Status::Ok();
  }
  Status Mesh(const nlohmann::json& mesh, const std::string& field) const {
    if (!mesh.is_object()) return Fail(field, "must be an object with positions and indices");
    if (Status status = Numbers(Member(mesh, "positions"), field + ".positions", 3); !status) return status;
    return Indices(Member(mesh, "indices"), field + ".indices", mesh["positions"].size() / 3);
  }

 private:
  std::string file_;
};

// The header, the static mesh, the shapes and the bodies that use them.
Status CheckBodies(const nlohmann::json& document, const RecordingChecker& check) {
  const nlohmann::json& format = Member(document, "format");
  if (!format.is_string() || format.get<std::string>() != "strata-recording")
    return check.Fail("format", "not a strata recording (\"format\": \"strata-recording\" expected)");
  const nlohmann::json& version = Member(document, "version");
  if (!version.is_number_integer() || version.get<std::int64_t>() != kFormatVersion)
    return check.Fail("version", "version " + std::to_string(kFormatVersion) + " expected (a whole number)");
  if (!Member(document, "title").is_string()) return check.Fail("title", "must be a string");
  if (Status status = check.Mesh(Member(document, "static"), "static"); !status) return status;
  const nlohmann::json& shapes = Member(document, "shapes");
  if (!shapes.is_array()) return check.Fail("shapes", "must be an array");
  for (std::size_t i = 0; i < shapes.size(); ++i)
    if (Status status = check.Mesh(shapes[i], "shapes[" + std::to_string(i) + "]"); !status) return status;
  const nlohmann::json& bodies = Member(document, "bodies");
  if (!bodies.is_array()) return check.Fail("bodies", "must be an array");
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const nlohmann::json& shape = Member(bodies[i], "shape");
    if (!shape.is_number_unsigned() || shape.get<std::uint64_t>() >= shapes.size())
      return check.Fail("bodies[" + std::to_string(i) + "].shape", "must be the index of a shape");
    if (bodies[i].contains("sensor") && !bodies[i]["sensor"].is_boolean())
      return check.Fail("bodies[" + std::to_string(i) + "].sensor", "must be true or false");
  }
  return Status::Ok();
}

// The agent profiles, if any: each named, with a positive radius and height.
Status CheckProfiles(const nlohmann::json& document, const RecordingChecker& check) {
  const nlohmann::json& profiles = Member(document, "profiles", Missing::kEmptyArray);
  if (!profiles.is_array()) return check.Fail("profiles", "must be an array");
  for (std::size_t i = 0; i < profiles.size(); ++i) {
    const std::string field = "profiles[" + std::to_string(i) + "]";
    if (!Member(profiles[i], "name").is_string()) return check.Fail(field + ".name", "must be a string");
    for (const char* size : {"radius", "height"}) {
      const nlohmann::json& value = Member(profiles[i], size);
      if (!value.is_number() || !(value.get<double>() > 0.0) || !std::isfinite(value.get<double>()))
        return check.Fail(field + "." + size, "must be a finite number > 0");
    }
  }
  return Status::Ok();
}

/// How many profiles the frames' tile states and the navmeshes are for (one when none is named).
std::size_t ProfileCount(const nlohmann::json& document) {
  return std::max<std::size_t>(1, Member(document, "profiles", Missing::kEmptyArray).size());
}

// The tile grid, if any; `tile_count` is how many tile states every frame must hold (a tile a profile).
Status CheckTiles(const nlohmann::json& document, const RecordingChecker& check, std::size_t& tile_count) {
  tile_count = 0;
  if (document.contains("tiles")) {
    const nlohmann::json& tiles = document["tiles"];
    if (!tiles.is_object() || !Member(tiles, "size").is_number() || !(tiles["size"].get<double>() > 0.0) ||
        !Member(tiles, "y").is_number() || !std::isfinite(tiles["y"].get<double>()) ||
        !Member(tiles, "coords").is_array())
      return check.Fail("tiles", "must have a positive size, a finite y and coords");
    for (const nlohmann::json& coord : tiles["coords"])
      if (!coord.is_array() || coord.size() != 2 || !coord[0].is_number_integer() ||
          !coord[1].is_number_integer())
        return check.Fail("tiles.coords", "must be [x, z] pairs of whole numbers");
    tile_count = tiles["coords"].size() * ProfileCount(document);
  }
  return Status::Ok();
}

Status CheckCharacters(const nlohmann::json& document, const RecordingChecker& check) {
  const nlohmann::json& characters = Member(document, "characters", Missing::kEmptyArray);
  if (!characters.is_array()) return check.Fail("characters", "must be an array");
  for (std::size_t i = 0; i < characters.size(); ++i) {
    const std::string field = "characters[" + std::to_string(i) + "]";
    const nlohmann::json& radius = Member(characters[i], "radius");
    const nlohmann::json& height = Member(characters[i], "height");
    if (!radius.is_number() || !height.is_number() || !(radius.get<double>() > 0.0) ||
        !(height.get<double>() >= 2.0 * radius.get<double>()) || !std::isfinite(height.get<double>()))
      return check.Fail(field, "must have a positive radius and a finite height of at least two radii");
    if (!Member(characters[i], "name").is_string()) return check.Fail(field + ".name", "must be a string");
    const nlohmann::json& route = Member(characters[i], "route", Missing::kEmptyArray);
    if (!route.is_array()) return check.Fail(field + ".route", "must be an array of points");
    for (const nlohmann::json& point : route)
      if (Status status = check.Numbers(point, field + ".route", 3); !status || point.size() != 3)
        return check.Fail(field + ".route", "must be an array of x, y, z points");
  }
  return Status::Ok();
}

// Every frame: a pose a body, feet a character, a state a tile.
Status CheckFrames(const nlohmann::json& document, const RecordingChecker& check, std::size_t tile_count) {
  const nlohmann::json& bodies = Member(document, "bodies");
  const nlohmann::json& characters = Member(document, "characters", Missing::kEmptyArray);
  const nlohmann::json& frames = Member(document, "frames");
  if (!frames.is_array()) return check.Fail("frames", "must be an array");
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const std::string field = "frames[" + std::to_string(i) + "]";
    const nlohmann::json& frame = frames[i];
    if (!frame.is_object() || !Member(frame, "step").is_number_integer() ||
        !Member(frame, "time").is_number() || !std::isfinite(frame["time"].get<double>()))
      return check.Fail(field, "must have a whole step and a finite time");
    const nlohmann::json& poses = Member(frame, "poses");
    if (Status status = check.Numbers(poses, field + ".poses", 7); !status) return status;
    if (poses.size() != 7 * bodies.size()) return check.Fail(field + ".poses", "must hold 7 numbers a body");
    if (!characters.empty()) {
      const nlohmann::json& feet = Member(frame, "characters");
      if (Status status = check.Numbers(feet, field + ".characters", 3); !status) return status;
      if (feet.size() != 3 * characters.size())
        return check.Fail(field + ".characters", "must hold 3 numbers a character");
    }
    if (frame.contains("agents")) {
      const nlohmann::json& positions = frame["agents"];
      if (Status status = check.Numbers(positions, field + ".agents", 3); !status) return status;
      if (positions.size() != 3 * Member(document, "agents", Missing::kEmptyArray).size())
        return check.Fail(field + ".agents", "must hold 3 numbers an agent");
    }
    if (tile_count > 0) {
      const nlohmann::json& states = Member(frame, "tiles");
      if (!states.is_array() || states.size() != tile_count)
        return check.Fail(field + ".tiles", "must hold one state a tile a profile");
      for (const nlohmann::json& state : states)
        if (!state.is_number_unsigned() ||
            state.get<std::uint64_t>() > static_cast<std::uint64_t>(StateCode(navmesh::TileState::kStale)))
          return check.Fail(field + ".tiles", "holds an unknown tile state");
    }
  }
  return Status::Ok();
}

Status CheckSurface(const nlohmann::json& surface, const std::string& field, const RecordingChecker& check) {
  if (!surface.is_object()) return check.Fail(field, "must be an object");
  if (Status status = check.Numbers(Member(surface, "positions"), field + ".positions", 9); !status)
    return status;
  const nlohmann::json& islands = Member(surface, "island");
  if (!islands.is_array() || islands.size() != surface["positions"].size() / 9)
    return check.Fail(field + ".island", "must hold one island a triangle");
  for (const nlohmann::json& island : islands)
    if (!island.is_number_unsigned() || island.get<std::uint64_t>() > std::uint64_t{1} << 30)
      return check.Fail(field + ".island", "must be whole numbers up to 2^30");
  return Status::Ok();
}

// One agent: its points and path, and the profile and size it walks with.
Status CheckAgent(const nlohmann::json& agent, const std::string& field, std::size_t profile_count,
                  const RecordingChecker& check) {
  if (!agent.is_object()) return check.Fail(field, "must be an object");
  for (const char* point : {"position", "target"}) {
    const nlohmann::json& value = Member(agent, point);
    if (Status status = check.Numbers(value, field + "." + point, 3); !status) return status;
    if (value.size() != 3) return check.Fail(field + "." + point, "must be x, y, z");
  }
  const nlohmann::json& path = Member(agent, "path", Missing::kEmptyArray);
  if (!path.is_array()) return check.Fail(field + ".path", "must be an array of points");
  for (const nlohmann::json& point : path)
    if (Status status = check.Numbers(point, field + ".path", 3); !status || point.size() != 3)
      return check.Fail(field + ".path", "must be an array of x, y, z points");
  if (agent.contains("profile") &&
      (!agent["profile"].is_number_unsigned() || agent["profile"].get<std::uint64_t>() >= profile_count))
    return check.Fail(field + ".profile", "must be the index of a profile");
  for (const char* size : {"radius", "height"})
    if (agent.contains(size) && (!agent[size].is_number() || !(agent[size].get<double>() > 0.0) ||
                                 !std::isfinite(agent[size].get<double>())))
      return check.Fail(field + "." + size, "must be a finite number > 0");
  if (agent.contains("reached") && !agent["reached"].is_boolean())
    return check.Fail(field + ".reached", "must be true or false");
  return Status::Ok();
}

// Each profile's navmesh by island, and the agents with their paths.
Status CheckNavMeshAndAgents(const nlohmann::json& document, const RecordingChecker& check) {
  const std::size_t profile_count = ProfileCount(document);
  const nlohmann::json& navmeshes = Member(document, "navmeshes", Missing::kEmptyArray);
  if (!navmeshes.is_array() || navmeshes.size() > profile_count)
    return check.Fail("navmeshes", "must be an array of at most one navmesh a profile");
  for (std::size_t i = 0; i < navmeshes.size(); ++i)
    if (Status status = CheckSurface(navmeshes[i], "navmeshes[" + std::to_string(i) + "]", check); !status)
      return status;
  const nlohmann::json& agents = Member(document, "agents", Missing::kEmptyArray);
  if (!agents.is_array()) return check.Fail("agents", "must be an array");
  for (std::size_t i = 0; i < agents.size(); ++i)
    if (Status status = CheckAgent(agents[i], "agents[" + std::to_string(i) + "]", profile_count, check);
        !status)
      return status;
  return Status::Ok();
}

Status CheckRecording(const nlohmann::json& document, const RecordingChecker& check) {
  std::size_t tile_count = 0;
  if (Status status = CheckBodies(document, check); !status) return status;
  if (Status status = CheckProfiles(document, check); !status) return status;
  if (Status status = CheckTiles(document, check, tile_count); !status) return status;
  if (Status status = CheckCharacters(document, check); !status) return status;
  if (Status status = CheckFrames(document, check, tile_count); !status) return status;
  return CheckNavMeshAndAgents(document, check);
}

}  // namespace

Result<nlohmann::json> ReadRecording(const std::filesystem::path& path) {
  Result<std::string> text = ReadInputFile(path, kMaxRecordingBytes);
  if (!text) return text.error();
  Result<nlohmann::json> parsed = ParseStrictJson(*text, path.string(), {64, kMaxRecordingMemory});
  if (!parsed) return parsed.error();
  const nlohmann::json document = std::move(*parsed);
  const RecordingChecker check(path.string());
  if (Status status = CheckRecording(document, check); !status) return status.error();
  return document;
}

}  // namespace strata::view
