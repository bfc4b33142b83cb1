#pragma once
/// Rigid cloth patches (paper §5): thin boxes approximating the cloth under the hand, rebuilt every
/// step from the vertices in contact with rigid bodies (Vr), so the rigid simulator sees the cloth.
#include <span>
#include <vector>

#include "core/types.hpp"

namespace dexcloth::coupling {

/// Clustering thresholds (paper eqs. 9–11).
struct ClusterParams {
  double distance{0.040};  ///< δw: ‖xi − xj‖ ≤ δw [m]
  double normal_deg{20.0};  ///< δn: angle between ni and nj ≤ δn [deg] (‖ni − nj‖ ≤ 2 sin(δn/2))
  double offset{0.003};  ///< δd: |(xi − xj)·ni| + |(xi − xj)·nj| ≤ δd [m]
};

/// A cloth vertex offered to the patch builder.
struct PatchVertex {
  Vec3 x{Vec3::Zero()};   ///< position [m]
  Vec3 v{Vec3::Zero()};   ///< velocity [m/s]
  Vec3 n{Vec3::UnitZ()};  ///< unit surface normal
  double mass{};          ///< [kg]
};

/// One rigid cloth patch: a box of size (x, y, thickness) in its frame R = [e_u e_v n].
struct RigidPatch {
  Vec3 center{Vec3::Zero()};            ///< box centre, on the fitted plane [m]
  Mat3 R{Mat3::Identity()};             ///< columns: rectangle axes u, v and the plane normal
  Vec3 size{Vec3::Zero()};              ///< full extents along u, v, n [m]
  double mass{};                        ///< sum of the vertex masses [kg]
  Vec3 linear_velocity{Vec3::Zero()};   ///< velocity of the box centre [m/s]
  Vec3 angular_velocity{Vec3::Zero()};  ///< fitted to the cloth [rad/s]; DART's box starts
                                        ///< without it (update_patches)
  std::vector<int> vertices;  ///< indices into the builder's input (cloth vertices once placed)
  std::vector<int> cloths;    ///< cloth mesh of each vertex, once placed
};

/// Groups vertices into clusters: i and j are joined (transitively) when all three paper
/// conditions hold. Returns the clusters as lists of input indices, each sorted, ordered by their
/// first index. Uses a uniform grid of cell δw, so it is near-linear in the vertex count.
std::vector<std::vector<int>> cluster_vertices(std::span<const PatchVertex> vertices,
                                               const ClusterParams& params);

/// Fits a patch to a cluster: least-squares plane (for vertices along a line, which fit no plane,
/// the one holding the line and the mean vertex normal), minimum-area rectangle of the vertices
/// projected on it (rotating calipers on the convex hull), each side at least `min_size`, thickness
/// `thickness`, summed mass, linear velocity from the momentum, angular velocity from the angular
/// momentum about the centre of mass (ω = I⁻¹L, pseudo-inverse for collinear clusters).
RigidPatch build_patch(std::span<const PatchVertex> vertices, std::span<const int> cluster,
                       double thickness, double min_size);

/// A point of a rigid surface that a patch's cloth touches, and the surface's unit normal there
/// (pointing out of the body, toward the cloth).
struct SurfaceTouch {
  Vec3 point{Vec3::Zero()};
  Vec3 normal{Vec3::UnitZ()};
  bool support{false};  ///< a body no controller drives (a table), which the cloth lies on
  /// The surface of a fast body ahead of the cloth (speculative_touches.hpp), placed where DART
  /// is to meet it within its next step (patch_update.cpp): the box reaches out to it.
  bool ahead{false};
  int body{-1};  ///< the touching body, or −1 (centre_between_surfaces faces one per side)
};

/// Centres the patch between the rigid surfaces its cloth touches on both sides (two fingers
/// of a pinch) and makes it `thickness` thick, so each finger sinks into it by the same depth and
/// the rigid simulator pushes both back alike. Centred on the cloth instead, a patch missed one
/// finger as soon as the cloth sat a fraction of a millimetre off centre, and that finger closed
/// through it. The surfaces are those facing within 20° of the patch normal; the box is first
/// turned about its centre to their plane (component-wise median of their normals, each turned
/// to the patch's side) and then centred on the median offset of each side (a finger's flank
/// beside the pad is outvoted). When no surface faces the patch's normal on one side, the same
/// is tried about the median of all the touches' normals (a plane fitted to cloth bent round a
/// pad's edge can tilt more than 20°). Of the surfaces facing each side only the body with the
/// most touches there counts (SurfaceTouch::body; the pad): a flat box meets one body per side,
/// and turned to the median of a thumb's pad and its proximal phalanx, bent away behind it, a
/// box leant on the phalanx and left the pad without squeeze. Supports (SurfaceTouch::support)
/// are left out: a cloth pressed onto a table lies on it (lay_on_support). A patch touched on one
/// side only, or none, is left as it is. When one of the facing surfaces is a touch ahead of a
/// fast body (SurfaceTouch::ahead), the box fills the gap between the two sides' medians if that
/// is more than `thickness`, so both fingers meet it within the step. Returns whether it was
/// centred.
bool centre_between_surfaces(RigidPatch& patch, std::span<const SurfaceTouch> touches,
                             double thickness);

/// Lays a patch that centre_between_surfaces left alone on the support its cloth lies on (a body
/// no controller drives: a table), when a driven body presses the cloth toward it, its surface
/// normal within 70° of the support's reversed (a finger's pad or a thumb's rounded tip): the box
/// turns to the support's normal (the median of its touches') and spans `thickness` from the
/// support's surface: a layer pressed there takes one repulsion thickness, not the two of a layer
/// floating between two fingers (the body rests within the reach of the cloth, which its repulsion
/// squeezes onto the support: a napkin under a resting box, from 3.9 mm above the table to 0.1).
/// Centred between a thumb and the table as between two fingers, the box held the thumb
/// two thicknesses up, beyond the reach of the cloth lying on the table: the patch was gone at the
/// next step and the thumb, sprung back by its joints, fell through the cloth. Tilted to the
/// fitted cloth and centred on it, as when the thumb's normal was too far from the table's, the
/// box sank half into the table and the thumb, meeting a sloped face, pushed it aside. Returns
/// whether it did.
/// A pressing touch ahead of a fast body (SurfaceTouch::ahead) raises the box's top to the
/// median of those touches when that is higher than `thickness` reaches.
bool lay_on_support(RigidPatch& patch, std::span<const SurfaceTouch> touches, double thickness);

/// Joins clusters of one cloth that are pressed from opposite sides into one stack (a fold or
/// several layers of cloth between two fingers, or a single layer crumpled into a step whose
/// parts touch one finger each). `touches[c]` are the rigid surfaces touching cluster c, whose
/// members index `vertices`. A cluster touched from one side only (at least 80 % of its surface
/// normals within 20° of their mean m: a vertex or two at the cloth's edge may curl round the
/// finger) joins another one-sided cluster whose mean normal is within 20° of −m when each faces
/// the other: the other's mean surface point (over its touches along its m) lies ahead along m
/// by at most `max_gap` [m] and within `max_lateral` [m] of its own across m. Each cluster is
/// pressed by one finger only, so each patch alone would be a free light box the finger pushes
/// aside; as one patch the stack is squeezed between both. Returns, per resulting cluster, the
/// cloth layers it holds: 1 for a cluster left alone, 2 for a stack whose joined clusters lie
/// over each other (a vertex of one, projected along the other's normal, within `overlap` [m]
/// of the convex hull of the other's vertices), however many clusters it joined (those pressed
/// by one finger are pieces of one outer layer; a finger's pad and flank, or a crumple, split a
/// layer into several, and counting them as layers made a 25 mm patch between pads 8 mm apart),
/// and 1 for a stack of clusters side by side: one layer stepped between the fingers, which
/// they press flat (counted as two, a key pinch on a curtain's stepped edge held the pads a
/// thickness apart until the step gave way under the pull, and the curtain slipped 8 mm while
/// they closed); `clusters` and `touches` are rewritten alike (a joined cluster's members
/// sorted, its touches concatenated), in order of each stack's first cluster.
std::vector<int> join_facing_clusters(std::vector<std::vector<int>>& clusters,
                                      std::vector<std::vector<SurfaceTouch>>& touches,
                                      std::span<const PatchVertex> vertices, double max_gap,
                                      double max_lateral, double overlap);

/// Minimum-area enclosing rectangle of 2-D points: its centre, unit axis u (v = u rotated by 90°)
/// and full extents. Exposed for tests.
struct Rectangle2 {
  Vec2 center{Vec2::Zero()};
  Vec2 axis{Vec2::UnitX()};
  Vec2 extent{Vec2::Zero()};
};
Rectangle2 min_area_rectangle(std::span<const Vec2> points);

}  // namespace dexcloth::coupling
