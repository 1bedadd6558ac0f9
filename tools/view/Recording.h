// Recording: what a demo or simulate run leaves for `strata view` (`--record FILE`): the static bodies'
// triangles once, each moving body's (and sensor's) shape once, sampled frames of their poses, of the
// characters' and agents' positions and of every agent profile's navmesh tile states, and at the end each
// profile's navmesh surface by island and the agents with their paths. A JSON file (format
// "strata-recording", version 2; tools/README.md lists its fields). Call a Recorder from the thread that
// steps the world, between steps; ReadRecording from any thread.
#pragma once

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "navmesh/NavMeshService.h"
#include "physics/character/Character.h"
#include "physics/core/Result.h"
#include "physics/world/PhysicsSystem.h"

namespace strata::view {

/// An agent as the demo placed it: where it started, its target and the path it set off on, the profile it
/// walks (an index into the service's) with its size, and whether it arrived.
struct RecordedAgent {
  Vec3 position;
  Vec3 target;
  std::vector<Vec3> path;
  int profile = 0;
  float radius = 0.6f;
  float height = 2.0f;
  bool reached = false;
};

class Recorder {
 public:
  /// Takes the bodies in `world` now: static ones as world triangles, moving ones (dynamic, kinematic) and
  /// sensors as their shape's triangles. Bodies added later are not recorded; one removed later keeps its
  /// last pose. Reads the world through its BodyInterface (each body's read lock); `world` must outlive the
  /// recorder.
  Recorder(PhysicsSystem& world, std::string source, std::string title);

  /// Records the service's profiles and their navmesh tiles over `box` from now on (every profile's tile
  /// states in every frame).
  void TrackTiles(const navmesh::NavMeshService& service, const AABB& box);
  /// Records `count` agents' positions in every frame from now on: `positions` gives them (count points).
  void TrackAgents(std::size_t count, std::function<std::vector<Vec3>()> positions);
  /// Records `character` (its capsule, and its feet in every frame) under `name`; it must outlive the
  /// recorder. `route`: the points it was sent along, if any, drawn as a line.
  void TrackCharacter(const Character& character, const std::string& name,
                      const std::vector<Vec3>& route = {});
  /// One frame: the moving bodies' poses and, when tracked, the tiles' states.
  void Capture(int step, float time);
  /// Every profile's navmesh surface (by island) when `service` is given, and the agents, at the end of the
  /// run (as many as TrackAgents said, when it was called).
  void Finish(const navmesh::NavMeshService* service, const std::vector<RecordedAgent>& agents);

  std::size_t frame_count() const { return frames_.size(); }
  /// The most numbers a recording's frames may hold together: what `strata view` reads back within its
  /// memory budget (ReadRecording).
  static constexpr std::uint64_t kMaxFrameValues = 20'000'000;
  /// Fails, saying what to change, when `frames` frames of what this recorder tracks would pass
  /// kMaxFrameValues: a run checks before it starts rather than filling the memory or writing a file that
  /// cannot be viewed.
  Status CheckFrameBudget(std::uint64_t frames) const;
  /// Writes the file (everything so far, frames included) whole or not at all.
  Status Write(const std::filesystem::path& path) const;

 private:
  PhysicsSystem& world_;
  std::vector<BodyID> moving_;
  std::vector<float> last_poses_;
  const navmesh::NavMeshService* service_ = nullptr;
  std::vector<navmesh::TileCoord> tiles_;
  std::vector<const Character*> characters_;
  std::size_t agent_count_ = 0;
  std::function<std::vector<Vec3>()> agent_positions_;
  nlohmann::json frames_ = nlohmann::json::array();
  nlohmann::json document_;  // all but the frames
};

/// Reads and checks a recording: the format and version, every number finite, every index in range, every
/// frame as long as the bodies and tiles say. Errors name the file and the field.
Result<nlohmann::json> ReadRecording(const std::filesystem::path& path);

}  // namespace strata::view
