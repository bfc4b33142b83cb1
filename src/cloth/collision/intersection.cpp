#include "cloth/collision/intersection.hpp"

#include <algorithm>
#include <atomic>

#include "cloth/collision/bvh.hpp"
#include "cloth/collision/predicates.hpp"

namespace dexcloth::collision {

namespace {

// Closed 2-D segments (p, q) and (r, s) share a point.
bool segments_intersect_2d(const Vec2& p, const Vec2& q, const Vec2& r, const Vec2& s) {
  const int o1 = orient2d(p, q, r), o2 = orient2d(p, q, s);
  const int o3 = orient2d(r, s, p), o4 = orient2d(r, s, q);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  // Collinear touching: an endpoint on the other segment (coordinate comparisons are exact).
  auto on_segment = [](const Vec2& a, const Vec2& b, const Vec2& x) {
    return std::min(a.x(), b.x()) <= x.x() && x.x() <= std::max(a.x(), b.x()) &&
           std::min(a.y(), b.y()) <= x.y() && x.y() <= std::max(a.y(), b.y());
  };
  if (o1 == 0 && on_segment(p, q, r)) return true;
  if (o2 == 0 && on_segment(p, q, s)) return true;
  if (o3 == 0 && on_segment(r, s, p)) return true;
  if (o4 == 0 && on_segment(r, s, q)) return true;
  return false;
}

// Closed 2-D point-in-triangle for a triangle of orientation `o` (±1).
bool point_in_triangle_2d(const Vec2& x, const Vec2& a, const Vec2& b, const Vec2& c, int o) {
  return orient2d(a, b, x) * o >= 0 && orient2d(b, c, x) * o >= 0 && orient2d(c, a, x) * o >= 0;
}

}  // namespace

bool segment_intersects_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                                 const Vec3& c) {
  const int op = orient3d(a, b, c, p), oq = orient3d(a, b, c, q);
  if (op != 0 && op == oq) return false;
  if (op == 0 && oq == 0) {
    // Segment in the triangle's plane: drop the normal's dominant axis, test in 2-D.
    const Vec3 n = (b - a).cross(c - a);
    if (n.squaredNorm() == 0.0) return false;
    int axis = 0;
    n.cwiseAbs().maxCoeff(&axis);
    const int i = (axis + 1) % 3, j = (axis + 2) % 3;
    const Vec2 p2(p[i], p[j]), q2(q[i], q[j]), a2(a[i], a[j]), b2(b[i], b[j]), c2(c[i], c[j]);
    const int o = orient2d(a2, b2, c2);
    if (o == 0) return false;
    if (point_in_triangle_2d(p2, a2, b2, c2, o) || point_in_triangle_2d(q2, a2, b2, c2, o))
      return true;
    return segments_intersect_2d(p2, q2, a2, b2) || segments_intersect_2d(p2, q2, b2, c2) ||
           segments_intersect_2d(p2, q2, c2, a2);
  }
  // The segment meets the plane at one point: inside iff the line sees the edges consistently.
  const int s1 = orient3d(p, q, a, b), s2 = orient3d(p, q, b, c), s3 = orient3d(p, q, c, a);
  const bool any_pos = s1 > 0 || s2 > 0 || s3 > 0;
  const bool any_neg = s1 < 0 || s2 < 0 || s3 < 0;
  if (!any_pos && !any_neg) return false;  // zero-area triangle
  return !(any_pos && any_neg);
}

bool triangles_intersect(const Vec3& a0, const Vec3& a1, const Vec3& a2, const Vec3& b0,
                         const Vec3& b1, const Vec3& b2) {
  // Separated by either triangle's plane.
  const int ob0 = orient3d(a0, a1, a2, b0), ob1 = orient3d(a0, a1, a2, b1),
            ob2 = orient3d(a0, a1, a2, b2);
  if (ob0 != 0 && ob0 == ob1 && ob1 == ob2) return false;
  const int oa0 = orient3d(b0, b1, b2, a0), oa1 = orient3d(b0, b1, b2, a1),
            oa2 = orient3d(b0, b1, b2, a2);
  if (oa0 != 0 && oa0 == oa1 && oa1 == oa2) return false;
  // Two closed triangles meet iff an edge of one meets the other (the ends of the intersection
  // set lie on boundaries; in the coplanar case containment is caught by the edges inside).
  return segment_intersects_triangle(a0, a1, b0, b1, b2) ||
         segment_intersects_triangle(a1, a2, b0, b1, b2) ||
         segment_intersects_triangle(a2, a0, b0, b1, b2) ||
         segment_intersects_triangle(b0, b1, a0, a1, a2) ||
         segment_intersects_triangle(b1, b2, a0, a1, a2) ||
         segment_intersects_triangle(b2, b0, a0, a1, a2);
}

int count_intersections(const std::vector<const CollisionMesh*>& meshes, bool use_x1,
                        WorkerPool* pool) {
  std::vector<Bvh> trees;
  return count_intersections(meshes, use_x1, trees, pool);
}

int count_intersections(const std::vector<const CollisionMesh*>& meshes, bool use_x1,
                        std::vector<Bvh>& bvhs, WorkerPool* pool) {
  const std::size_t nm = meshes.size();
  bvhs.resize(nm);
  for (std::size_t m = 0; m < nm; ++m) {
    const Points& x = use_x1 ? meshes[m]->x1 : meshes[m]->x0;
    const Triangles& faces = meshes[m]->faces;
    if (bvhs[m].num_faces() == faces.rows()) {
      bvhs[m].refit(faces, x, x, 0.0);
    } else {
      bvhs[m].build(faces, x, x, 0.0);
    }
  }
  std::atomic<int> count{0};
  std::vector<BvhQuery> queries;
  for (std::size_t i = 0; i < nm; ++i) {
    for (std::size_t j = i; j < nm; ++j) {
      const CollisionMesh& mi = *meshes[i];
      const CollisionMesh& mj = *meshes[j];
      if (mi.obstacle && mj.obstacle) continue;
      if (i == j && !mi.self_collision) continue;
      const Points& xi = use_x1 ? mi.x1 : mi.x0;
      const Points& xj = use_x1 ? mj.x1 : mj.x0;
      // Pieces of the search to whichever thread is free; the count is a sum, the same in any
      // order.
      WorkerPool* on = split_query(bvhs[i], bvhs[j], i == j, pool, queries);
      for_each_index(on, queries.size(), [&](std::size_t k) {
        std::vector<FacePair> pairs;
        run_query(bvhs[i], bvhs[j], queries[k], i == j ? &mi.faces : nullptr, pairs);
        int found = 0;
        for (const FacePair& fp : pairs) {
          auto pi = [&](int c) { return Vec3(xi.row(mi.faces(fp.a, c))); };
          auto pj = [&](int c) { return Vec3(xj.row(mj.faces(fp.b, c))); };
          if (triangles_intersect(pi(0), pi(1), pi(2), pj(0), pj(1), pj(2))) ++found;
        }
        count += found;
      });
    }
  }
  return count;
}

}  // namespace dexcloth::collision
