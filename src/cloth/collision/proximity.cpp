#include "cloth/collision/proximity.hpp"

#include <numbers>
#include <optional>

#include "cloth/collision/closest_points.hpp"
#include "cloth/collision/obstacle_pieces.hpp"
#include "core/assert.hpp"

namespace dexcloth::collision {

namespace {

Vec3 row(const CollisionMesh& m, int v) { return m.x0.row(v).transpose(); }

// Unit normal from the gap, or from the geometry when the gap vanishes.
Vec3 contact_normal(const Vec3& gap, const Vec3& geometric) {
  if (gap.squaredNorm() > 1e-28) return gap.normalized();
  if (geometric.squaredNorm() > 0.0) return geometric.normalized();
  return Vec3::UnitZ();
}

// Cloth–cloth pairs must be across the surface, not along it: in a flat sheet a vertex lies
// within the thickness of the diagonal edge of a non-incident triangle (h/√2 on a grid of
// spacing h), and parallel edges of neighbouring rows have interior closest points. Such
// in-plane pairs are not contacts (ARCSim likewise measures vertex–face distance along the
// face normal and edge–edge distance along the edges' common perpendicular). A pair counts when
// its gap makes at most 60° with the face normal (vertex–face) or with e_a × e_b (edge–edge).
constexpr double kMinAcrossCosine = 0.5;

bool across_surface(const Vec3& gap, const Vec3& direction) {
  const double g = gap.norm(), d = direction.norm();
  if (g < 1e-14) return true;               // touching: keep, the normal comes from geometry
  if (d < 1e-14 * (1.0 + g)) return false;  // degenerate face or parallel edges
  return std::abs(gap.dot(direction)) >= kMinAcrossCosine * g * d;
}

// Two points of one cloth within the thickness of each other across its surface are joined by a
// fold at least as long as a half circle of that diameter, π/2 · thickness. Pairs closer than that
// in the rest shape are bending neighbours, not contacts: on a mesh whose edges are about the
// thickness long, a bent sheet otherwise pushes its own two-ring neighbours apart, and a napkin
// hung by a corner crumpled into a ball. Continuous collision detection still stops them crossing.
// The candidates leave them out (CollisionCandidates::set_rest_neighbour_distance).
constexpr double kFoldLength = 0.5 * std::numbers::pi;

// An obstacle's edge between two coplanar faces (a diagonal of a box's or a table's flat side)
// is no feature of its surface. A cloth edge near it is nearest the plane at one of its ends,
// which the vertex–face pairs have, while the edges' common perpendicular tilts with the cloth
// edge's slope; and a cloth vertex over one of the two faces is nearest the other at the edge,
// with the gap tilted toward the vertex. Both pushed crumpled cloth sideways along a flat,
// frictionless table (up to 75 mm/s of its centre's velocity in 0.7 s). Nor is a vertex inside
// a flat region (all its faces in one plane, none of its edges on the mesh's boundary): a cloth
// vertex over one face is nearest another at that vertex, and the vertex is nearest a cloth face
// above it along a gap that leans with the cloth. Such pairs are left out; the cloth's vertices
// over the region have their pairs straight down (coplanar, flat_edge, flat_vertex and
// on_flat_feature: mesh_topology.hpp).

bool along(const Vec3& gap, const Vec3& n) {
  return gap.cross(n).norm() <= 1e-6 * gap.norm() * n.norm();
}

// Whether a vertex–face gap to an obstacle face ends on a flat edge or a flat vertex of it
// (barycentric `bary`: one weight zero, or one weight 1), off the face normal n.
bool on_flat_feature(const CollisionMesh& m, const MeshTopology& topology, int face,
                     const Vec3& bary, const Vec3& gap, const Vec3& n) {
  if (along(gap, n)) return false;  // straight above the face
  return collision::on_flat_feature(m.x0, m.faces, topology, face, bary);
}

// Where two shapes of one body overlap, the part of each one's surface inside the other is no
// surface of the body, and a pair ending there pushes the cloth along that buried surface's
// normal (in press_flatten, pairs with the thumb's capsule where it runs inside the pad box on
// it, and the rising hand carried folds of the napkin up). Such pairs are left out: the segment
// from the cloth to a buried point leaves the body through its outer surface, so a closer pair
// on that surface is found. A point less than this many thicknesses inside another shape is on
// the surface (the crease between them).
constexpr double kBuriedMargin = 1e-6;

// Whether point p of the surface of mesh m, on its face f, is buried in another of its pieces
// (`pieces`: each mesh's, none for a cloth or an obstacle of one piece).
bool buried(const std::vector<ObstaclePieces>& pieces, const CollisionCandidates& candidates, int m,
            int f, const Vec3& p, double thickness) {
  const ObstaclePieces& own = pieces[static_cast<std::size_t>(m)];
  return own.size() > 1 &&
         own.inside_other(candidates.topology(m).face_piece[static_cast<std::size_t>(f)], p,
                          kBuriedMargin * thickness);
}

/// How far the pairs of meshes a and b are searched: `obstacle_reach` with an obstacle searched
/// beyond the thickness, else `thickness`.
double reach(const CollisionMesh& a, const CollisionMesh& b, double thickness,
             double obstacle_reach) {
  return searched_beyond_thickness(a) || searched_beyond_thickness(b) ? obstacle_reach : thickness;
}

/// The proximity of vertex–face candidate `c`, if closer than `thickness` (or `obstacle_reach`,
/// with an obstacle searched beyond the thickness), appended to `out`.
void vertex_face_proximity(const std::vector<const CollisionMesh*>& meshes,
                           const std::vector<ObstaclePieces>& pieces,
                           const CollisionCandidates& candidates, const VertexFacePair& c,
                           double thickness, double obstacle_reach, std::vector<Proximity>& out) {
  const CollisionMesh& vm = *meshes[static_cast<std::size_t>(c.vertex_mesh)];
  const CollisionMesh& fm = *meshes[static_cast<std::size_t>(c.face_mesh)];
  const int a = fm.faces(c.face, 0), b = fm.faces(c.face, 1), cc = fm.faces(c.face, 2);
  const Vec3 p = row(vm, c.vertex), xa = row(fm, a), xb = row(fm, b), xc = row(fm, cc);
  const Vec3 bary = closest_point_triangle(p, xa, xb, xc);
  const Vec3 q = bary[0] * xa + bary[1] * xb + bary[2] * xc;
  const Vec3 gap = p - q;
  const double dist = gap.norm();
  const bool cloth_pair = !vm.obstacle && !fm.obstacle;
  if (dist >= reach(vm, fm, thickness, obstacle_reach)) return;
  if (cloth_pair && !across_surface(gap, (xb - xa).cross(xc - xa))) return;
  if (fm.obstacle && on_flat_feature(fm, candidates.topology(c.face_mesh), c.face, bary, gap,
                                     (xb - xa).cross(xc - xa)))
    return;
  if (buried(pieces, candidates, c.face_mesh, c.face, q, thickness)) return;
  if (vm.obstacle) {
    const MeshTopology& topology = candidates.topology(c.vertex_mesh);
    if (const auto plane = flat_vertex(vm.x0, vm.faces, topology, c.vertex);
        plane && !along(gap, *plane))
      return;
    const int face = topology.vertex_faces[static_cast<std::size_t>(
        topology.vertex_face_start[static_cast<std::size_t>(c.vertex)])];
    if (buried(pieces, candidates, c.vertex_mesh, face, p, thickness)) return;
  }
  Proximity prox;
  prox.edge_edge = false;
  prox.mesh = {c.vertex_mesh, c.face_mesh};
  prox.corner = {c.vertex, a, b, cc};
  prox.first = c.vertex;
  prox.second = c.face;
  prox.w = {1.0, -bary[0], -bary[1], -bary[2]};
  prox.normal = contact_normal(gap, (xb - xa).cross(xc - xa));
  prox.distance = dist;
  out.push_back(prox);
}

/// The proximity of edge–edge candidate `c`, if closer than `thickness` (or `obstacle_reach`,
/// with an obstacle searched beyond the thickness), appended to `out`.
void edge_edge_proximity(const std::vector<const CollisionMesh*>& meshes,
                         const std::vector<ObstaclePieces>& pieces,
                         const CollisionCandidates& candidates, const EdgeEdgePair& c,
                         double thickness, double obstacle_reach, std::vector<Proximity>& out) {
  const CollisionMesh& ma = *meshes[static_cast<std::size_t>(c.mesh_a)];
  const CollisionMesh& mb = *meshes[static_cast<std::size_t>(c.mesh_b)];
  const std::array<int, 2>& ea =
      candidates.topology(c.mesh_a).edges[static_cast<std::size_t>(c.edge_a)];
  const std::array<int, 2>& eb =
      candidates.topology(c.mesh_b).edges[static_cast<std::size_t>(c.edge_b)];
  const Vec3 p0 = row(ma, ea[0]), p1 = row(ma, ea[1]), q0 = row(mb, eb[0]), q1 = row(mb, eb[1]);
  const Vec2 su = closest_points_segments(p0, p1, q0, q1);
  // Closest points at an edge's end are a vertex–face pair's (closest on that face's
  // boundary): keep edge–edge pairs for interior closest points only, so no pair counts twice.
  if (su[0] <= 0.0 || su[0] >= 1.0 || su[1] <= 0.0 || su[1] >= 1.0) return;
  const Vec3 pa = p0 + su[0] * (p1 - p0), qb = q0 + su[1] * (q1 - q0);
  const Vec3 gap = pa - qb;
  const double dist = gap.norm();
  const bool cloth_pair = !ma.obstacle && !mb.obstacle;
  if (dist >= reach(ma, mb, thickness, obstacle_reach)) return;
  if (cloth_pair && !across_surface(gap, (p1 - p0).cross(q1 - q0))) return;
  if ((ma.obstacle && flat_edge(ma.x0, ma.faces, candidates.topology(c.mesh_a), c.edge_a)) ||
      (mb.obstacle && flat_edge(mb.x0, mb.faces, candidates.topology(c.mesh_b), c.edge_b)))
    return;
  const auto buried_edge = [&](int m, int edge, const Vec3& point) {
    const int face = candidates.topology(m).edge_faces[static_cast<std::size_t>(edge)][0];
    return buried(pieces, candidates, m, face, point, thickness);
  };
  if (buried_edge(c.mesh_a, c.edge_a, pa) || buried_edge(c.mesh_b, c.edge_b, qb)) return;
  Proximity prox;
  prox.edge_edge = true;
  prox.mesh = {c.mesh_a, c.mesh_b};
  prox.corner = {ea[0], ea[1], eb[0], eb[1]};
  prox.first = c.edge_a;
  prox.second = c.edge_b;
  prox.w = {1.0 - su[0], su[0], -(1.0 - su[1]), -su[1]};
  prox.normal = contact_normal(gap, (p1 - p0).cross(q1 - q0));
  prox.distance = dist;
  out.push_back(prox);
}

}  // namespace

void find_proximities(const std::vector<const CollisionMesh*>& meshes, double thickness,
                      CollisionCandidates& candidates, std::vector<Proximity>& out,
                      std::vector<std::vector<Proximity>>& scratch) {
  find_proximities(meshes, thickness, thickness, candidates, out, scratch);
}

void find_proximities(const std::vector<const CollisionMesh*>& meshes, double thickness,
                      double obstacle_reach, CollisionCandidates& candidates,
                      std::vector<Proximity>& out, std::vector<std::vector<Proximity>>& scratch) {
  DEXCLOTH_DEMAND(thickness > 0.0 && obstacle_reach >= thickness);
  out.clear();
  // Boxes of x0 inflated by half the thickness meet when primitives are within the thickness
  // (those of obstacles searched beyond it by the rest of their reach); face pairs of one cloth
  // made only of rest neighbours are left out before any pair test.
  candidates.set_rest_neighbour_distance(kFoldLength * thickness);
  candidates.update(meshes, false, 0.5 * thickness, obstacle_reach - 0.5 * thickness);
  // The pieces of every obstacle made of several (the shapes of one body), at x0.
  std::vector<ObstaclePieces> pieces(meshes.size());
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const MeshTopology& topology = candidates.topology(static_cast<int>(m));
    if (meshes[m]->obstacle && topology.pieces() > 1)
      pieces[m].update(meshes[m]->x0, meshes[m]->faces, topology);
  }
  // The vertex–face, then the edge–edge candidates, in consecutive chunks shared round-robin
  // among the pool's threads; the chunks' proximities concatenated in order.
  // Few candidates are tested on the calling thread (waking the pool costs more).
  constexpr std::size_t kParallelCandidates = 8000;
  const std::size_t total = candidates.vertex_face().size() + candidates.edge_edge().size();
  WorkerPool* pool = total >= kParallelCandidates ? candidates.pool() : nullptr;
  const int threads = pool ? pool->threads() : 1;
  const std::size_t chunks = 4 * static_cast<std::size_t>(threads);
  if (scratch.size() < 2 * chunks) scratch.resize(2 * chunks);
  const std::vector<VertexFacePair>& vf = candidates.vertex_face();
  const std::vector<EdgeEdgePair>& ee = candidates.edge_edge();
  auto search = [&](int t) {
    for (std::size_t c = static_cast<std::size_t>(t); c < chunks;
         c += static_cast<std::size_t>(threads)) {
      std::vector<Proximity>& a = scratch[c];
      std::vector<Proximity>& b = scratch[chunks + c];
      a.clear();
      b.clear();
      for (std::size_t k = vf.size() * c / chunks; k < vf.size() * (c + 1) / chunks; ++k)
        vertex_face_proximity(meshes, pieces, candidates, vf[k], thickness, obstacle_reach, a);
      for (std::size_t k = ee.size() * c / chunks; k < ee.size() * (c + 1) / chunks; ++k)
        edge_edge_proximity(meshes, pieces, candidates, ee[k], thickness, obstacle_reach, b);
    }
  };
  if (pool) {
    pool->run(search);
  } else {
    search(0);
  }
  for (std::size_t c = 0; c < 2 * chunks; ++c)
    out.insert(out.end(), scratch[c].begin(), scratch[c].end());
}

void find_proximities(const std::vector<const CollisionMesh*>& meshes, double thickness,
                      CollisionCandidates& candidates, std::vector<Proximity>& out) {
  std::vector<std::vector<Proximity>> scratch;
  find_proximities(meshes, thickness, candidates, out, scratch);
}

}  // namespace dexcloth::collision
