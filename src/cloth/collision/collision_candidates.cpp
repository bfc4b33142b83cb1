#include "cloth/collision/collision_candidates.hpp"

#include <algorithm>

namespace dexcloth::collision {

namespace {

// Box of a set of vertices over x0 (and x1 when swept), inflated by margin.
struct Box {
  Vec3 lo, hi;
};

template <int N>
Box vertex_box(const CollisionMesh& m, const std::array<int, N>& v, bool swept, double margin) {
  Box b{m.x0.row(v[0]).transpose(), m.x0.row(v[0]).transpose()};
  for (int k = 0; k < N; ++k) {
    b.lo = b.lo.cwiseMin(m.x0.row(v[static_cast<std::size_t>(k)]).transpose());
    b.hi = b.hi.cwiseMax(m.x0.row(v[static_cast<std::size_t>(k)]).transpose());
    if (swept) {
      b.lo = b.lo.cwiseMin(m.x1.row(v[static_cast<std::size_t>(k)]).transpose());
      b.hi = b.hi.cwiseMax(m.x1.row(v[static_cast<std::size_t>(k)]).transpose());
    }
  }
  b.lo.array() -= margin;
  b.hi.array() += margin;
  return b;
}

bool overlap(const Box& a, const Box& b) {
  return (a.lo.array() <= b.hi.array()).all() && (b.lo.array() <= a.hi.array()).all();
}

bool shares_vertex(const std::array<int, 2>& e, const std::array<int, 2>& g) {
  return e[0] == g[0] || e[0] == g[1] || e[1] == g[0] || e[1] == g[1];
}

}  // namespace

void CollisionCandidates::update(const std::vector<const CollisionMesh*>& meshes, bool swept,
                                 double margin) {
  const std::size_t nm = meshes.size();
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
      m_bvh[m].build(mesh.faces, mesh.x0, x1, margin);
    } else {
      m_bvh[m].refit(mesh.faces, mesh.x0, x1, margin);
    }
  }
  // Primitive pairs of every relevant mesh pair.
  m_vf.clear();
  m_ee.clear();
  for (std::size_t a = 0; a < nm; ++a) {
    for (std::size_t b = a; b < nm; ++b) {
      if (meshes[a]->obstacle && meshes[b]->obstacle) continue;
      collect(meshes, static_cast<int>(a), static_cast<int>(b), swept, margin);
    }
  }
}

void CollisionCandidates::collect(const std::vector<const CollisionMesh*>& meshes, int ma, int mb,
                                  bool swept, double margin) {
  const CollisionMesh& A = *meshes[static_cast<std::size_t>(ma)];
  const CollisionMesh& B = *meshes[static_cast<std::size_t>(mb)];
  const MeshTopology& ta = m_topology[static_cast<std::size_t>(ma)];
  const MeshTopology& tb = m_topology[static_cast<std::size_t>(mb)];
  const bool self = ma == mb;
  m_face_pairs.clear();
  if (self) self_overlapping_faces(m_bvh[static_cast<std::size_t>(ma)], A.faces, false, m_face_pairs);
  else overlapping_faces(m_bvh[static_cast<std::size_t>(ma)], m_bvh[static_cast<std::size_t>(mb)], m_face_pairs);

  // Owned vertex of one face against the other face, unless it is one of that face's corners.
  auto vertex_face = [&](const CollisionMesh& vm, const MeshTopology& vt, int vmi, int fv,
                         const CollisionMesh& fm, int fmi, int ff) {
    const std::uint8_t owned = vt.owned_vertices[static_cast<std::size_t>(fv)];
    if (owned == 0) return;
    const std::array<int, 3> face{fm.faces(ff, 0), fm.faces(ff, 1), fm.faces(ff, 2)};
    const Box fbox = vertex_box<3>(fm, face, swept, margin);
    for (int k = 0; k < 3; ++k) {
      if ((owned & (1u << k)) == 0) continue;
      const int v = vm.faces(fv, k);
      if (self && (v == face[0] || v == face[1] || v == face[2])) continue;
      if (!overlap(vertex_box<1>(vm, {v}, swept, margin), fbox)) continue;
      m_vf.push_back({vmi, v, fmi, ff});
    }
  };

  for (const FacePair& fp : m_face_pairs) {
    vertex_face(A, ta, ma, fp.a, B, mb, fp.b);
    vertex_face(B, tb, mb, fp.b, A, ma, fp.a);
    // Owned edges of one face against owned edges of the other.
    const std::uint8_t oa = ta.owned_edges[static_cast<std::size_t>(fp.a)];
    const std::uint8_t ob = tb.owned_edges[static_cast<std::size_t>(fp.b)];
    if (oa == 0 || ob == 0) continue;
    for (int i = 0; i < 3; ++i) {
      if ((oa & (1u << i)) == 0) continue;
      const int ea = ta.face_edges[static_cast<std::size_t>(fp.a)][static_cast<std::size_t>(i)];
      const std::array<int, 2>& va = ta.edges[static_cast<std::size_t>(ea)];
      const Box abox = vertex_box<2>(A, va, swept, margin);
      for (int j = 0; j < 3; ++j) {
        if ((ob & (1u << j)) == 0) continue;
        const int eb = tb.face_edges[static_cast<std::size_t>(fp.b)][static_cast<std::size_t>(j)];
        const std::array<int, 2>& vb = tb.edges[static_cast<std::size_t>(eb)];
        if (self && shares_vertex(va, vb)) continue;
        if (!overlap(abox, vertex_box<2>(B, vb, swept, margin))) continue;
        m_ee.push_back({ma, ea, mb, eb});
      }
    }
  }
}

}  // namespace dexcloth::collision
