#include "assets/scene/SceneLoader.h"
#include "assets/json/StrictJson.h"
#include "assets/scene/JointParser.h"
#include "assets/scene/SceneJsonReader.h"

#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "assets/import/HeightMapImporter.h"
#include "assets/import/MeshImporter.h"
#include "physics/body/BodyInterface.h"
#include "physics/core/InputFile.h"
#include "physics/shapes/BoxShape.h"
#include "physics/shapes/CapsuleShape.h"
#include "physics/shapes/ConvexHullShape.h"
#include "physics/shapes/HeightFieldShape.h"
#include "physics/shapes/SphereShape.h"
#include "physics/shapes/TriangleMeshShape.h"

namespace strata {

namespace {

using Json = SceneJson;
using Reader = SceneJsonReader;

Result<std::vector<Vec3>> ParsePoints(const Reader& reader, const Json& shape, const std::string& key) {
  if (!shape.contains(key) || !shape[key].is_array())
    return reader.Fail(key, "must be an array of [x, y, z] points");
  std::vector<Vec3> points;
  for (std::size_t i = 0; i < shape[key].size(); ++i) {
    Vec3 point;
    STRATA_TRY(reader.ParseVector(shape[key][i], key + "/" + std::to_string(i), point));
    points.push_back(point);
  }
  return points;
}

Result<ShapeRef> ParseMesh(const Reader& reader, const Json& shape, const std::filesystem::path& base) {
  if (shape.contains("file")) {
    if (!shape["file"].is_string()) return reader.Fail("file", "must be a path string");
    MeshImportOptions options;
    STRATA_TRY(reader.Number(shape, "scale", options.scale));
    STRATA_TRY(reader.Boolean(shape, "z_up", options.z_up));
    Result<ImportedMesh> mesh = ImportMesh(base / shape["file"].get<std::string>(), options);
    if (!mesh) return reader.Fail("file", mesh.error().message);
    Result<ShapeRef> created = TriangleMeshShape::Create(mesh->vertices, mesh->triangles);
    if (!created) return reader.Fail("file", created.error().message);
    return created;
  }
  Result<std::vector<Vec3>> vertices = ParsePoints(reader, shape, "vertices");
  if (!vertices) return vertices.error();
  if (!shape.contains("indices") || !shape["indices"].is_array() || shape["indices"].size() % 3 != 0)
    return reader.Fail("indices", "must be a flat array of vertex indices, 3 per triangle");
  std::vector<TriangleMeshShape::Indices> triangles;
  const Json& indices = shape["indices"];
  for (std::size_t i = 0; i < indices.size(); i += 3) {
    TriangleMeshShape::Indices triangle;
    for (std::size_t k = 0; k < 3; ++k) {
      const std::string key = "indices/" + std::to_string(i + k);
      if (!indices[i + k].is_number_unsigned()) return reader.Fail(key, "must be a non-negative integer");
      // Read wide: get<std::uint32_t>() would wrap 4294967298 to 2, a valid index of another vertex.
      const auto index = indices[i + k].get<std::uint64_t>();
      if (index >= vertices->size())
        return reader.Fail(key, std::to_string(index) + " is not a vertex index (there are " +
                                    std::to_string(vertices->size()) + " vertices)");
      triangle[k] = static_cast<std::uint32_t>(index);
    }
    triangles.push_back(triangle);
  }
  Result<ShapeRef> created = TriangleMeshShape::Create(*vertices, triangles);
  if (!created) return reader.Fail("", created.error().message);
  return created;
}

// A grid size from the scene: a whole number of samples, within what a height field may hold.
Status ParseSampleCount(const Reader& reader, const Json& shape, const std::string& key, std::uint32_t& out) {
  if (!shape.contains(key)) return reader.Fail(key, "is required");
  if (!shape[key].is_number_unsigned() || shape[key].get<std::uint64_t>() < 2 ||
      shape[key].get<std::uint64_t>() > HeightFieldShape::kMaxSamples)
    return reader.Fail(key, "must be a whole number of samples, at least 2");
  out = static_cast<std::uint32_t>(shape[key].get<std::uint64_t>());
  return Status::Ok();
}

Result<ShapeRef> ParseHeightField(const Reader& reader, const Json& shape,
                                  const std::filesystem::path& base) {
  float cell_size = 1.0f;
  STRATA_TRY(reader.Number(shape, "cell_size", cell_size));
  std::uint32_t columns = 0, rows = 0;
  std::vector<float> heights;
  const std::string where = shape.contains("file") ? "file" : "heights";
  if (shape.contains("file")) {
    if (!shape["file"].is_string()) return reader.Fail("file", "must be a path string");
    const std::filesystem::path path = base / shape["file"].get<std::string>();
    if (path.extension() == ".png") {
      if (shape.contains("columns") || shape.contains("rows"))
        return reader.Fail("file", "a picture's size is its own: leave out columns and rows");
      Vec3 range(0.0f, 1.0f, 0.0f);
      if (shape.contains("height_range")) {
        const Json& value = shape["height_range"];
        if (!value.is_array() || value.size() != 2 || !value[0].is_number() || !value[1].is_number())
          return reader.Fail("height_range", "must be [low, high] in metres");
        range = Vec3(value[0].get<float>(), value[1].get<float>(), 0.0f);
        if (!IsFinite(range)) return reader.Fail("height_range", "must be finite");
      }
      Result<HeightMap> map = ImportHeightMapPicture(path, range.x(), range.y());
      if (!map) return reader.Fail("file", map.error().message);
      columns = map->columns, rows = map->rows, heights = std::move(map->heights);
    } else {
      if (shape.contains("height_range")) return reader.Fail("height_range", "is for a PNG picture only");
      STRATA_TRY(ParseSampleCount(reader, shape, "columns", columns));
      STRATA_TRY(ParseSampleCount(reader, shape, "rows", rows));
      Result<HeightMap> map = ImportRawHeights(path, columns, rows);
      if (!map) return reader.Fail("file", map.error().message);
      heights = std::move(map->heights);
    }
  } else {
    STRATA_TRY(ParseSampleCount(reader, shape, "columns", columns));
    STRATA_TRY(ParseSampleCount(reader, shape, "rows", rows));
    if (!shape.contains("heights") || !shape["heights"].is_array())
      return reader.Fail("heights", "must be an array of columns x rows heights (null for a hole)");
    const Json& values = shape["heights"];
    for (std::size_t i = 0; i < values.size(); ++i) {
      if (values[i].is_null()) {
        heights.push_back(HeightFieldShape::kHole);
        continue;
      }
      const std::string key = "heights/" + std::to_string(i);
      if (!values[i].is_number()) return reader.Fail(key, "must be a number, or null for a hole");
      const double height = values[i].get<double>();
      if (!std::isfinite(height) || std::abs(height) > std::numeric_limits<float>::max())
        return reader.Fail(key, "must be finite and fit a 32-bit float");
      heights.push_back(static_cast<float>(height));
    }
  }
  Result<ShapeRef> created = HeightFieldShape::Create(columns, rows, cell_size, heights);
  if (!created) return reader.Fail(where, created.error().message);
  return created;
}

Result<ShapeRef> ParseShape(const Reader& reader, const Json& shape, const std::filesystem::path& base) {
  if (!shape.is_object()) return reader.Fail("", "must be an object");
  std::string type;
  STRATA_TRY(reader.String(shape, "type", type));
  auto created = [&](Result<ShapeRef> result, const std::string& key) -> Result<ShapeRef> {
    if (!result) return reader.Fail(key, result.error().message);
    return result;
  };
  float radius = -1.0f, half_height = -1.0f;
  Vec3 half_extents = Vec3::Constant(-1.0f);
  if (type == "sphere") {
    STRATA_TRY(reader.OnlyKeys(shape, {"type", "radius"}));
    STRATA_TRY(reader.Number(shape, "radius", radius));
    return created(SphereShape::Create(radius), "radius");
  }
  if (type == "box") {
    STRATA_TRY(reader.OnlyKeys(shape, {"type", "half_extents"}));
    STRATA_TRY(reader.Vector(shape, "half_extents", half_extents));
    return created(BoxShape::Create(half_extents), "half_extents");
  }
  if (type == "capsule") {
    STRATA_TRY(reader.OnlyKeys(shape, {"type", "radius", "half_height"}));
    STRATA_TRY(reader.Number(shape, "radius", radius));
    STRATA_TRY(reader.Number(shape, "half_height", half_height));
    return created(CapsuleShape::Create(half_height, radius), "");
  }
  if (type == "convex_hull") {
    STRATA_TRY(reader.OnlyKeys(shape, {"type", "points"}));
    Result<std::vector<Vec3>> points = ParsePoints(reader, shape, "points");
    if (!points) return points.error();
    return created(ConvexHullShape::Create(*points), "points");
  }
  if (type == "mesh") {
    STRATA_TRY(reader.OnlyKeys(shape, {"type", "vertices", "indices", "file", "scale", "z_up"}));
    return ParseMesh(reader, shape, base);
  }
  if (type == "heightfield") {
    STRATA_TRY(
        reader.OnlyKeys(shape, {"type", "columns", "rows", "cell_size", "heights", "file", "height_range"}));
    return ParseHeightField(reader, shape, base);
  }
  return reader.Fail(
      "type", "must be one of sphere, box, capsule, convex_hull, mesh, heightfield (got '" + type + "')");
}

// "motion" and "motion_quality", and the layer the motion puts the body on.
Status ParseMotion(const Reader& reader, const Json& body, BodyCreationSettings& settings) {
  std::string motion = "dynamic";
  STRATA_TRY(reader.String(body, "motion", motion));
  if (motion == "static")
    settings.motion_type = MotionType::kStatic;
  else if (motion == "kinematic")
    settings.motion_type = MotionType::kKinematic;
  else if (motion == "dynamic")
    settings.motion_type = MotionType::kDynamic;
  else
    return reader.Fail("motion", "must be static, kinematic or dynamic (got '" + motion + "')");
  std::string quality = "discrete";
  STRATA_TRY(reader.String(body, "motion_quality", quality));
  if (quality == "linear_cast")
    settings.motion_quality = MotionQuality::kLinearCast;
  else if (quality != "discrete")
    return reader.Fail("motion_quality", "must be discrete or linear_cast (got '" + quality + "')");
  settings.object_layer = settings.motion_type == MotionType::kStatic ? layers::kNonMoving : layers::kMoving;
  return Status::Ok();
}

Result<SceneBody> ParseBody(const Reader& reader, const Json& body, const std::filesystem::path& base) {
  if (!body.is_object()) return reader.Fail("", "must be an object");
  STRATA_TRY(reader.OnlyKeys(body, {"name",
                                    "shape",
                                    "position",
                                    "rotation",
                                    "motion",
                                    "mass",
                                    "density",
                                    "friction",
                                    "restitution",
                                    "linear_velocity",
                                    "angular_velocity",
                                    "linear_damping",
                                    "angular_damping",
                                    "gravity_factor",
                                    "allow_sleeping",
                                    "max_linear_velocity",
                                    "max_angular_velocity",
                                    "motion_quality",
                                    "sensor",
                                    "sensor_detects_static",
                                    "report_contacts"}));
  SceneBody out;
  STRATA_TRY(reader.String(body, "name", out.name));
  if (!body.contains("shape")) return reader.Fail("shape", "is required");
  Result<ShapeRef> shape = ParseShape(reader.At("shape"), body["shape"], base);
  if (!shape) return shape.error();
  BodyCreationSettings& settings = out.settings;
  settings.shape = *shape;
  STRATA_TRY(reader.Vector(body, "position", settings.position));
  // Caught here, with its JSON path: past this the broad phase refuses the body's bounds when the world is
  // built, and could only name it by its index in the batch.
  if (settings.position.cwiseAbs().maxCoeff() > kMaxScenePosition)
    return reader.Fail("position", "must be within 1e9 m of the origin on every axis");
  STRATA_TRY(reader.Rotation(body, "rotation", settings.rotation));
  STRATA_TRY(ParseMotion(reader, body, settings));
  if (body.contains("mass") && body.contains("density"))
    return reader.Fail("mass", "give mass or density, not both");
  if (body.contains("mass")) {
    float mass = 0.0f;
    STRATA_TRY(reader.Number(body, "mass", mass));
    if (mass <= 0.0f) return reader.Fail("mass", "must be positive");
    settings.mass = mass;
  }
  STRATA_TRY(reader.Number(body, "density", settings.density));
  STRATA_TRY(reader.Number(body, "friction", settings.friction));
  STRATA_TRY(reader.Number(body, "restitution", settings.restitution));
  STRATA_TRY(reader.Vector(body, "linear_velocity", settings.linear_velocity));
  STRATA_TRY(reader.Vector(body, "angular_velocity", settings.angular_velocity));
  STRATA_TRY(reader.Number(body, "linear_damping", settings.linear_damping));
  STRATA_TRY(reader.Number(body, "angular_damping", settings.angular_damping));
  STRATA_TRY(reader.Number(body, "gravity_factor", settings.gravity_factor));
  STRATA_TRY(reader.Boolean(body, "allow_sleeping", settings.allow_sleeping));
  STRATA_TRY(reader.Number(body, "max_linear_velocity", settings.max_linear_velocity));
  STRATA_TRY(reader.Number(body, "max_angular_velocity", settings.max_angular_velocity));
  STRATA_TRY(reader.Boolean(body, "sensor", settings.is_sensor));
  STRATA_TRY(reader.Boolean(body, "sensor_detects_static", settings.sensor_detects_static));
  STRATA_TRY(reader.Boolean(body, "report_contacts", settings.report_contacts));
  // A sensor goes on the moving layer whatever its motion: the default layers never pair two static ones,
  // and a static trigger that sees static bodies must be paired with them.
  if (settings.is_sensor) settings.object_layer = layers::kMoving;
  if (Status valid = settings.Validate(); !valid) {
    // Point at the value to change: the mass (or the density it came from), or the shape's size.
    const std::string& message = valid.message();
    std::string key;
    if (message.find("mass must be in") != std::string::npos) key = settings.mass ? "mass" : "density";
    if (message.find("mm across") != std::string::npos) key = "shape";
    if (message.find("sensor") != std::string::npos)
      key = settings.is_sensor ? "sensor" : "sensor_detects_static";
    return reader.Fail(key, message);
  }
  return out;
}

Status ParseSettings(const Reader& reader, const Json& json, Scene& scene) {
  if (!json.is_object()) return reader.Fail("", "must be an object");
  if (json.contains("position_iterations"))
    return reader.Fail("position_iterations",
                       "was replaced by substeps and relax_iterations (see assets/scenes/README.md)");
  STRATA_TRY(reader.OnlyKeys(
      json, {"gravity", "dt", "substeps", "velocity_iterations", "relax_iterations", "restitution_iterations",
             "contact_hertz", "contact_damping_ratio", "contact_push_max_velocity", "exact_small_islands",
             "gyroscopic_torque", "sleeping"}));
  PhysicsSettings& physics = scene.physics;
  STRATA_TRY(reader.Vector(json, "gravity", physics.gravity));
  STRATA_TRY(reader.Number(json, "dt", scene.dt));
  if (!(scene.dt > 0.0f) || scene.dt > 1.0f) return reader.Fail("dt", "must be in (0, 1] seconds");
  STRATA_TRY(reader.Integer(json, "substeps", physics.substeps));
  STRATA_TRY(reader.Integer(json, "velocity_iterations", physics.velocity_iterations));
  STRATA_TRY(reader.Integer(json, "relax_iterations", physics.relax_iterations));
  STRATA_TRY(reader.Integer(json, "restitution_iterations", physics.restitution_iterations));
  STRATA_TRY(reader.Number(json, "contact_hertz", physics.contact_hertz));
  STRATA_TRY(reader.Number(json, "contact_damping_ratio", physics.contact_damping_ratio));
  STRATA_TRY(reader.Number(json, "contact_push_max_velocity", physics.contact_push_max_velocity));
  STRATA_TRY(reader.Boolean(json, "exact_small_islands", physics.exact_small_islands));
  STRATA_TRY(reader.Boolean(json, "gyroscopic_torque", physics.gyroscopic_torque));
  STRATA_TRY(reader.Boolean(json, "sleeping", physics.allow_sleeping));
  if (Status valid = physics.Validate(); !valid) return reader.Fail("", valid.message());
  return Status::Ok();
}

#undef STRATA_TRY

}  // namespace

Result<Scene> ParseScene(const std::string& text, const std::string& source,
                         const std::filesystem::path& base_directory) {
  Result<Json> parsed = ParseStrictJson(text, source);
  if (!parsed) return parsed.error();
  const Json json = std::move(*parsed);
  const Reader root(source, "");
  if (!json.is_object()) return root.Fail("", "the scene must be a JSON object");
  if (Status keys = root.OnlyKeys(json, {"settings", "bodies", "constraints"}); !keys) return keys.error();
  Scene scene;
  if (json.contains("settings"))
    if (Status settings = ParseSettings(root.At("settings"), json["settings"], scene); !settings)
      return settings.error();
  if (!json.contains("bodies") || !json["bodies"].is_array()) return root.Fail("bodies", "must be an array");
  std::set<std::string> names;
  for (std::size_t i = 0; i < json["bodies"].size(); ++i) {
    const Reader reader = root.At("bodies/" + std::to_string(i));
    Result<SceneBody> body = ParseBody(reader, json["bodies"][i], base_directory);
    if (!body) return body.error();
    if (body->name.empty()) body->name = "body" + std::to_string(i);
    if (!names.insert(body->name).second)
      return reader.Fail("name", "duplicate body name '" + body->name + "'");
    scene.bodies.push_back(std::move(*body));
  }
  if (json.contains("constraints")) {
    if (!json["constraints"].is_array()) return root.Fail("constraints", "must be an array");
    std::map<std::string, int> body_index;
    for (std::size_t i = 0; i < scene.bodies.size(); ++i)
      body_index[scene.bodies[i].name] = static_cast<int>(i);
    std::set<std::string> joint_names;
    for (std::size_t i = 0; i < json["constraints"].size(); ++i) {
      const std::string path = "constraints/" + std::to_string(i);
      const Reader reader = root.At(path);
      Result<SceneConstraint> joint =
          ParseConstraint(reader, json["constraints"][i], body_index, scene.bodies);
      if (!joint) return joint.error();
      if (joint->name.empty()) joint->name = "joint" + std::to_string(i);
      if (!joint_names.insert(joint->name).second)
        return reader.Fail("name", "duplicate constraint name '" + joint->name + "'");
      joint->path = "/" + path;
      scene.constraints.push_back(std::move(*joint));
    }
  }
  return scene;
}

Result<Scene> LoadScene(const std::filesystem::path& path) {
  Result<std::string> text = ReadInputFile(path, kMaxSceneFileBytes);
  if (!text) return text.error();
  return ParseScene(*text, path.string(), path.parent_path());
}

Result<SceneWorld> BuildSceneWorld(const Scene& scene, PhysicsSystemConfig config) {
  config.max_bodies = std::max<std::uint32_t>(16, static_cast<std::uint32_t>(scene.bodies.size()));
  Result<std::unique_ptr<PhysicsSystem>> system = PhysicsSystem::Create(config, scene.physics);
  if (!system) return system.error();
  SceneWorld world{std::move(*system), {}, {}};
  std::vector<BodyID> ids;
  for (const SceneBody& body : scene.bodies) {
    Result<BodyID> id = world.system->bodies().CreateBody(body.settings);
    if (!id) return MakeError(id.error().code, "body '" + body.name + "': " + id.error().message);
    ids.push_back(*id);
  }
  if (Status added = world.system->bodies().AddBodies(ids); !added) return added.error();
  for (const SceneConstraint& constraint : scene.constraints) {
    JointSettings settings = constraint.settings;
    std::visit(
        [&](auto& joint) {
          joint.body_a = constraint.body_a >= 0 ? ids[constraint.body_a] : BodyID{};
          joint.body_b = ids[constraint.body_b];
        },
        settings);
    Result<ConstraintID> id = world.system->constraints().Add(settings);
    if (!id) return MakeError(id.error().code, constraint.path + ": " + id.error().message);
    world.constraint_ids.push_back(*id);
  }
  world.ids = std::move(ids);
  return world;
}

}  // namespace strata
