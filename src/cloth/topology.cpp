#include "cloth/topology.hpp"

#include <algorithm>
#include <tuple>

namespace dexcloth::cloth {

Topology build_topology(const Triangles& faces) {
  // One record per face corner edge: (min, max, face, corner), sorted to group equal edges.
  struct HalfEdge {
    int lo, hi, face, corner;
  };
  std::vector<HalfEdge> half;
  half.reserve(static_cast<std::size_t>(faces.rows()) * 3);
  for (int f = 0; f < faces.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int a = faces(f, c), b = faces(f, (c + 1) % 3);
      half.push_back({std::min(a, b), std::max(a, b), f, c});
    }
  }
  std::sort(half.begin(), half.end(), [](const HalfEdge& p, const HalfEdge& q) {
    return std::tie(p.lo, p.hi, p.face, p.corner) < std::tie(q.lo, q.hi, q.face, q.corner);
  });

  Topology topo;
  for (std::size_t i = 0; i < half.size();) {
    std::size_t j = i;
    while (j < half.size() && half[j].lo == half[i].lo && half[j].hi == half[i].hi) ++j;
    topo.edges.push_back({half[i].lo, half[i].hi});
    // Exactly two faces: a hinge, edge oriented as in the first face.
    if (j - i == 2) {
      const HalfEdge& p = half[i];
      const HalfEdge& q = half[i + 1];
      Hinge h;
      h.v = {faces(p.face, p.corner), faces(p.face, (p.corner + 1) % 3),
             faces(p.face, (p.corner + 2) % 3), faces(q.face, (q.corner + 2) % 3)};
      h.faces = {p.face, q.face};
      topo.hinges.push_back(h);
    }
    i = j;
  }
  return topo;
}

}  // namespace dexcloth::cloth
