#include "assets/scene/SceneLoader.h"
#include "assets/json/StrictJson.h"
#include "assets/scene/JointParser.h"
#include "assets/scene/SceneBuilder.h"
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
#include "physics/shapes/HeightFieldShape.h"
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

// Where a shape whose numbers parse but make no valid shape is pointed at, by its type and source.
struct ShapeSource {
  std::string type;
  bool from_file = false;

  std::string ErrorKey() const {
    if (type == "sphere") return "radius";
    if (type == "box") return "half_extents";
    if (type == "convex_hull") return "points";
    if (type == "mesh") return from_file ? "file" : "";
    if (type == "heightfield") return from_file ? "file" : "heights";
    return "";
  }
};

Status ParseMeshFile(const Reader& reader, const Json& shape, const std::filesystem::path& base,
                     MeshGeometry& mesh) {
  if (!shape["file"].is_string()) return reader.Fail("file", "must be a path string");
  MeshImportOptions options;
  STRATA_TRY(reader.Number(shape, "scale", options.scale));
  STRATA_TRY(reader.Boolean(shape, "z_up", options.z_up));
  Result<ImportedMesh> imported = ImportMesh(base / shape["file"].get<std::string>(), options);
  if (!imported) return reader.Fail("file", imported.error().message);
  mesh.vertices = std::move(imported->vertices);
  mesh.triangles = std::move(imported->triangles);
  return Status::Ok();
}

Status ParseMesh(const Reader& reader, const Json& shape, const std::filesystem::path& base,
                 MeshGeometry& mesh) {
  if (shape.contains("file")) return ParseMeshFile(reader, shape, base, mesh);
  Result<std::vector<Vec3>> vertices = ParsePoints(reader, shape, "vertices");
  if (!vertices) return vertices.error();
  if (!shape.contains("indices") || !shape["indices"].is_array() || shape["indices"].size() % 3 != 0)
    return reader.Fail("indices", "must be a flat array of vertex indices, 3 per triangle");
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
    mesh.triangles.push_back(triangle);
  }
  mesh.vertices = std::move(*vertices);
  return Status::Ok();
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

Status ParseHeightPicture(const Reader& reader, const Json& shape, const std::filesystem::path& path,
                          HeightFieldGeometry& field) {
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
  field.columns = map->columns, field.rows = map->rows, field.heights = std::move(map->heights);
  return Status::Ok();
}

Status ParseHeightFile(const Reader& reader, const Json& shape, const std::filesystem::path& base,
                       HeightFieldGeometry& field) {
  if (!shape["file"].is_string()) return reader.Fail("file", "must be a path string");
  const std::filesystem::path path = base / shape["file"].get<std::string>();
  if (path.extension() == ".png") return ParseHeightPicture(reader, shape, path, field);
  if (shape.contains("height_range")) return reader.Fail("height_range", "is for a PNG picture only");
  STRATA_TRY(ParseSampleCount(reader, shape, "columns", field.columns));
  STRATA_TRY(ParseSampleCount(reader, shape, "rows", field.rows));
  Result<HeightMap> map = ImportRawHeights(path, field.columns, field.rows);
  if (!map) return reader.Fail("file", map.error().message);
  field.heights = std::move(map->heights);
  return Status::Ok();
}

Status ParseHeightField(const Reader& reader, const Json& shape, const std::filesystem::path& base,
                        HeightFieldGeometry& field) {
  STRATA_TRY(reader.Number(shape, "cell_size", field.cell));
  if (shape.contains("file")) return ParseHeightFile(reader, shape, base, field);
  STRATA_TRY(ParseSampleCount(reader, shape, "columns", field.columns));
  STRATA_TRY(ParseSampleCount(reader, shape, "rows", field.rows));
  if (!shape.contains("heights") || !shape["heights"].is_array())
    return reader.Fail("heights", "must be an array of columns x rows heights (null for a hole)");
  const Json& values = shape["heights"];
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (values[i].is_null()) {
      field.heights.push_back(HeightFieldShape::kHole);
      continue;
    }
    const std::string key = "heights/" + std::to_string(i);
    if (!values[i].is_number()) return reader.Fail(key, "must be a number, or null for a hole");
    const double height = values[i].get<double>();
    if (!std::isfinite(height) || std::abs(height) > std::numeric_limits<float>::max())
      return reader.Fail(key, "must be finite and fit a 32-bit float");
    field.heights.push_back(static_cast<float>(height));
  }
  return Status::Ok();
}

// "convex_radius" of a box or hull, when given.
Status ParseConvexRadius(const Reader& reader, const Json& shape, BodyDescription& body) {
  if (!shape.contains("convex_radius")) return Status::Ok();
  float radius = 0.0f;
  STRATA_TRY(reader.Number(shape, "convex_radius", radius));
  if (radius < 0.0f) return reader.Fail("convex_radius", "must be >= 0 (0: sharp edges)");
  body.convex_radius = radius;
  return Status::Ok();
}

// The geometry-backed shapes: their data goes to the scene's lists, the body names its entry.
Status ParseGeometryShape(const Reader& reader, const Json& shape, const std::filesystem::path& base,
                          const std::string& type, SceneDescription& scene, BodyDescription& body) {
  if (type == "convex_hull") {
    STRATA_TRY(reader.OnlyKeys(shape, {"type", "points", "convex_radius"}));
    STRATA_TRY(ParseConvexRadius(reader, shape, body));
    Result<std::vector<Vec3>> points = ParsePoints(reader, shape, "points");
    if (!points) return points.error();
    body.shape = SceneShape::kHull, body.geometry = static_cast<std::uint32_t>(scene.hulls.size());
    scene.hulls.push_back({std::move(*points)});
    return Status::Ok();
  }
  if (type == "mesh") {
    STRATA_TRY(reader.OnlyKeys(shape, {"type", "vertices", "indices", "file", "scale", "z_up"}));
    MeshGeometry mesh;
    STRATA_TRY(ParseMesh(reader, shape, base, mesh));
    body.shape = SceneShape::kMesh, body.geometry = static_cast<std::uint32_t>(scene.meshes.size());
    scene.meshes.push_back(std::move(mesh));
    return Status::Ok();
  }
  if (type == "heightfield") {
    STRATA_TRY(
        reader.OnlyKeys(shape, {"type", "columns", "rows", "cell_size", "heights", "file", "height_range"}));
    HeightFieldGeometry field;
    STRATA_TRY(ParseHeightField(reader, shape, base, field));
    body.shape = SceneShape::kHeightField;
    body.geometry = static_cast<std::uint32_t>(scene.height_fields.size());
    scene.height_fields.push_back(std::move(field));
    return Status::Ok();
  }
  return reader.Fail(
      "type", "must be one of sphere, box, capsule, convex_hull, mesh, heightfield (got '" + type + "')");
}

// The shape's description into `body` (and `scene`'s geometry), then the shape made from it, so a shape
// that cannot be made is reported at the value that makes it so.
Result<ShapeRef> ParseShape(const Reader& reader, const Json& shape, const std::filesystem::path& base,
                            SceneDescription& scene, BodyDescription& body) {
  if (!shape.is_object()) return reader.Fail("", "must be an object");
  ShapeSource source;
  STRATA_TRY(reader.String(shape, "type", source.type));
  source.from_file = shape.contains("file");
  body.radius = body.half_height = -1.0f;
  body.half_extents = Vec3::Constant(-1.0f);
  if (source.type == "sphere") {
    STRATA_TRY(reader.OnlyKeys(shape, {"type", "radius"}));
    STRATA_TRY(reader.Number(shape, "radius", body.radius));
    body.shape = SceneShape::kSphere;
  } else if (source.type == "box") {
    STRATA_TRY(reader.OnlyKeys(shape, {"type", "half_extents", "convex_radius"}));
    STRATA_TRY(reader.Vector(shape, "half_extents", body.half_extents));
    STRATA_TRY(ParseConvexRadius(reader, shape, body));
    body.shape = SceneShape::kBox;
  } else if (source.type == "capsule") {
    STRATA_TRY(reader.OnlyKeys(shape, {"type", "radius", "half_height"}));
    STRATA_TRY(reader.Number(shape, "radius", body.radius));
    STRATA_TRY(reader.Number(shape, "half_height", body.half_height));
    body.shape = SceneShape::kCapsule;
  } else {
    STRATA_TRY(ParseGeometryShape(reader, shape, base, source.type, scene, body));
  }
  Result<ShapeRef> made = MakeShape(scene, body);
  if (!made) {
    // A radius too large for the shape is the radius's fault; anything else, the geometry's.
    const bool radius_fault =
        body.convex_radius && made.error().message.find("convex radius") != std::string::npos;
    return reader.Fail(radius_fault ? "convex_radius" : source.ErrorKey(), made.error().message);
  }
  return made;
}

// "motion" and "motion_quality".
Status ParseMotion(const Reader& reader, const Json& json, BodyDescription& body) {
  std::string motion = "dynamic";
  STRATA_TRY(reader.String(json, "motion", motion));
  if (motion == "static")
    body.motion = SceneMotion::kStatic;
  else if (motion == "kinematic")
    body.motion = SceneMotion::kKinematic;
  else if (motion == "dynamic")
    body.motion = SceneMotion::kDynamic;
  else
    return reader.Fail("motion", "must be static, kinematic or dynamic (got '" + motion + "')");
  std::string quality = "discrete";
  STRATA_TRY(reader.String(json, "motion_quality", quality));
  if (quality != "linear_cast" && quality != "discrete")
    return reader.Fail("motion_quality", "must be discrete or linear_cast (got '" + quality + "')");
  body.linear_cast = quality == "linear_cast";
  return Status::Ok();
}

// A number that stays unset (each engine's default) when the key is absent.
Status OptionalNumber(const Reader& reader, const Json& json, const std::string& key,
                      std::optional<float>& out) {
  if (!json.contains(key)) return Status::Ok();
  float value = 0.0f;
  STRATA_TRY(reader.Number(json, key, value));
  out = value;
  return Status::Ok();
}

Status ParseMass(const Reader& reader, const Json& json, BodyDescription& body) {
  if (json.contains("mass") && json.contains("density"))
    return reader.Fail("mass", "give mass or density, not both");
  if (json.contains("mass")) {
    STRATA_TRY(reader.Number(json, "mass", body.mass));
    if (body.mass <= 0.0f) return reader.Fail("mass", "must be positive");
  }
  return OptionalNumber(reader, json, "density", body.density);
}

Status ParseBodyValues(const Reader& reader, const Json& json, BodyDescription& body) {
  STRATA_TRY(reader.Vector(json, "position", body.position));
  // Caught here, with its JSON path: past this the broad phase refuses the body's bounds when the world is
  // built, and could only name it by its index in the batch.
  if (body.position.cwiseAbs().maxCoeff() > kMaxScenePosition)
    return reader.Fail("position", "must be within 1e9 m of the origin on every axis");
  STRATA_TRY(reader.Rotation(json, "rotation", body.rotation));
  STRATA_TRY(ParseMotion(reader, json, body));
  STRATA_TRY(ParseMass(reader, json, body));
  STRATA_TRY(reader.Number(json, "friction", body.friction));
  STRATA_TRY(reader.Number(json, "restitution", body.restitution));
  STRATA_TRY(reader.Vector(json, "linear_velocity", body.linear_velocity));
  STRATA_TRY(reader.Vector(json, "angular_velocity", body.angular_velocity));
  STRATA_TRY(OptionalNumber(reader, json, "linear_damping", body.linear_damping));
  STRATA_TRY(OptionalNumber(reader, json, "angular_damping", body.angular_damping));
  STRATA_TRY(OptionalNumber(reader, json, "gravity_factor", body.gravity_factor));
  STRATA_TRY(reader.Boolean(json, "allow_sleeping", body.allow_sleeping));
  STRATA_TRY(OptionalNumber(reader, json, "max_linear_velocity", body.max_linear_velocity));
  STRATA_TRY(OptionalNumber(reader, json, "max_angular_velocity", body.max_angular_velocity));
  STRATA_TRY(reader.Boolean(json, "sensor", body.sensor));
  STRATA_TRY(reader.Boolean(json, "sensor_detects_static", body.sensor_detects_static));
  return reader.Boolean(json, "report_contacts", body.report_contacts);
}

// Parses body `json` into `scene` and returns its shape, after checking the body Strata would make.
Result<ShapeRef> ParseBody(const Reader& reader, const Json& json, const std::filesystem::path& base,
                           SceneDescription& scene) {
  if (!json.is_object()) return reader.Fail("", "must be an object");
  STRATA_TRY(reader.OnlyKeys(json, {"name",
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
  BodyDescription body;
  body.friction = BodyCreationSettings().friction;  // the file format's defaults are Strata's
  body.restitution = BodyCreationSettings().restitution;
  STRATA_TRY(reader.String(json, "name", body.name));
  if (!json.contains("shape")) return reader.Fail("shape", "is required");
  Result<ShapeRef> shape = ParseShape(reader.At("shape"), json["shape"], base, scene, body);
  if (!shape) return shape.error();
  STRATA_TRY(ParseBodyValues(reader, json, body));
  const BodyCreationSettings settings = ToBodySettings(body, *shape);
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
  scene.bodies.push_back(std::move(body));
  return shape;
}

Status ParseSettings(const Reader& reader, const Json& json, SceneDescription& scene) {
  if (!json.is_object()) return reader.Fail("", "must be an object");
  if (json.contains("position_iterations"))
    return reader.Fail("position_iterations",
                       "was replaced by substeps and relax_iterations (see assets/scenes/README.md)");
  STRATA_TRY(reader.OnlyKeys(
      json, {"gravity", "dt", "substeps", "velocity_iterations", "relax_iterations", "restitution_iterations",
             "contact_hertz", "contact_damping_ratio", "contact_push_max_velocity", "exact_small_islands",
             "gyroscopic_torque", "sleeping", "sleep_rule", "sleep_point_velocity"}));
  STRATA_TRY(reader.Vector(json, "gravity", scene.gravity));
  STRATA_TRY(reader.Number(json, "dt", scene.dt));
  if (!(scene.dt > 0.0f) || scene.dt > 1.0f) return reader.Fail("dt", "must be in (0, 1] seconds");
  STRATA_TRY(reader.Integer(json, "substeps", scene.substeps));
  STRATA_TRY(reader.Integer(json, "velocity_iterations", scene.velocity_iterations));
  STRATA_TRY(reader.Integer(json, "relax_iterations", scene.relax_iterations));
  STRATA_TRY(reader.Integer(json, "restitution_iterations", scene.restitution_iterations));
  STRATA_TRY(reader.Number(json, "contact_hertz", scene.contact_hertz));
  STRATA_TRY(reader.Number(json, "contact_damping_ratio", scene.contact_damping_ratio));
  STRATA_TRY(reader.Number(json, "contact_push_max_velocity", scene.contact_push_max_velocity));
  STRATA_TRY(reader.Boolean(json, "exact_small_islands", scene.exact_small_islands));
  STRATA_TRY(reader.Boolean(json, "gyroscopic_torque", scene.gyroscopic_torque));
  STRATA_TRY(reader.Boolean(json, "sleeping", scene.sleeping));
  std::string rule = scene.sleep_rule == SleepRule::kPointMovement ? "point_movement" : "velocity";
  STRATA_TRY(reader.String(json, "sleep_rule", rule));
  if (rule != "velocity" && rule != "point_movement")
    return reader.Fail("sleep_rule", "must be velocity or point_movement (got '" + rule + "')");
  scene.sleep_rule = rule == "velocity" ? SleepRule::kVelocity : SleepRule::kPointMovement;
  STRATA_TRY(reader.Number(json, "sleep_point_velocity", scene.sleep_point_velocity));
  if (Status valid = ToPhysicsSettings(scene).Validate(); !valid) return reader.Fail("", valid.message());
  return Status::Ok();
}

Status ParseBodies(const Reader& root, const Json& json, const std::filesystem::path& base, Scene& scene) {
  if (!json.contains("bodies") || !json["bodies"].is_array()) return root.Fail("bodies", "must be an array");
  std::set<std::string> names;
  for (std::size_t i = 0; i < json["bodies"].size(); ++i) {
    const Reader reader = root.At("bodies/" + std::to_string(i));
    Result<ShapeRef> shape = ParseBody(reader, json["bodies"][i], base, scene.description);
    if (!shape) return shape.error();
    std::string& name = scene.description.bodies.back().name;
    if (name.empty()) name = "body" + std::to_string(i);
    if (!names.insert(name).second) return reader.Fail("name", "duplicate body name '" + name + "'");
    scene.shapes.push_back(std::move(*shape));
  }
  return Status::Ok();
}

Status ParseJoints(const Reader& root, const Json& json, SceneDescription& scene) {
  if (!json.contains("constraints")) return Status::Ok();
  if (!json["constraints"].is_array()) return root.Fail("constraints", "must be an array");
  std::map<std::string, int> body_index;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i)
    body_index[scene.bodies[i].name] = static_cast<int>(i);
  std::set<std::string> names;
  for (std::size_t i = 0; i < json["constraints"].size(); ++i) {
    const Reader reader = root.At("constraints/" + std::to_string(i));
    Result<JointDescription> joint =
        ParseConstraint(reader, json["constraints"][i], body_index, scene.bodies);
    if (!joint) return joint.error();
    if (joint->name.empty()) joint->name = "joint" + std::to_string(i);
    if (!names.insert(joint->name).second)
      return reader.Fail("name", "duplicate constraint name '" + joint->name + "'");
    scene.joints.push_back(std::move(*joint));
  }
  return Status::Ok();
}

#undef STRATA_TRY

// What BuildSceneWorld needs of a Scene made or changed in code, not read from a file: a shape per body and
// joints between bodies of the scene.
Status CheckBuildable(const Scene& scene) {
  const SceneDescription& description = scene.description;
  const int body_count = static_cast<int>(description.bodies.size());
  if (scene.shapes.size() != description.bodies.size())
    return MakeError(ErrorCode::kInvalidArgument, "the scene has " + std::to_string(scene.shapes.size()) +
                                                      " shapes for " + std::to_string(body_count) +
                                                      " bodies");
  for (std::size_t i = 0; i < description.joints.size(); ++i) {
    const JointDescription& joint = description.joints[i];
    if (joint.body_a < -1 || joint.body_a >= body_count || joint.body_b < 0 || joint.body_b >= body_count)
      return MakeError(ErrorCode::kInvalidArgument, "/constraints/" + std::to_string(i) +
                                                        ": names a body the scene does not have (it has " +
                                                        std::to_string(body_count) + ")");
  }
  return Status::Ok();
}

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
  scene.description.sleeping = PhysicsSettings().allow_sleeping;  // the file format's default is Strata's
  if (json.contains("settings"))
    if (Status settings = ParseSettings(root.At("settings"), json["settings"], scene.description); !settings)
      return settings.error();
  if (Status bodies = ParseBodies(root, json, base_directory, scene); !bodies) return bodies.error();
  if (Status joints = ParseJoints(root, json, scene.description); !joints) return joints.error();
  return scene;
}

Result<Scene> LoadScene(const std::filesystem::path& path) {
  Result<std::string> text = ReadInputFile(path, kMaxSceneFileBytes);
  if (!text) return text.error();
  return ParseScene(*text, path.string(), path.parent_path());
}

Result<SceneWorld> BuildSceneWorld(const Scene& scene, PhysicsSystemConfig config) {
  const SceneDescription& description = scene.description;
  if (Status valid = CheckBuildable(scene); !valid) return valid.error();
  config.max_bodies = std::max<std::uint32_t>(16, static_cast<std::uint32_t>(description.bodies.size()));
  Result<std::unique_ptr<PhysicsSystem>> system =
      PhysicsSystem::Create(config, ToPhysicsSettings(description));
  if (!system) return system.error();
  SceneWorld world{std::move(*system), {}, {}};
  for (std::size_t i = 0; i < description.bodies.size(); ++i) {
    const BodyDescription& body = description.bodies[i];
    Result<BodyID> id = world.system->bodies().CreateBody(ToBodySettings(body, scene.shapes[i]));
    if (!id) return MakeError(id.error().code, "body '" + body.name + "': " + id.error().message);
    world.ids.push_back(*id);
  }
  if (Status added = world.system->bodies().AddBodies(world.ids); !added) return added.error();
  for (std::size_t i = 0; i < description.joints.size(); ++i) {
    Result<ConstraintID> id =
        world.system->constraints().Add(ToJointSettings(description.joints[i], world.ids));
    if (!id)
      return MakeError(id.error().code, "/constraints/" + std::to_string(i) + ": " + id.error().message);
    world.constraint_ids.push_back(*id);
  }
  return world;
}

}  // namespace strata
