#pragma once
/// Internal state of a RigidWorld (DART types). Included only by src/rigid/*.cpp.
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include <dart/collision/CollisionFilter.hpp>
#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/BoxShape.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/simulation/World.hpp>

#include "rigid/world.hpp"

namespace dexcloth::rigid::detail {

/// One body node known to the world.
struct BodyRecord {
  std::string name;                          ///< "skeleton/body_node"
  dart::dynamics::BodyNode* node{};
  int skeleton{-1};
  int patch{-1};                             ///< pool index for patch bodies, else −1
  std::vector<ContactPoint> contacts;        ///< from the last step
};

/// One skeleton known to the world.
struct SkeletonRecord {
  std::string name;
  std::string file;                          ///< URDF path as given, "" otherwise
  dart::dynamics::SkeletonPtr skel;
  std::vector<int> bodies;                   ///< BodyRecord indices, DART order
  std::vector<PoseKeyframe> motion;          ///< keyframed (kinematic) props
  /// Joint PD per DOF (set_joint_pd; URDF joint damping is the initial kd): stiffness
  /// [N·m/rad or N/m], damping [N·m·s/rad or N·s/m], target [rad or m]. Realised by
  /// apply_stable_pd; DART's own joint springs stay at zero, its dampers too but for the
  /// prediction apply_stable_pd makes through them.
  Eigen::VectorXd pd_kp, pd_kd, pd_target;
  /// Scratch of apply_stable_pd (sized once per skeleton).
  Eigen::VectorXd pd_applied, pd_rhs, pd_qdd;
};

/// One pool patch.
struct PatchRecord {
  int body{-1};
  int skeleton{-1};
  bool active{false};
  int layer{0};  ///< PatchState::layer
  std::shared_ptr<dart::dynamics::BoxShape> box;
  Eigen::Isometry3d X_W_park{Eigen::Isometry3d::Identity()};  ///< where an inactive patch waits
};

/// Collision filter: DART's body-node rules (adjacent links, self collision, black list) plus
/// the patch rules (no pairs of patches of one layer, inactive patches collide with nothing).
class CollisionFilter final : public dart::collision::BodyNodeCollisionFilter {
 public:
  explicit CollisionFilter(const WorldImpl& world) : m_world(&world) {}
  bool ignoresCollision(const dart::collision::CollisionObject* object1,
                        const dart::collision::CollisionObject* object2) const override;

 private:
  const WorldImpl* m_world;
};

struct WorldImpl {
  RigidWorldOptions options;
  dart::simulation::WorldPtr world;
  std::shared_ptr<CollisionFilter> filter;
  std::vector<SkeletonRecord> skeletons;
  std::vector<BodyRecord> bodies;
  std::unordered_map<const dart::dynamics::BodyNode*, int> body_of_node;
  std::vector<PatchRecord> patches;
  std::unique_ptr<PatchPool> pool;
  bool patch_gravity{true};
  long steps{};
  /// Obstacle export cache: exportable bodies and their body-frame meshes, built when the
  /// number of bodies changes.
  std::size_t obstacle_cache_bodies{0};
  std::vector<int> obstacle_bodies;
  std::vector<LocalMesh> obstacle_local;
  int num_contacts{};
  std::vector<Eigen::VectorXd> held_forces;  ///< per skeleton, the forces added for a step

  /// Adds `skel` to the DART world and registers its bodies.
  int register_skeleton(dart::dynamics::SkeletonPtr skel, std::string file);
  /// Record of the body owning a DART body node, or −1 (unknown node).
  int body_index(const dart::dynamics::BodyNode* node) const;
  /// Moves patch `i` to its parked, inactive state.
  void park_patch(int i);
  /// Makes patch `i`'s box a member of the contact solver's collision group in its own right,
  /// no longer through its skeleton's subscription (see world.cpp).
  void detach_patch_shape(int i);
  /// Sets patch `i`'s box size and rebuilds its collision object (see world.cpp).
  void resize_patch(int i, const Vec3& size);
  /// The shape node of patch `i`'s box.
  const dart::dynamics::ShapeNode* patch_shape_node(int i) const;
  /// Adds the stable-PD torques of every skeleton with joint gains to its forces (see world.cpp).
  void apply_stable_pd();
  /// Appends the last DART step's contacts to the bodies' lists, forces scaled by `weight`.
  void record_contacts(double weight);
};

/// Sets pose and velocity of a free-joint root (positions and body-frame velocities).
void set_free_root_state(dart::dynamics::Skeleton& skel, const Eigen::Isometry3d& X_WB,
                         const Vec3& v_W, const Vec3& w_W);

}  // namespace dexcloth::rigid::detail
