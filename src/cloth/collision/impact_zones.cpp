#include "cloth/collision/impact_zones.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "cloth/collision/ccd.hpp"

namespace dexcloth::collision {

namespace {

Vec3 x0_of(const CollisionMesh& m, int v) { return m.x0.row(v).transpose(); }
Vec3 x1_of(const CollisionMesh& m, int v) { return m.x1.row(v).transpose(); }

/// Merges repeated messages into their first occurrence, counted: a zone hit again in every
/// round reported the same fallback up to 40 times in one step.
void merge_repeats(std::vector<std::string>& messages) {
  std::vector<std::string> unique;
  std::vector<int> count;
  for (std::string& m : messages) {
    const auto it = std::find(unique.begin(), unique.end(), m);
    if (it != unique.end()) {
      ++count[static_cast<std::size_t>(it - unique.begin())];
    } else {
      unique.push_back(std::move(m));
      count.push_back(1);
    }
  }
  for (std::size_t k = 0; k < unique.size(); ++k)
    if (count[k] > 1) unique[k] += " (" + std::to_string(count[k]) + " rounds)";
  messages = std::move(unique);
}

/// Unit normal of face f of `m` at x0 (outward on a closed obstacle: counter-clockwise).
Vec3 unit_face_normal(const CollisionMesh& m, int f) {
  const Vec3 n = face_normal(m.x0, m.faces, f);
  return n.squaredNorm() > 0.0 ? Vec3(n.normalized()) : Vec3::Zero();
}

/// Outward direction of obstacle `m` at a vertex: the sum of its faces' unit normals.
Vec3 vertex_outward(const CollisionMesh& m, const MeshTopology& topology, int v) {
  Vec3 o = Vec3::Zero();
  for (int k = topology.vertex_face_start[static_cast<std::size_t>(v)];
       k < topology.vertex_face_start[static_cast<std::size_t>(v) + 1]; ++k)
    o += unit_face_normal(m, topology.vertex_faces[static_cast<std::size_t>(k)]);
  return o;
}

/// Outward direction of obstacle `m` at a point of edge e at fraction u along it (from its
/// first vertex): its two faces' normals, or a vertex's at an end.
Vec3 edge_outward(const CollisionMesh& m, const MeshTopology& topology, int e, double u) {
  const std::array<int, 2>& ends = topology.edges[static_cast<std::size_t>(e)];
  if (u <= 0.0) return vertex_outward(m, topology, ends[0]);
  if (u >= 1.0) return vertex_outward(m, topology, ends[1]);
  Vec3 o = Vec3::Zero();
  for (const int f : topology.edge_faces[static_cast<std::size_t>(e)])
    if (f >= 0) o += unit_face_normal(m, f);
  return o;
}

/// Outward direction of obstacle `m` at the point of face f with barycentric weights b: the
/// face's normal inside it, an edge's or a vertex's on its boundary.
Vec3 face_outward(const CollisionMesh& m, const MeshTopology& topology, int f, const Vec3& b) {
  for (int k = 0; k < 3; ++k) {
    if (b[k] == 1.0) return vertex_outward(m, topology, m.faces(f, k));
    const int next = (k + 1) % 3, other = (k + 2) % 3;  // edge k joins corners k and k + 1
    if (b[other] == 0.0 && b[k] > 0.0 && b[next] > 0.0) {
      const int e = topology.face_edges[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)];
      const bool along = topology.edges[static_cast<std::size_t>(e)][0] == m.faces(f, k);
      return edge_outward(m, topology, e, along ? b[next] : b[k]);
    }
  }
  return unit_face_normal(m, f);
}

}  // namespace

// A cloth primitive that starts just inside a closed obstacle (pushed a few micrometres in by
// the solve, the impact zones' own rounding, or a body that turned into it) has an impact with
// the obstacle's surface from behind, and the CCD orients its normal by that start side: into
// the body. The projection then keeps the cloth inside and the body carries it along wherever
// it goes (a napkin vertex on the edge of a thumb's pad box rose with the hand to 11 cm, its
// edge to the next vertex on the inner side of the box's edge, stretched ten times). Within the
// offset the side is not told by the start gap but by the obstacle: the normal points out of it,
// along the outward direction at the obstacle's feature, so the projection puts the cloth back
// outside, and a pair that leaves on its own is no impact. Deeper cloth is left as the CCD has
// it (push_out_of_obstacles moves it out). Returns whether the normal was turned.
bool ImpactZoneSolver::orient_outward(const std::vector<CollisionMesh*>& meshes, bool edge_edge,
                                      const std::array<int, 4>& mesh,
                                      const std::array<int, 2>& primitive, const Corners& x0,
                                      double offset, Impact& impact) {
  // The obstacle's side: the face or edge q (second) or the vertex or edge p (first).
  const CollisionMesh& first = *meshes[static_cast<std::size_t>(mesh[0])];
  const CollisionMesh& second = *meshes[static_cast<std::size_t>(mesh[3])];
  if (first.obstacle == second.obstacle) return false;
  const bool obstacle_second = second.obstacle;
  const int o_mesh = obstacle_second ? mesh[3] : mesh[0];
  const MeshTopology& topology = m_candidates.topology(o_mesh);
  if (!topology.closed) return false;
  const Eigen::Vector4d& w = impact.w;
  double start = 0.0;
  for (std::size_t k = 0; k < 4; ++k)
    start += w[static_cast<Eigen::Index>(k)] * impact.normal.dot(x0[k]);
  if (std::abs(start) >= offset) return false;
  // The cloth's closest point at the start, inside a piece of the obstacle?
  const Vec3 cloth = obstacle_second
                         ? Vec3(edge_edge ? Vec3(w[0] * x0[0] + w[1] * x0[1]) : x0[0])
                         : Vec3(edge_edge ? Vec3(-w[2] * x0[2] - w[3] * x0[3])
                                          : Vec3(-w[1] * x0[1] - w[2] * x0[2] - w[3] * x0[3]));
  const auto m = static_cast<std::size_t>(o_mesh);
  if (m_pieces_ready[m] == 0) {
    m_pieces[m].update(meshes[m]->x0, meshes[m]->faces, topology);
    m_pieces_ready[m] = 1;
  }
  if (!m_pieces[m].inside_other(-1, cloth)) return false;
  const CollisionMesh& o = *meshes[m];
  Vec3 outward;
  if (edge_edge) {
    const int e = obstacle_second ? primitive[1] : primitive[0];
    // Its corners are the edge's listed ends, in order: u is the fraction from the first.
    outward = edge_outward(o, topology, e, obstacle_second ? -w[3] : w[1]);
  } else if (obstacle_second) {
    outward = face_outward(o, topology, primitive[1], Vec3(-w[1], -w[2], -w[3]));
  } else {
    outward = vertex_outward(o, topology, primitive[0]);
  }
  // The normal points from the second primitive toward the first.
  const double side = impact.normal.dot(outward);
  if (obstacle_second ? side >= 0.0 : side <= 0.0) return false;
  impact.normal = -impact.normal;
  return true;
}

int ImpactZoneSolver::find_root(int gid) {
  while (m_parent[static_cast<std::size_t>(gid)] != gid) {
    int& p = m_parent[static_cast<std::size_t>(gid)];
    p = m_parent[static_cast<std::size_t>(p)];  // path halving
    gid = p;
  }
  return gid;
}

int ImpactZoneSolver::find_impacts(const std::vector<CollisionMesh*>& meshes,
                                   const ImpactZoneOptions& options, bool moved_only) {
  m_view.assign(meshes.begin(), meshes.end());
  // After a round, a pair none of whose vertices the round moved has the motion (and the
  // masses) it had in that round's test: no impact then (or one whose zone moved its
  // vertices), none now. The search skips such pairs; the impacts found, and their order,
  // are those of a search over all pairs.
  if (moved_only) {
    m_candidates.update_moved(m_view, options.ccd_tolerance, m_moved);
  } else {
    m_candidates.update(m_view, true, options.ccd_tolerance);
  }
  const std::size_t before = m_impacts.size();

  // Cloth skimming a flat part of an obstacle within the CCD tolerance of its plane meets it at
  // an angle to the start gap (taken with the hit's weights): a vertex meeting a face part-way
  // through a slide gets the start gap's direction, nearly in the plane, and an edge meeting a
  // flat edge (between coplanar faces) the edges' common perpendicular, tilted with the cloth
  // edge. Both pushed a crumpled heap's bottom, pressed into a frictionless table's plane,
  // sideways (its velocity changed by 0.6–1.8 mm/s in 0.7 s), and a patch skimming a box's top
  // back along its slide. Met inside a face, or on a flat edge or vertex, by cloth that started
  // in front of that plane, the surface's normal there is the plane's (outward: counter-
  // clockwise faces). (Leaving the flat edges' impacts out instead left grab_pile with 49
  // intersecting pairs.)
  auto on_flat_surface = [&](bool edge_edge, const std::array<int, 4>& mesh,
                             const std::array<int, 2>& primitive, const Corners& c0,
                             Impact& impact) {
    // The obstacle's side: the face or edge q (second), or the edge p (first).
    const bool second = meshes[static_cast<std::size_t>(mesh[3])]->obstacle;
    if (!second && !(edge_edge && meshes[static_cast<std::size_t>(mesh[0])]->obstacle)) return;
    const int m = second ? mesh[3] : mesh[0];
    const CollisionMesh& o = *meshes[static_cast<std::size_t>(m)];
    const MeshTopology& topology = m_candidates.topology(m);
    int face = -1;
    if (edge_edge) {
      const int e = second ? primitive[1] : primitive[0];
      if (!flat_edge(o.x0, o.faces, topology, e)) return;
      face = topology.edge_faces[static_cast<std::size_t>(e)][0];
    } else {
      const Vec3 bary(-impact.w[1], -impact.w[2], -impact.w[3]);
      if (bary.minCoeff() <= 0.0 && !on_flat_feature(o.x0, o.faces, topology, primitive[1], bary))
        return;
      face = primitive[1];
    }
    // The face's normal at the impact (the obstacle is rigid), toward the cloth's side.
    Vec3 corner[3];
    for (int k = 0; k < 3; ++k) {
      const int v = o.faces(face, k);
      corner[k] = x0_of(o, v) + impact.t * (x1_of(o, v) - x0_of(o, v));
    }
    Vec3 n = (corner[1] - corner[0]).cross(corner[2] - corner[0]);
    if (!second) n = -n;  // the impact's normal points from q toward p
    if (n.squaredNorm() == 0.0 || coplanar(n, impact.normal)) return;
    Vec3 start = Vec3::Zero();  // p − q at x0, with the hit's weights
    for (std::size_t k = 0; k < 4; ++k) start += impact.w[static_cast<Eigen::Index>(k)] * c0[k];
    if (n.dot(start) < 0.0) return;  // came from behind the plane: the CCD's own normal
    impact.normal = n.normalized();
  };
  // Resolves corners, tests the pair unless every corner is fixed, records a hit. `primitive`:
  // the vertex and face, or the two edges.
  auto test = [&](bool edge_edge, const std::array<int, 4>& mesh, const std::array<int, 4>& vertex,
                  const std::array<int, 2>& primitive) {
    Impact impact;
    bool movable = false;
    Corners c0, c1;
    for (std::size_t k = 0; k < 4; ++k) {
      const CollisionMesh& m = *meshes[static_cast<std::size_t>(mesh[k])];
      impact.corner[k] = {mesh[k], vertex[k],
                          m_offset[static_cast<std::size_t>(mesh[k])] + vertex[k],
                          inverse_mass(m, vertex[k])};
      movable = movable || impact.corner[k].inv_mass > 0.0;
      c0[k] = x0_of(m, vertex[k]);
      c1[k] = x1_of(m, vertex[k]);
    }
    // Only fixed corners: if some are held by static friction only, an obstacle runs into a
    // stuck cloth vertex, and not passing through comes first: those vertices are let go.
    // Otherwise nothing can respond, so say so (once, on the first round).
    bool releasable = false;
    for (std::size_t k = 0; k < 4 && !movable; ++k) {
      const CollisionMesh& m = *meshes[static_cast<std::size_t>(mesh[k])];
      releasable = releasable || held_by_friction(m, vertex[k]);
    }
    if (!movable && !releasable && !m_count_fixed) return;
    const std::optional<CcdHit> hit = edge_edge ? edge_edge_ccd(c0, c1, options.ccd_tolerance)
                                                : vertex_face_ccd(c0, c1, options.ccd_tolerance);
    if (!hit) return;
    if (!movable && !releasable) {
      ++m_fixed_impacts;
      return;
    }
    if (!movable)
      for (std::size_t k = 0; k < 4; ++k) {
        CollisionMesh& m = *meshes[static_cast<std::size_t>(mesh[k])];
        if (!held_by_friction(m, vertex[k])) continue;
        m.frozen[static_cast<std::size_t>(vertex[k])] = 0;
        ++m_released;
        impact.corner[k].inv_mass = inverse_mass(m, vertex[k]);
      }
    impact.w = hit->w;
    impact.normal = hit->normal;
    impact.t = hit->t;
    on_flat_surface(edge_edge, mesh, primitive, c0, impact);
    if (orient_outward(meshes, edge_edge, mesh, primitive, c0, options.offset, impact)) {
      // Turned: the pair leaves the obstacle; once it ends outside, nothing is to be stopped.
      double end = 0.0;
      for (std::size_t k = 0; k < 4; ++k)
        end += hit->w[static_cast<Eigen::Index>(k)] * impact.normal.dot(c1[k]);
      if (end >= 10.0 * options.ccd_tolerance) return;
    }
    // Separation to enforce: the offset, but never more than the pair had at the start of the
    // step (movable corners at x0, fixed ones where they must end), so that the start state
    // satisfies every constraint and each zone's projection is feasible; at least a little more
    // than the CCD tolerance, so a resolved pair is not detected again.
    double start = 0.0;
    for (std::size_t k = 0; k < 4; ++k)
      start += hit->w[static_cast<Eigen::Index>(k)] *
               impact.normal.dot(impact.corner[k].inv_mass > 0.0 ? c0[k] : c1[k]);
    impact.target = std::min(options.offset, std::max(start, 10.0 * options.ccd_tolerance));
    // Violation a converged projection may leave: a fraction of the offset, but never so much
    // that the pair ends within the CCD tolerance.
    impact.slack = std::max(std::min(options.violation_tolerance * options.offset,
                                     0.5 * (impact.target - options.ccd_tolerance)),
                            options.violation_tolerance * impact.target);
    m_impacts.push_back(impact);
  };

  for (const VertexFacePair& p : m_candidates.vertex_face()) {
    const CollisionMesh& fm = *meshes[static_cast<std::size_t>(p.face_mesh)];
    test(false, {p.vertex_mesh, p.face_mesh, p.face_mesh, p.face_mesh},
         {p.vertex, fm.faces(p.face, 0), fm.faces(p.face, 1), fm.faces(p.face, 2)},
         {p.vertex, p.face});
  }
  for (const EdgeEdgePair& p : m_candidates.edge_edge()) {
    const auto& ea = m_candidates.topology(p.mesh_a).edges[static_cast<std::size_t>(p.edge_a)];
    const auto& eb = m_candidates.topology(p.mesh_b).edges[static_cast<std::size_t>(p.edge_b)];
    test(true, {p.mesh_a, p.mesh_a, p.mesh_b, p.mesh_b}, {ea[0], ea[1], eb[0], eb[1]},
         {p.edge_a, p.edge_b});
  }
  return static_cast<int>(m_impacts.size() - before);
}

std::pair<CollisionMesh*, int> ImpactZoneSolver::locate(const std::vector<CollisionMesh*>& meshes,
                                                        int gid) const {
  const auto it = std::upper_bound(m_offset.begin(), m_offset.end(), gid) - 1;
  return {meshes[static_cast<std::size_t>(it - m_offset.begin())], gid - *it};
}

bool ImpactZoneSolver::project(const std::vector<CollisionMesh*>& meshes,
                               const std::vector<int>& impacts, const std::vector<int>& members,
                               const ImpactZoneOptions& options) {
  // Gauss–Seidel on the dual of min Σ m‖x − x̂‖²/2 s.t. c_j(x) = n·Σ w x − target_j ≥ 0, λ ≥ 0;
  // converged when no constraint is violated by more than its slack.
  m_zone_x1.clear();
  for (const int g : members) {
    const auto [m, v] = locate(meshes, g);
    m_zone_x1.push_back(x1_of(*m, v));
  }
  if (gauss_seidel(meshes, impacts, options)) return true;
  // Not converged (an infeasible zone's dual grows without bound and its x1 with it, to
  // metres and then to NaN): the fallback starts from the zone's motion as it came.
  for (std::size_t k = 0; k < members.size(); ++k) {
    const auto [m, v] = locate(meshes, members[k]);
    m->x1.row(v) = m_zone_x1[k].transpose();
  }
  return false;
}

bool ImpactZoneSolver::gauss_seidel(const std::vector<CollisionMesh*>& meshes,
                                    const std::vector<int>& impacts,
                                    const ImpactZoneOptions& options) {
  for (const int i : impacts) m_impacts[static_cast<std::size_t>(i)].lambda = 0.0;
  for (int sweep = 0; sweep < options.max_sweeps; ++sweep) {
    double worst = 0.0;
    for (const int i : impacts) {
      Impact& im = m_impacts[static_cast<std::size_t>(i)];
      double c = -im.target, k_eff = 0.0;
      for (std::size_t k = 0; k < 4; ++k) {
        const Corner& cr = im.corner[k];
        const double w = im.w[static_cast<Eigen::Index>(k)];
        c += w * im.normal.dot(x1_of(*meshes[static_cast<std::size_t>(cr.mesh)], cr.vertex));
        k_eff += w * w * cr.inv_mass;
      }
      worst = std::max(worst, -c / im.slack);
      if (k_eff == 0.0) continue;
      const double dl = std::max(-im.lambda, -c / k_eff);
      if (dl == 0.0) continue;
      im.lambda += dl;
      for (std::size_t k = 0; k < 4; ++k) {
        const Corner& cr = im.corner[k];
        if (cr.inv_mass == 0.0) continue;
        meshes[static_cast<std::size_t>(cr.mesh)]->x1.row(cr.vertex) +=
            (cr.inv_mass * im.w[static_cast<Eigen::Index>(k)] * dl * im.normal).transpose();
      }
    }
    if (worst <= 1.0) return true;
    if (!std::isfinite(worst)) return false;  // diverged
  }
  return false;
}

void ImpactZoneSolver::move_rigidly(const std::vector<CollisionMesh*>& meshes,
                                    const std::vector<int>& members) {
  // Mass-weighted centre, linear and angular momentum of the zone's motion over the step.
  const auto locate = [&](int gid) { return this->locate(meshes, gid); };
  double total = 0.0;
  Vec3 c0 = Vec3::Zero(), d = Vec3::Zero();
  for (const int g : members) {
    const auto [m, v] = locate(g);
    const double mass = m->mass[v];
    total += mass;
    c0 += mass * x0_of(*m, v);
    d += mass * (x1_of(*m, v) - x0_of(*m, v));
  }
  c0 /= total;
  d /= total;
  Vec3 l = Vec3::Zero();
  Mat3 inertia = Mat3::Zero();
  for (const int g : members) {
    const auto [m, v] = locate(g);
    const double mass = m->mass[v];
    const Vec3 r = x0_of(*m, v) - c0;
    l += mass * r.cross(x1_of(*m, v) - x0_of(*m, v) - d);
    inertia += mass * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
  }
  // ω = I⁺ L (pseudo-inverse: a single vertex or a line of vertices has a singular I).
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(inertia);
  const double cutoff = 1e-12 * std::max(eig.eigenvalues().maxCoeff(), 1e-300);
  Vec3 inv = Vec3::Zero();
  for (int k = 0; k < 3; ++k)
    if (eig.eigenvalues()[k] > cutoff) inv[k] = 1.0 / eig.eigenvalues()[k];
  const Vec3 omega = eig.eigenvectors() * inv.asDiagonal() * eig.eigenvectors().transpose() * l;
  const double angle = omega.norm();
  const Mat3 rotation =
      angle > 0.0 ? Mat3(Eigen::AngleAxisd(angle, omega / angle)) : Mat3(Mat3::Identity());
  for (const int g : members) {
    const auto [m, v] = locate(g);
    m->x1.row(v) = (c0 + d + rotation * (x0_of(*m, v) - c0)).transpose();
  }
}

void ImpactZoneSolver::release_held_corners(const std::vector<CollisionMesh*>& meshes,
                                            const std::vector<int>& impacts,
                                            std::vector<int>& members) {
  if (members.empty()) return;
  const int root = find_root(members.front());
  for (const int i : impacts)
    for (Corner& c : m_impacts[static_cast<std::size_t>(i)].corner) {
      CollisionMesh& m = *meshes[static_cast<std::size_t>(c.mesh)];
      if (c.inv_mass > 0.0 || !held_by_friction(m, c.vertex)) continue;
      m.frozen[static_cast<std::size_t>(c.vertex)] = 0;
      ++m_released;
      c.inv_mass = inverse_mass(m, c.vertex);
      m_parent[static_cast<std::size_t>(find_root(c.gid))] = root;
      members.push_back(c.gid);
    }
}

void ImpactZoneSolver::stay_at_start(const std::vector<CollisionMesh*>& meshes,
                                     const std::vector<int>& members) {
  for (const int g : members) {
    const auto [m, v] = locate(meshes, g);
    m->x1.row(v) = m->x0.row(v);
  }
}

ImpactZoneReport ImpactZoneSolver::resolve(const std::vector<CollisionMesh*>& meshes,
                                           const ImpactZoneOptions& options) {
  ImpactZoneReport report;
  // Global vertex ids, singleton zones, every vertex starting at level 0.
  m_offset.assign(meshes.size(), 0);
  int total = 0;
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    demand_valid(*meshes[m]);
    m_offset[m] = total;
    total += static_cast<int>(meshes[m]->x0.rows());
  }
  m_parent.resize(static_cast<std::size_t>(total));
  for (int g = 0; g < total; ++g) m_parent[static_cast<std::size_t>(g)] = g;
  m_level.assign(static_cast<std::size_t>(total), 0);
  m_impacts.clear();
  m_released = 0;
  m_pieces.resize(meshes.size());
  m_pieces_ready.assign(meshes.size(), 0);
  bool fixed_collisions = false;

  for (int iter = 0;; ++iter) {
    const std::size_t first_new = m_impacts.size();
    m_count_fixed = iter == 0;
    m_fixed_impacts = 0;
    const int found = find_impacts(meshes, options, iter > 0);
    if (m_fixed_impacts > 0) {
      fixed_collisions = true;
      report.warnings.push_back("impact zones: " + std::to_string(m_fixed_impacts) +
                                " impacts between fixed vertices and obstacles cannot be resolved");
    }
    if (found == 0) {
      report.converged = !fixed_collisions;
      report.iterations = iter;
      break;
    }
    if (iter == options.max_iterations) {
      report.iterations = iter;
      report.warnings.push_back("impact zones: " + std::to_string(found) +
                                " impacts unresolved after " + std::to_string(iter) +
                                " iterations");
      m_impacts.resize(first_new);
      break;
    }
    // Merge the new impacts' movable vertices into zones.
    for (std::size_t i = first_new; i < m_impacts.size(); ++i) {
      int root = -1;
      for (const Corner& c : m_impacts[i].corner) {
        if (c.inv_mass == 0.0) continue;
        const int r = find_root(c.gid);
        if (root < 0)
          root = r;
        else if (r != root)
          m_parent[static_cast<std::size_t>(r)] = root;
      }
    }
    // Group every impact by zone; respond in each zone that got a new impact.
    m_moved.resize(meshes.size());
    for (std::size_t m = 0; m < meshes.size(); ++m)
      m_moved[m].assign(static_cast<std::size_t>(meshes[m]->x0.rows()), 0);
    m_by_root.clear();
    for (std::size_t i = 0; i < m_impacts.size(); ++i) {
      for (const Corner& c : m_impacts[i].corner) {
        if (c.inv_mass == 0.0) continue;
        m_by_root.emplace_back(find_root(c.gid), static_cast<int>(i));
        break;
      }
    }
    std::sort(m_by_root.begin(), m_by_root.end());
    report.zones = 0;
    for (std::size_t b = 0; b < m_by_root.size();) {
      std::size_t e = b;
      bool active = false;
      m_zone_impacts.clear();
      m_zone_members.clear();
      for (; e < m_by_root.size() && m_by_root[e].first == m_by_root[b].first; ++e) {
        const int i = m_by_root[e].second;
        active = active || static_cast<std::size_t>(i) >= first_new;
        m_zone_impacts.push_back(i);
        for (const Corner& c : m_impacts[static_cast<std::size_t>(i)].corner)
          if (c.inv_mass > 0.0) m_zone_members.push_back(c.gid);
      }
      b = e;
      ++report.zones;
      if (!active) continue;
      std::sort(m_zone_members.begin(), m_zone_members.end());
      m_zone_members.erase(std::unique(m_zone_members.begin(), m_zone_members.end()),
                           m_zone_members.end());
      std::uint8_t had = 0;
      for (const int g : m_zone_members) had = std::max(had, m_level[static_cast<std::size_t>(g)]);
      // Late rounds force the robust fallbacks.
      std::uint8_t level = had;
      if (2 * iter >= options.max_iterations) level = std::max<std::uint8_t>(level, 1);
      if (4 * iter >= 3 * options.max_iterations) level = 2;

      const std::string size = std::to_string(m_zone_members.size());
      std::uint8_t next = 0;
      if (level == 0) {
        // Inelastic projection; rigid motion when it does not converge.
        if (!project(meshes, m_zone_impacts, m_zone_members, options)) {
          move_rigidly(meshes, m_zone_members);
          next = 1;
          report.warnings.push_back("impact zones: projection of a zone of " + size +
                                    " vertices did not converge; zone moved rigidly");
        }
      } else if (level == 1 && had == 0) {
        move_rigidly(meshes, m_zone_members);
        next = 1;
        report.warnings.push_back("impact zones: zone of " + size +
                                  " vertices still colliding after " + std::to_string(iter) +
                                  " rounds; zone moved rigidly");
      } else {
        // A rigid zone hit again (by neighbours or obstacles) keeps its start positions. Cloth
        // vertices held by static friction that run into it are let go and stay with it: held,
        // they would go on through a zone that no longer moves (a stack's middle layer crossed
        // the layer beside it when the hand's pinch re-opened).
        release_held_corners(meshes, m_zone_impacts, m_zone_members);
        stay_at_start(meshes, m_zone_members);
        next = 2;
        report.warnings.push_back("impact zones: zone of " + size +
                                  " vertices kept at its start-of-step positions");
      }
      for (const int g : m_zone_members) {
        const auto m = static_cast<std::size_t>(
            std::upper_bound(m_offset.begin(), m_offset.end(), g) - m_offset.begin() - 1);
        m_moved[m][static_cast<std::size_t>(g - m_offset[m])] = 1;
      }
      if (next > 0) {
        ++report.rigid_zones;
        for (const int g : m_zone_members) m_level[static_cast<std::size_t>(g)] = next;
      }
    }
    report.impacts = static_cast<int>(m_impacts.size());
  }
  report.impacts = static_cast<int>(m_impacts.size());
  report.released = m_released;
  merge_repeats(report.warnings);
  return report;
}

}  // namespace dexcloth::collision
