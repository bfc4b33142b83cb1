#include "cloth/collision/collision_candidates.hpp"

#include <algorithm>
#include <cmath>

#include "core/assert.hpp"

namespace dexcloth::collision {

namespace {

bool overlap(const PrimitiveBox& a, const PrimitiveBox& b) {
  return a.lo[0] <= b.hi[0] && b.lo[0] <= a.hi[0] && a.lo[1] <= b.hi[1] && b.lo[1] <= a.hi[1] &&
         a.lo[2] <= b.hi[2] && b.lo[2] <= a.hi[2];
}

PrimitiveBox merge(const PrimitiveBox& a, const PrimitiveBox& b) {
  PrimitiveBox m;
  for (int d = 0; d < 3; ++d) {
    m.lo[d] = std::min(a.lo[d], b.lo[d]);
    m.hi[d] = std::max(a.hi[d], b.hi[d]);
  }
  return m;
}

// The bits of a RestNeighbours mask that primitive_pairs tests for faces owning `va`, `ea`
// (first face) and `vb`, `eb` (second face) of their corners and edges: face pairs whose every
// such pair is a rest neighbour make no candidate.
std::uint16_t owned_bits(std::uint8_t va, std::uint8_t ea, std::uint8_t vb, std::uint8_t eb) {
  auto bits = static_cast<std::uint16_t>((va & 0x7u) | ((vb & 0x7u) << 3));
  for (int i = 0; i < 3; ++i)
    if (ea & (1u << i))
      bits |= static_cast<std::uint16_t>((eb & 0x7u) << RestNeighbours::edge_edge_bit(i, 0));
  return bits;
}

// The mean length of a cloth's edges in its rest plane [m].
double mean_edge(const std::vector<double>& uv, const MeshTopology& topology) {
  double sum = 0.0;
  for (const std::array<int, 2>& e : topology.edges) {
    const auto a = static_cast<std::size_t>(e[0]), b = static_cast<std::size_t>(e[1]);
    sum += std::hypot(uv[2 * a] - uv[2 * b], uv[2 * a + 1] - uv[2 * b + 1]);
  }
  return topology.edges.empty() ? 0.0 : sum / static_cast<double>(topology.edges.size());
}

bool shares_vertex(const std::array<int, 2>& e, const std::array<int, 2>& g) {
  return e[0] == g[0] || e[0] == g[1] || e[1] == g[0] || e[1] == g[1];
}

}  // namespace

void CollisionCandidates::update(const std::vector<const CollisionMesh*>& meshes, bool swept,
                                 double margin) {
  update(meshes, swept, margin, margin);
}

void CollisionCandidates::update(const std::vector<const CollisionMesh*>& meshes, bool swept,
                                 double margin, double obstacle_margin) {
  DEXCLOTH_DEMAND(margin >= 0.0 && obstacle_margin >= margin);
  const std::size_t nm = meshes.size();
  const auto inflation = [&](std::size_t m) {
    return searched_beyond_thickness(*meshes[m]) ? obstacle_margin : margin;
  };
  if (m_topology.size() != nm) {
    m_topology.clear();
    m_topology.resize(nm);
    m_bvh.assign(nm, Bvh());
  }
  // Build on first use or after a change of size; refit otherwise.
  for (std::size_t m = 0; m < nm; ++m) {
    const CollisionMesh& mesh = *meshes[m];
    const Points& x1 = swept ? mesh.x1 : mesh.x0;
    MeshTopology& topo = m_topology[m];
    if (topo.num_vertices != mesh.x0.rows() ||
        topo.face_edges.size() != static_cast<std::size_t>(mesh.faces.rows()) ||
        m_bvh[m].num_faces() != mesh.faces.rows() || (m_bvh[m].empty() && mesh.faces.rows() > 0)) {
      topo = build_topology(mesh.faces, static_cast<int>(mesh.x0.rows()));
      m_bvh[m].build(mesh.faces, mesh.x0, x1, inflation(m));
      if (m_rest.size() > m) m_rest[m] = RestNeighbours();
      if (m_unfolded.size() > m) m_unfolded[m] = UnfoldedSubtrees();
      if (m_windows.size() > m) m_windows[m] = {};
    } else {
      m_bvh[m].refit(mesh.faces, mesh.x0, x1, inflation(m));
    }
  }
  // Rest neighbours of each self-colliding cloth, listed once per topology and distance.
  m_rest.resize(nm);
  for (std::size_t m = 0; m < nm; ++m) {
    const CollisionMesh& mesh = *meshes[m];
    if (m_rest_distance > 0.0 && m_rest[m].distance() != m_rest_distance && mesh.rest.rows() > 0 &&
        mesh.self_collision)
      m_rest[m].build(mesh.rest, mesh.faces, m_topology[m], m_rest_distance);
  }
  // Subtrees of each self-colliding cloth with a rest shape, and windows of its rest plane, that
  // hold no pair the search must find: no two primitives within 2·margin unless they share a
  // vertex (swept, over the motion) or are rest neighbours (proximity).
  m_unfolded.resize(nm);
  m_windows.resize(nm);
  m_mean_edge.resize(nm);
  m_skip.assign(nm, QuerySkip{});
  for (std::size_t m = 0; m < nm; ++m) {
    const CollisionMesh& mesh = *meshes[m];
    if (mesh.obstacle || !mesh.self_collision || mesh.rest.rows() == 0) continue;
    if (!swept && rest_neighbours(static_cast<int>(m)) == nullptr) continue;
    UnfoldedSubtrees& unfolded = m_unfolded[m];
    UnfoldedWindows& windows = m_windows[m][swept ? 1 : 0];
    if (!unfolded.built_for(m_bvh[m])) {
      unfolded.build(mesh.rest, mesh.faces, m_bvh[m]);
      m_mean_edge[m] = mean_edge(unfolded.rest_plane(), m_topology[m]);
    }
    if (m_kept_fits) {
      while (m_kept_fits->size() <= m)
        m_kept_fits->push_back(std::make_unique<UnfoldedSubtrees::KeptFits>());
      unfolded.keep_fits_in((*m_kept_fits)[m].get());
    }
    // The stride: the rest extent of two faces about to be in reach, so that most face pairs
    // the search finds fit in a window.
    const double stride = 2.0 * m_mean_edge[m] + 2.0 * margin;
    if (!windows.built_for(m_bvh[m].num_nodes(), stride))
      windows.build(unfolded.rest_plane(), mesh.faces, m_topology[m], unfolded.rest_boxes(),
                    stride);
    if (swept) {
      unfolded.update_swept(m_bvh[m], mesh.faces, m_topology[m], mesh.x0, mesh.x1, 2.0 * margin,
                            m_pool);
    } else {
      unfolded.update(m_bvh[m], mesh.x0, m_rest_distance, 2.0 * margin, m_pool);
    }
    m_skip[m] = QuerySkip{&unfolded.flags(), nullptr, nullptr, nullptr};
    if (unfolded.flags()[0] != 0) continue;  // the whole cloth is left out: no window is asked
    if (swept) {
      windows.update_swept(mesh.x0, mesh.x1, unfolded.separation(mesh.faces, m_topology[m]),
                           2.0 * margin, m_pool);
    } else {
      // Rest distances in the rest plane are short of the true ones by the flatness at each end.
      windows.update(mesh.x0, m_rest_distance - 2.0 * unfolded.flatness(), 2.0 * margin, m_pool);
    }
    m_skip[m].windows = &windows;
  }
  // Boxes of every vertex (x0, and x1 when swept, inflated by margin) and edge, once per update.
  m_vertex_boxes.resize(nm);
  m_edge_boxes.resize(nm);
  m_face_boxes.resize(nm);
  for (std::size_t m = 0; m < nm; ++m) primitive_boxes(*meshes[m], m, swept, inflation(m));
  collect_all(meshes, nullptr);
  m_swept_margin = swept && obstacle_margin == margin ? margin : -1.0;
}

void CollisionCandidates::update_moved(const std::vector<const CollisionMesh*>& meshes,
                                       double margin,
                                       const std::vector<std::vector<std::uint8_t>>& moved) {
  const std::size_t nm = meshes.size();
  bool same = m_swept_margin == margin && m_topology.size() == nm && moved.size() == nm;
  for (std::size_t m = 0; same && m < nm; ++m) {
    const CollisionMesh& mesh = *meshes[m];
    same = m_topology[m].num_vertices == mesh.x0.rows() &&
           m_topology[m].face_edges.size() == static_cast<std::size_t>(mesh.faces.rows()) &&
           m_bvh[m].num_faces() == mesh.faces.rows() &&
           (moved[m].empty() || moved[m].size() == static_cast<std::size_t>(mesh.x0.rows()));
  }
  if (!same) {
    update(meshes, true, margin);
    return;
  }
  // Only the meshes with a moved vertex changed: their trees and boxes again, and which of
  // their subtrees hold a face with a moved vertex.
  m_touched.resize(nm);
  std::vector<std::uint8_t> any(nm, 0);
  for (std::size_t m = 0; m < nm; ++m) {
    const CollisionMesh& mesh = *meshes[m];
    any[m] = std::any_of(moved[m].begin(), moved[m].end(), [](std::uint8_t f) { return f != 0; });
    if (any[m] == 0) {
      m_touched[m].assign(static_cast<std::size_t>(m_bvh[m].num_nodes()), 0);
      continue;
    }
    touched_subtrees(m_bvh[m], mesh.faces, moved[m], m_touched[m]);
    m_bvh[m].refit(mesh.faces, mesh.x0, mesh.x1, margin, m_touched[m]);
    primitive_boxes(mesh, m, true, margin, &moved[m]);
  }
  m_skip.assign(nm, QuerySkip{});
  collect_all(meshes, &any);
}

void CollisionCandidates::collect_all(const std::vector<const CollisionMesh*>& meshes,
                                      const std::vector<std::uint8_t>* moved_meshes) {
  m_vf.clear();
  m_ee.clear();
  for (std::size_t a = 0; a < meshes.size(); ++a) {
    for (std::size_t b = a; b < meshes.size(); ++b) {
      if (meshes[a]->obstacle && meshes[b]->obstacle) continue;
      if (a == b && !meshes[a]->self_collision) continue;
      if (moved_meshes != nullptr && (*moved_meshes)[a] == 0 && (*moved_meshes)[b] == 0) continue;
      collect(meshes, static_cast<int>(a), static_cast<int>(b), moved_meshes != nullptr);
    }
  }
}

void CollisionCandidates::primitive_boxes(const CollisionMesh& mesh, std::size_t m, bool swept,
                                          double inflate, const std::vector<std::uint8_t>* moved) {
  const auto changed = [moved](int v) {
    return moved == nullptr || (*moved)[static_cast<std::size_t>(v)] != 0;
  };
  const Points& x1 = swept ? mesh.x1 : mesh.x0;
  std::vector<PrimitiveBox>& vb = m_vertex_boxes[m];
  vb.resize(static_cast<std::size_t>(mesh.x0.rows()));
  for (int v = 0; v < static_cast<int>(mesh.x0.rows()); ++v) {
    if (!changed(v)) continue;
    PrimitiveBox& b = vb[static_cast<std::size_t>(v)];
    for (int d = 0; d < 3; ++d) {
      b.lo[d] = std::min(mesh.x0(v, d), x1(v, d)) - inflate;
      b.hi[d] = std::max(mesh.x0(v, d), x1(v, d)) + inflate;
    }
  }
  const std::vector<std::array<int, 2>>& edges = m_topology[m].edges;
  std::vector<PrimitiveBox>& eb = m_edge_boxes[m];
  eb.resize(edges.size());
  for (std::size_t e = 0; e < edges.size(); ++e)
    if (changed(edges[e][0]) || changed(edges[e][1]))
      eb[e] = merge(vb[static_cast<std::size_t>(edges[e][0])],
                    vb[static_cast<std::size_t>(edges[e][1])]);
  std::vector<PrimitiveBox>& fb = m_face_boxes[m];
  fb.resize(static_cast<std::size_t>(mesh.faces.rows()));
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
    if (changed(mesh.faces(f, 0)) || changed(mesh.faces(f, 1)) || changed(mesh.faces(f, 2)))
      fb[static_cast<std::size_t>(f)] = merge(merge(vb[static_cast<std::size_t>(mesh.faces(f, 0))],
                                                    vb[static_cast<std::size_t>(mesh.faces(f, 1))]),
                                              vb[static_cast<std::size_t>(mesh.faces(f, 2))]);
}

void CollisionCandidates::share_fits(CollisionCandidates& other) {
  if (!m_kept_fits) m_kept_fits = other.m_kept_fits;
  if (!m_kept_fits)
    m_kept_fits = std::make_shared<std::vector<std::unique_ptr<UnfoldedSubtrees::KeptFits>>>();
  other.m_kept_fits = m_kept_fits;
}

void CollisionCandidates::set_rest_neighbour_distance(double distance) {
  DEXCLOTH_DEMAND(distance >= 0.0);
  m_rest_distance = distance;
}

const RestNeighbours* CollisionCandidates::rest_neighbours(int m) const {
  const RestNeighbours& r = m_rest[static_cast<std::size_t>(m)];
  return m_rest_distance > 0.0 && r.distance() == m_rest_distance ? &r : nullptr;
}

void CollisionCandidates::collect(const std::vector<const CollisionMesh*>& meshes, int ma, int mb,
                                  bool touched) {
  const Bvh& ta = m_bvh[static_cast<std::size_t>(ma)];
  const Bvh& tb = m_bvh[static_cast<std::size_t>(mb)];
  const bool self = ma == mb;
  // The query in pieces, each taken by the next free thread, which finds its overlapping faces
  // and makes their primitive pairs; the pieces' pairs are concatenated in the pieces' order
  // (the order of the whole query, whichever thread ran a piece). The pieces' work is far from
  // even (a sheet's self query is mostly within halves, little between them: handed out
  // round-robin, one of two threads did three quarters of pinch_move's).
  QuerySkip query_skip = self ? m_skip[static_cast<std::size_t>(ma)] : QuerySkip{};
  if (touched) {
    query_skip.touched_a = &m_touched[static_cast<std::size_t>(ma)];
    query_skip.touched_b = &m_touched[static_cast<std::size_t>(mb)];
  }
  const QuerySkip* skip = self || touched ? &query_skip : nullptr;
  WorkerPool* pool = split_query(ta, tb, self, m_pool, m_queries, skip);
  const std::size_t pieces = m_queries.size();
  if (m_piece_pairs.size() < pieces) {
    m_piece_pairs.resize(pieces);
    m_piece_vf.resize(pieces);
    m_piece_ee.resize(pieces);
  }
  for_each_index(pool, pieces, [&](std::size_t k) {
    m_piece_pairs[k].clear();
    run_query(ta, tb, m_queries[k], nullptr, m_piece_pairs[k], skip);
    m_piece_vf[k].clear();
    m_piece_ee[k].clear();
    primitive_pairs(meshes, ma, mb, m_piece_pairs[k], m_piece_vf[k], m_piece_ee[k]);
  });
  for (std::size_t k = 0; k < pieces; ++k) {
    m_vf.insert(m_vf.end(), m_piece_vf[k].begin(), m_piece_vf[k].end());
    m_ee.insert(m_ee.end(), m_piece_ee[k].begin(), m_piece_ee[k].end());
  }
}

void CollisionCandidates::primitive_pairs(const std::vector<const CollisionMesh*>& meshes, int ma,
                                          int mb, const std::vector<FacePair>& face_pairs,
                                          std::vector<VertexFacePair>& vf,
                                          std::vector<EdgeEdgePair>& ee) const {
  const CollisionMesh& A = *meshes[static_cast<std::size_t>(ma)];
  const CollisionMesh& B = *meshes[static_cast<std::size_t>(mb)];
  const MeshTopology& ta = m_topology[static_cast<std::size_t>(ma)];
  const MeshTopology& tb = m_topology[static_cast<std::size_t>(mb)];
  const bool self = ma == mb;
  const std::vector<PrimitiveBox>& vba = m_vertex_boxes[static_cast<std::size_t>(ma)];
  const std::vector<PrimitiveBox>& vbb = m_vertex_boxes[static_cast<std::size_t>(mb)];
  const std::vector<PrimitiveBox>& eba = m_edge_boxes[static_cast<std::size_t>(ma)];
  const std::vector<PrimitiveBox>& ebb = m_edge_boxes[static_cast<std::size_t>(mb)];

  const std::vector<PrimitiveBox>& fba = m_face_boxes[static_cast<std::size_t>(ma)];
  const std::vector<PrimitiveBox>& fbb = m_face_boxes[static_cast<std::size_t>(mb)];
  // Pairs of rest neighbours are never contacts (find_proximities): left out here, whole face
  // pairs of them at once.
  const RestNeighbours* rest = self ? rest_neighbours(ma) : nullptr;

  // Owned vertex of one face against the other face, unless it is one of that face's corners
  // or a rest neighbour of it (bit `rest_bit` + corner of the face pair's mask).
  auto vertex_face = [&](const CollisionMesh& vm, const MeshTopology& vt,
                         const std::vector<PrimitiveBox>& vb, int vmi, int fv,
                         const CollisionMesh& fm, const std::vector<PrimitiveBox>& fb, int fmi,
                         int ff, std::uint16_t mask, int rest_bit) {
    const std::uint8_t owned = vt.owned_vertices[static_cast<std::size_t>(fv)];
    if (owned == 0) return;
    const std::array<int, 3> face{fm.faces(ff, 0), fm.faces(ff, 1), fm.faces(ff, 2)};
    const PrimitiveBox& fbox = fb[static_cast<std::size_t>(ff)];
    for (int k = 0; k < 3; ++k) {
      if ((owned & (1u << k)) == 0) continue;
      const int v = vm.faces(fv, k);
      if (self && (v == face[0] || v == face[1] || v == face[2])) continue;
      if (mask & (1u << (rest_bit + k))) continue;
      if (!overlap(vb[static_cast<std::size_t>(v)], fbox)) continue;
      vf.push_back({vmi, v, fmi, ff});
    }
  };

  for (const FacePair& fp : face_pairs) {
    const std::uint16_t mask = rest ? rest->mask(fp.a, fp.b) : std::uint16_t{0};
    if (mask != 0) {
      const std::uint16_t owned = owned_bits(ta.owned_vertices[static_cast<std::size_t>(fp.a)],
                                             ta.owned_edges[static_cast<std::size_t>(fp.a)],
                                             tb.owned_vertices[static_cast<std::size_t>(fp.b)],
                                             tb.owned_edges[static_cast<std::size_t>(fp.b)]);
      if ((mask & owned) == owned) continue;
    }
    vertex_face(A, ta, vba, ma, fp.a, B, fbb, mb, fp.b, mask,
                RestNeighbours::vertex_face_bit(false, 0));
    vertex_face(B, tb, vbb, mb, fp.b, A, fba, ma, fp.a, mask,
                RestNeighbours::vertex_face_bit(true, 0));
    // Owned edges of one face against owned edges of the other.
    const std::uint8_t oa = ta.owned_edges[static_cast<std::size_t>(fp.a)];
    const std::uint8_t ob = tb.owned_edges[static_cast<std::size_t>(fp.b)];
    if (oa == 0 || ob == 0) continue;
    for (int i = 0; i < 3; ++i) {
      if ((oa & (1u << i)) == 0) continue;
      const int ea = ta.face_edges[static_cast<std::size_t>(fp.a)][static_cast<std::size_t>(i)];
      const std::array<int, 2>& va = ta.edges[static_cast<std::size_t>(ea)];
      const PrimitiveBox& abox = eba[static_cast<std::size_t>(ea)];
      for (int j = 0; j < 3; ++j) {
        if ((ob & (1u << j)) == 0) continue;
        const int eb = tb.face_edges[static_cast<std::size_t>(fp.b)][static_cast<std::size_t>(j)];
        if (self && shares_vertex(va, tb.edges[static_cast<std::size_t>(eb)])) continue;
        if (mask & (1u << RestNeighbours::edge_edge_bit(i, j))) continue;
        if (!overlap(abox, ebb[static_cast<std::size_t>(eb)])) continue;
        ee.push_back({ma, ea, mb, eb});
      }
    }
  }
}

}  // namespace dexcloth::collision
