// PolyhedronCollider: separating-axis test between two convex polyhedra (boxes, hulls, mesh triangles)
// with face clipping for the manifold. Exact and robust for the flat-on-flat contacts of stacks and
// level geometry, where GJK on a 100 m floor against a 1 m box loses precision. Pure; any thread.
#pragma once

#include <array>
#include <span>

#include "physics/narrowphase/ContactManifold.h"
#include "physics/shapes/ConvexShape.h"

namespace strata {

/// World-space view of a convex polyhedron: vertices, face planes with their vertex loops, and edges.
struct Polyhedron {
  static constexpr int kMaxVertices = 64;
  static constexpr int kMaxFaces = 64;
  static constexpr int kMaxEdges = 128;

  int vertex_count = 0;
  int face_count = 0;
  int edge_count = 0;
  std::array<Vec3, kMaxVertices> vertices;
  std::array<Vec3, kMaxFaces> face_normals;   ///< outward, unit
  std::array<float, kMaxFaces> face_offsets;  ///< normal . x on the face
  std::array<int, kMaxFaces + 1> face_start;  ///< face f's loop is face_loop[face_start[f], face_start[f+1])
  std::array<int, kMaxFaces * 8> face_loop;
  std::array<std::array<int, 2>, kMaxEdges> edges;       ///< each undirected edge once
  std::array<std::array<int, 2>, kMaxEdges> edge_faces;  ///< the two faces each edge joins (closed shapes)
  bool one_sided = false;                                ///< a mesh triangle: only its front face collides
  bool is_box = false;           ///< vertex i has signs (bit 0: x, bit 1: y, bit 2: z)
  Vec3 centroid = Vec3::Zero();  ///< average of the vertices
  int direction_count = 0;
  std::array<Vec3, kMaxEdges> edge_directions;  ///< unit, one per set of parallel edges (SAT axes)

  /// Farthest vertex along `direction`.
  Vec3 Support(const Vec3& direction) const;
  /// Vertex loop of face f as a SupportingFace.
  void Face(int f, SupportingFace& face) const;
};

/// A box, hull or triangle posed in world space. Returns false for shapes that are not polyhedra.
bool MakePolyhedron(const ConvexShape& shape, const Pose& pose, Polyhedron& out);
/// A single mesh triangle with unit front normal `normal`: one front face (counter-clockwise a, b, c), three
/// edges. It is one-sided: contacts only push bodies out through the front, as level geometry expects.
void MakeTrianglePolyhedron(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& normal, Polyhedron& out);

/// The face of `p` whose normal is most aligned with `direction`.
int MostAlignedFace(const Polyhedron& p, const Vec3& direction);

/// Contact between two polyhedra. Returns true and fills `manifold` (normal from A to B and points) when
/// they are closer than `max_separation`.
bool CollidePolyhedra(const Polyhedron& a, const Polyhedron& b, float max_separation,
                      ContactManifold& manifold);

}  // namespace strata
