#include "coupling/rigid_patch.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <unordered_map>

namespace dexcloth::coupling {
namespace {

/// Union–find with path halving.
struct DisjointSets {
  std::vector<int> parent;
  explicit DisjointSets(int n) : parent(static_cast<std::size_t>(n)) {
    std::iota(parent.begin(), parent.end(), 0);
  }
  int find(int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void join(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
  /// The sets as lists of their members (each increasing), in order of their smallest member.
  std::vector<std::vector<int>> components() {
    std::vector<std::vector<int>> out;
    std::vector<int> slot(parent.size(), -1);
    for (int i = 0; i < static_cast<int>(parent.size()); ++i) {
      const int root = find(i);
      if (slot[static_cast<std::size_t>(root)] < 0) {
        slot[static_cast<std::size_t>(root)] = static_cast<int>(out.size());
        out.emplace_back();
      }
      out[static_cast<std::size_t>(slot[static_cast<std::size_t>(root)])].push_back(i);
    }
    return out;
  }
};

/// A cluster fits a plane when it spreads across its main direction by at least this share of
/// the patch's minimum size (RMS) [-].
constexpr double kMinPlaneSpread = 0.1;

bool joinable(const PatchVertex& a, const PatchVertex& b, const ClusterParams& p, double chord) {
  const Vec3 d = a.x - b.x;
  return d.norm() <= p.distance && (a.n - b.n).norm() <= chord &&
         std::abs(d.dot(a.n)) + std::abs(d.dot(b.n)) <= p.offset;
}

/// Cross product of (b − a) and (c − a) in 2-D.
double cross2(const Vec2& a, const Vec2& b, const Vec2& c) {
  return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
}

/// Distance from `p` to segment [a, b] in 2-D.
double segment_distance(const Vec2& a, const Vec2& b, const Vec2& p) {
  const Vec2 e = b - a;
  const double len2 = e.squaredNorm();
  const double s = len2 > 0.0 ? std::clamp((p - a).dot(e) / len2, 0.0, 1.0) : 0.0;
  return (a + s * e - p).norm();
}

/// Distance from `p` to the convex polygon `hull` (counter-clockwise, as convex_hull gives it;
/// one or two points are a point or a segment): 0 inside.
double hull_distance(const std::vector<Vec2>& hull, const Vec2& p) {
  if (hull.empty()) return std::numeric_limits<double>::infinity();
  if (hull.size() == 1) return (hull[0] - p).norm();
  bool inside = hull.size() > 2;
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Vec2& a = hull[i];
    const Vec2& b = hull[(i + 1) % hull.size()];
    inside = inside && cross2(a, b, p) >= 0.0;
    d = std::min(d, segment_distance(a, b, p));
  }
  return inside ? 0.0 : d;
}

/// Convex hull (Andrew's monotone chain), counter-clockwise, no collinear points.
std::vector<Vec2> convex_hull(std::vector<Vec2> pts) {
  std::sort(pts.begin(), pts.end(), [](const Vec2& a, const Vec2& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  if (pts.size() < 3) return pts;
  std::vector<Vec2> hull(2 * pts.size());
  std::size_t k = 0;
  for (const Vec2& p : pts) {
    while (k >= 2 && cross2(hull[k - 2], hull[k - 1], p) <= 0) --k;
    hull[k++] = p;
  }
  for (std::size_t i = pts.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross2(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  hull.resize(k - 1);
  return hull;
}

}  // namespace

std::vector<std::vector<int>> cluster_vertices(std::span<const PatchVertex> vertices,
                                               const ClusterParams& params) {
  const int n = static_cast<int>(vertices.size());
  const double chord = 2.0 * std::sin(0.5 * params.normal_deg * M_PI / 180.0);
  DisjointSets sets(n);
  // Uniform grid with cell δw: candidates of a vertex lie in the 27 surrounding cells.
  const auto cell_of = [&](const Vec3& x) {
    return Eigen::Vector3i((x / params.distance).array().floor().cast<int>());
  };
  const auto key = [](const Eigen::Vector3i& c) {
    return (static_cast<long long>(c.x()) * 73856093LL) ^
           (static_cast<long long>(c.y()) * 19349663LL) ^
           (static_cast<long long>(c.z()) * 83492791LL);
  };
  std::unordered_map<long long, std::vector<int>> grid;
  for (int i = 0; i < n; ++i) grid[key(cell_of(vertices[i].x))].push_back(i);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3i c = cell_of(vertices[i].x);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find(key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == grid.end()) continue;
          for (int j : it->second)
            if (j > i && joinable(vertices[i], vertices[j], params, chord)) sets.join(i, j);
        }
  }
  return sets.components();
}

Rectangle2 min_area_rectangle(std::span<const Vec2> points) {
  Rectangle2 best;
  if (points.empty()) return best;
  const std::vector<Vec2> hull = convex_hull({points.begin(), points.end()});
  double best_area = std::numeric_limits<double>::infinity();
  // Try each hull edge direction (the optimal rectangle has a side on a hull edge); with fewer
  // than two distinct points, any axis will do.
  std::vector<Vec2> axes;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Vec2 e = hull[(i + 1) % hull.size()] - hull[i];
    if (e.norm() > 0) axes.push_back(e.normalized());
  }
  if (axes.empty()) axes.push_back(Vec2::UnitX());
  for (const Vec2& u : axes) {
    const Vec2 v(-u.y(), u.x());
    double umin = INFINITY, umax = -INFINITY, vmin = INFINITY, vmax = -INFINITY;
    for (const Vec2& p : hull) {
      umin = std::min(umin, p.dot(u));
      umax = std::max(umax, p.dot(u));
      vmin = std::min(vmin, p.dot(v));
      vmax = std::max(vmax, p.dot(v));
    }
    const double area = (umax - umin) * (vmax - vmin);
    if (area < best_area - 1e-18) {
      best_area = area;
      best.axis = u;
      best.extent = Vec2(umax - umin, vmax - vmin);
      best.center = 0.5 * (umin + umax) * u + 0.5 * (vmin + vmax) * v;
    }
  }
  return best;
}

RigidPatch build_patch(std::span<const PatchVertex> vertices, std::span<const int> cluster,
                       double thickness, double min_size) {
  RigidPatch patch;
  patch.vertices.assign(cluster.begin(), cluster.end());
  // Mass, centre of mass, momentum.
  Vec3 com = Vec3::Zero(), momentum = Vec3::Zero(), mean_normal = Vec3::Zero();
  for (int i : cluster) {
    const PatchVertex& pv = vertices[i];
    patch.mass += pv.mass;
    com += pv.mass * pv.x;
    momentum += pv.mass * pv.v;
    mean_normal += pv.n;
  }
  com /= patch.mass;
  const Vec3 v_com = momentum / patch.mass;

  // Plane fit: normal = direction of least spread, oriented like the vertex normals.
  Mat3 cov = Mat3::Zero();
  for (int i : cluster) {
    const Vec3 r = vertices[i].x - com;
    cov += r * r.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(cov);
  // Vertices pressed from opposite sides (a stack) can have normals summing to zero.
  if (mean_normal.norm() < 1e-9 * static_cast<double>(cluster.size()))
    mean_normal = vertices[cluster.front()].n;
  mean_normal.normalize();
  // Vertices along a line (a row along a finger's edge) fit no plane: any normal about the line
  // fits, and the one the solver returns was up to 90° from the surfaces they touch. Then the
  // vertex normals, made orthogonal to the line, give it.
  const Eigen::Vector3d spread = eig.eigenvalues().cwiseMax(0.0);
  const double rms_across = std::sqrt(spread(1) / static_cast<double>(cluster.size()));
  const bool planar = cluster.size() >= 3 && spread(1) > 0.01 * spread(2) &&
                      rms_across > kMinPlaneSpread * min_size;
  Vec3 n = Vec3(eig.eigenvectors().col(0));
  if (!planar) {
    const Vec3 line = eig.eigenvectors().col(2);
    const Vec3 across = mean_normal - mean_normal.dot(line) * line;
    n = spread(2) > 0.0 && across.norm() > 1e-6 ? Vec3(across.normalized()) : mean_normal;
  }
  if (n.dot(mean_normal) < 0) n = -n;
  // In-plane basis, then the minimum-area rectangle of the projected vertices.
  Vec3 e1 = n.unitOrthogonal();
  Vec3 e2 = n.cross(e1);
  std::vector<Vec2> projected;
  projected.reserve(cluster.size());
  for (int i : cluster) {
    const Vec3 r = vertices[i].x - com;
    projected.emplace_back(r.dot(e1), r.dot(e2));
  }
  const Rectangle2 rect = min_area_rectangle(projected);
  const Vec3 u = rect.axis.x() * e1 + rect.axis.y() * e2;
  patch.R.col(0) = u;
  patch.R.col(1) = n.cross(u);
  patch.R.col(2) = n;
  patch.center = com + rect.center.x() * e1 + rect.center.y() * e2;
  patch.size =
      Vec3(std::max(rect.extent.x(), min_size), std::max(rect.extent.y(), min_size), thickness);

  // Angular velocity from the angular momentum about the centre of mass: ω = I⁻¹ L.
  Vec3 L = Vec3::Zero();
  Mat3 I = Mat3::Zero();
  for (int i : cluster) {
    const PatchVertex& pv = vertices[i];
    const Vec3 r = pv.x - com;
    L += pv.mass * r.cross(pv.v - v_com);
    I += pv.mass * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
  }
  const Eigen::SelfAdjointEigenSolver<Mat3> inertia(I);
  const double cutoff = 1e-12 * std::max(inertia.eigenvalues().maxCoeff(), 1e-300);
  Vec3 omega = Vec3::Zero();
  for (int k = 0; k < 3; ++k) {
    const double lambda = inertia.eigenvalues()(k);
    if (lambda > cutoff) {
      const Vec3 axis = inertia.eigenvectors().col(k);
      omega += axis * (axis.dot(L) / lambda);
    }
  }
  patch.angular_velocity = omega;
  patch.linear_velocity = v_com + omega.cross(patch.center - com);
  return patch;
}

namespace {

/// The median of a non-empty list (reordered); the mean of the middle two for an even count.
double median(std::vector<double>& values) {
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  if (values.size() % 2 == 1) return *mid;
  return 0.5 * (*mid + *std::max_element(values.begin(), mid));
}

/// The component-wise median of unit vectors given by their x, y and z components (reordered),
/// normalised; zero if that median is zero.
Vec3 median_direction(std::array<std::vector<double>, 3>& components) {
  const Vec3 m(median(components[0]), median(components[1]), median(components[2]));
  return m.norm() > 0.0 ? Vec3(m.normalized()) : Vec3::Zero();
}

/// Surfaces within this angle of the patch normal carry its faces [deg].
constexpr double kFacingDeg = 20.0;
/// A driven body presses a cluster against a support when its surface normal is within this angle
/// of the support's, reversed [deg].
constexpr double kPressingDeg = 70.0;
/// Share of a cluster's touches that must face one way for it to count as pressed from one side.
constexpr double kOneSidedShare = 0.8;

/// Offsets along `n` (from `center`) of the surfaces facing a patch of normal n from above
/// (normal within kFacingDeg of −n) and from below (within kFacingDeg of +n), and their normals
/// turned to +n.
struct FacingSurfaces {
  std::vector<double> above, below;
  std::vector<int> above_bodies, below_bodies;  ///< SurfaceTouch::body of each
  std::array<std::vector<double>, 3> normals;   ///< x, y, z components
  bool ahead{false};  ///< one of them is a touch ahead of a fast body (SurfaceTouch::ahead)
};

FacingSurfaces facing_surfaces(std::span<const SurfaceTouch> touches, const Vec3& center,
                               const Vec3& n) {
  const double min_cosine = std::cos(kFacingDeg * std::numbers::pi / 180.0);
  FacingSurfaces f;
  for (const SurfaceTouch& t : touches) {
    if (t.support) continue;
    const double facing = t.normal.dot(n);
    const double s = (t.point - center).dot(n);
    const bool above = facing <= -min_cosine && s > 0.0, below = facing >= min_cosine && s < 0.0;
    if (above) {
      f.above.push_back(s);
      f.above_bodies.push_back(t.body);
    }
    if (below) {
      f.below.push_back(s);
      f.below_bodies.push_back(t.body);
    }
    if (!above && !below) continue;
    for (int k = 0; k < 3; ++k) f.normals[k].push_back(above ? -t.normal[k] : t.normal[k]);
    f.ahead = f.ahead || t.ahead;
  }
  return f;
}

/// Moves the box by `shift`, its centre's velocity following the fitted motion, and makes it
/// `thickness` thick.
void shift_box(RigidPatch& patch, const Vec3& shift, double thickness) {
  patch.center += shift;
  patch.linear_velocity += patch.angular_velocity.cross(shift);
  patch.size.z() = thickness;
}

/// The body that most of `bodies` name (the lowest such id on a tie).
int most_frequent(std::vector<int> bodies) {
  std::sort(bodies.begin(), bodies.end());
  int best = bodies.front(), best_count = 0;
  for (std::size_t i = 0; i < bodies.size();) {
    std::size_t j = i;
    while (j < bodies.size() && bodies[j] == bodies[i]) ++j;
    if (static_cast<int>(j - i) > best_count) {
      best = bodies[i];
      best_count = static_cast<int>(j - i);
    }
    i = j;
  }
  return best;
}

}  // namespace

bool centre_between_surfaces(RigidPatch& patch, std::span<const SurfaceTouch> touches,
                             double thickness) {
  Vec3 axis = patch.R.col(2);
  FacingSurfaces f = facing_surfaces(touches, patch.center, axis);
  if (f.above.empty() || f.below.empty()) {
    // The fitted plane may tilt beyond kFacingDeg from the fingers (a fold bent round a pad's
    // edge joined the cluster; in a carried pinch it tilted 23° and the box, left thinner and
    // askew between the pads, let them close and the sheet go): then look for the faces about
    // the touches' own median direction (their normals each turned to the patch's side).
    std::array<std::vector<double>, 3> turned;
    for (const SurfaceTouch& t : touches) {
      if (t.support) continue;
      const Vec3 m = t.normal.dot(patch.R.col(2)) >= 0.0 ? t.normal : Vec3(-t.normal);
      for (int k = 0; k < 3; ++k) turned[static_cast<std::size_t>(k)].push_back(m[k]);
    }
    if (turned[0].empty()) return false;
    axis = median_direction(turned);
    if (axis.squaredNorm() == 0.0) return false;
    f = facing_surfaces(touches, patch.center, axis);
    if (f.above.empty() || f.below.empty()) return false;
  }
  // The pads: on each side, the body that touches the cloth most.
  const int top = most_frequent(f.above_bodies), bottom = most_frequent(f.below_bodies);
  std::vector<SurfaceTouch> pads;
  for (const SurfaceTouch& t : touches)
    if (t.body == top || t.body == bottom) pads.push_back(t);
  f = facing_surfaces(pads, patch.center, axis);
  // Turn the box to the surfaces' mean plane: the plane fitted to crumpled cloth in a pinch tilts
  // by up to 20°, and the corners of a tilted box sink millimetres deep into a finger, which
  // then takes the box's contact on an edge instead of squeezing it flat.
  Vec3 n = median_direction(f.normals);
  FacingSurfaces turned = facing_surfaces(pads, patch.center, n);
  if (!turned.above.empty() && !turned.below.empty()) {  // (none for a zero n)
    patch.R = Eigen::Quaterniond::FromTwoVectors(patch.R.col(2), n).toRotationMatrix() * patch.R;
    f = std::move(turned);
  } else {
    n = patch.R.col(2);
  }
  // The median on each side is the finger pad's face when the cloth also brushes the finger's
  // rounded flank around the pad. A box between surfaces ahead of fast fingers fills the gap
  // between them.
  const double above = median(f.above), below = median(f.below);
  shift_box(patch, 0.5 * (above + below) * n,
            f.ahead ? std::max(thickness, above - below) : thickness);
  return true;
}

bool lay_on_support(RigidPatch& patch, std::span<const SurfaceTouch> touches, double thickness) {
  std::array<std::vector<double>, 3> normals;
  for (const SurfaceTouch& t : touches)
    if (t.support)
      for (int k = 0; k < 3; ++k) normals[static_cast<std::size_t>(k)].push_back(t.normal[k]);
  if (normals[0].empty()) return false;
  const Vec3 n = median_direction(normals);
  if (n.squaredNorm() == 0.0) return false;
  const double facing_cosine = std::cos(kFacingDeg * std::numbers::pi / 180.0);
  const double pressing_cosine = std::cos(kPressingDeg * std::numbers::pi / 180.0);
  std::vector<double> below, ahead;
  bool pressed = false;
  for (const SurfaceTouch& t : touches) {
    const double s = (t.point - patch.center).dot(n), facing = t.normal.dot(n);
    if (t.support && facing >= facing_cosine && s < 0.0) below.push_back(s);
    if (t.support || facing > -pressing_cosine || s <= 0.0) continue;
    pressed = true;
    if (t.ahead) ahead.push_back(s);
  }
  if (!pressed || below.empty()) return false;
  patch.R = Eigen::Quaterniond::FromTwoVectors(patch.R.col(2), n).toRotationMatrix() * patch.R;
  // Up to the surface ahead of a fast body pressing down, when that is higher.
  const double bottom = median(below);
  const double height = ahead.empty() ? thickness : std::max(thickness, median(ahead) - bottom);
  shift_box(patch, (bottom + 0.5 * height) * n, height);
  return true;
}

std::vector<int> join_facing_clusters(std::vector<std::vector<int>>& clusters,
                                      std::vector<std::vector<SurfaceTouch>>& touches,
                                      std::span<const PatchVertex> vertices, double max_gap,
                                      double max_lateral, double overlap) {
  const int n = static_cast<int>(clusters.size());
  const double min_cosine = std::cos(kFacingDeg * std::numbers::pi / 180.0);
  // Mean surface point and normal of each cluster touched from one side only.
  std::vector<bool> one_sided(static_cast<std::size_t>(n), false);
  std::vector<Vec3> point(static_cast<std::size_t>(n), Vec3::Zero()),
      normal(static_cast<std::size_t>(n), Vec3::Zero());
  for (int c = 0; c < n; ++c) {
    const auto& t = touches[static_cast<std::size_t>(c)];
    if (t.empty()) continue;
    Vec3 m = Vec3::Zero();
    for (const SurfaceTouch& s : t) m += s.normal;
    if (m.norm() == 0.0) continue;
    m.normalize();
    // Pressed from one side: nearly all its touches face along m (a vertex or two at the edge
    // of the cloth curls round the finger's edge); its point is the mean of those.
    Vec3 q = Vec3::Zero();
    int along = 0;
    for (const SurfaceTouch& s : t)
      if (s.normal.dot(m) >= min_cosine) {
        q += s.point;
        ++along;
      }
    one_sided[static_cast<std::size_t>(c)] =
        along >= kOneSidedShare * static_cast<double>(t.size());
    point[static_cast<std::size_t>(c)] = q / std::max(1, along);
    normal[static_cast<std::size_t>(c)] = m;
  }
  const auto facing = [&](int a, int b) {
    const auto ua = static_cast<std::size_t>(a), ub = static_cast<std::size_t>(b);
    if (!one_sided[ua] || !one_sided[ub] || normal[ua].dot(normal[ub]) > -min_cosine) return false;
    const Vec3 d = point[ub] - point[ua];
    const double ahead = d.dot(normal[ua]);
    return ahead > 0.0 && ahead <= max_gap && (d - ahead * normal[ua]).norm() <= max_lateral;
  };
  // Whether a vertex of cluster b lies over cluster a: projected along a's normal, within
  // `overlap` of the convex hull of a's vertices.
  const auto over = [&](int a, int b) {
    const Vec3& m = normal[static_cast<std::size_t>(a)];
    const Vec3 u = m.unitOrthogonal(), w = m.cross(u);
    std::vector<Vec2> footprint;
    for (int k : clusters[static_cast<std::size_t>(a)])
      footprint.emplace_back(vertices[static_cast<std::size_t>(k)].x.dot(u),
                             vertices[static_cast<std::size_t>(k)].x.dot(w));
    const std::vector<Vec2> hull = convex_hull(std::move(footprint));
    return std::any_of(clusters[static_cast<std::size_t>(b)].begin(),
                       clusters[static_cast<std::size_t>(b)].end(), [&](int k) {
                         const Vec3& x = vertices[static_cast<std::size_t>(k)].x;
                         return hull_distance(hull, Vec2(x.dot(u), x.dot(w))) <= overlap;
                       });
  };
  DisjointSets sets(n);
  std::vector<char> stacked(static_cast<std::size_t>(n), 0);
  bool any = false;
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b)
      if (facing(a, b) && facing(b, a)) {
        sets.join(a, b);
        any = true;
        if (over(a, b) || over(b, a))
          stacked[static_cast<std::size_t>(a)] = stacked[static_cast<std::size_t>(b)] = 1;
      }
  std::vector<int> layers;
  if (!any) {
    layers.assign(static_cast<std::size_t>(n), 1);
    return layers;
  }
  // Each stack: its clusters' vertices (sorted) and touches, concatenated in the first slot.
  const std::vector<std::vector<int>> stacks = sets.components();
  for (std::size_t j = 0; j < stacks.size(); ++j) {
    const auto first = static_cast<std::size_t>(stacks[j].front());
    std::vector<int> members = std::move(clusters[first]);
    std::vector<SurfaceTouch> surfaces = std::move(touches[first]);
    for (std::size_t q = 1; q < stacks[j].size(); ++q) {
      const auto c = static_cast<std::size_t>(stacks[j][q]);
      members.insert(members.end(), clusters[c].begin(), clusters[c].end());
      surfaces.insert(surfaces.end(), touches[c].begin(), touches[c].end());
    }
    if (stacks[j].size() > 1) std::sort(members.begin(), members.end());
    clusters[j] = std::move(members);
    touches[j] = std::move(surfaces);
    const bool over_each_other = std::any_of(stacks[j].begin(), stacks[j].end(), [&](int c) {
      return stacked[static_cast<std::size_t>(c)] != 0;
    });
    layers.push_back(over_each_other ? 2 : 1);
  }
  clusters.resize(stacks.size());
  touches.resize(stacks.size());
  return layers;
}

}  // namespace dexcloth::coupling
