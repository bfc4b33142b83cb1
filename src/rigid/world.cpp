#include "rigid/world.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include <assimp/cimport.h>
#include <assimp/scene.h>
#include <dart/collision/CollisionObject.hpp>
#include <dart/collision/bullet/BulletCollisionDetector.hpp>
#include <dart/constraint/ConstraintSolver.hpp>
#include <dart/constraint/ContactConstraint.hpp>
#include <dart/dynamics/CapsuleShape.hpp>
#include <dart/dynamics/CylinderShape.hpp>
#include <dart/dynamics/DegreeOfFreedom.hpp>
#include <dart/dynamics/FreeJoint.hpp>
#include <dart/dynamics/MeshShape.hpp>
#include <dart/dynamics/ShapeNode.hpp>
#include <dart/dynamics/SphereShape.hpp>
#include <dart/dynamics/WeldJoint.hpp>
#include <dart/utils/urdf/DartLoader.hpp>

#include "core/assert.hpp"
#include "core/errors.hpp"
#include "rigid/detail/world_impl.hpp"

namespace dexcloth::rigid {

namespace dd = dart::dynamics;

namespace {

/// Contact penetration recovery: fraction of the depth removed per step, and its speed cap [m/s].
constexpr double kContactErrorReduction = 0.1;
constexpr double kContactMaxErrorVelocity = 0.005;
constexpr double kContactErrorAllowance = 2.5e-4;

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Throws InputRejected with one problem in `file`.
[[noreturn]] void reject(const std::string& file, std::string message) {
  ErrorList errors;
  errors.add(file.empty() ? std::string("rigid world") : file, "", std::move(message));
  throw InputRejected(std::move(errors));
}

/// What makes a loaded mesh unusable as a body's surface, or "" if nothing: no triangles, or a
/// non-finite coordinate (the reader takes "nan" and "inf" for numbers).
std::string mesh_problem(const aiScene& scene) {
  int triangles = 0;
  for (unsigned k = 0; k < scene.mNumMeshes; ++k) {
    const aiMesh& mesh = *scene.mMeshes[k];
    for (unsigned i = 0; i < mesh.mNumVertices; ++i) {
      const aiVector3D& p = mesh.mVertices[i];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        return "mesh has a non-finite vertex coordinate";
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) triangles += mesh.mFaces[f].mNumIndices == 3 ? 1 : 0;
  }
  return triangles == 0 ? "cannot read mesh: no triangles" : "";
}

/// Creates a single-body skeleton with a free root and one collision shape.
dd::SkeletonPtr make_free_body(const std::string& name, const std::shared_ptr<dd::Shape>& shape,
                               double mass, double friction, const Eigen::Isometry3d& X_BS) {
  auto skel = dd::Skeleton::create(name);
  dd::FreeJoint::Properties joint;
  joint.mName = name + "_root";
  auto* body =
      skel->createJointAndBodyNodePair<dd::FreeJoint>(nullptr, joint, dd::BodyNode::AspectProperties("body"))
          .second;
  auto* node = body->createShapeNodeWith<dd::VisualAspect, dd::CollisionAspect, dd::DynamicsAspect>(shape);
  node->setRelativeTransform(X_BS);
  node->getDynamicsAspect()->setFrictionCoeff(friction);
  const double m = mass > 0.0 ? mass : 1.0;
  dd::Inertia inertia(m, X_BS.translation(), X_BS.linear() * shape->computeInertia(m) * X_BS.linear().transpose());
  body->setInertia(inertia);
  return skel;
}

/// Local triangle mesh of one DART shape, or nothing for unsupported shape types.
std::optional<LocalMesh> tessellate(const dd::Shape& shape) {
  if (const auto* box = dynamic_cast<const dd::BoxShape*>(&shape)) return box_mesh(box->getSize());
  if (const auto* s = dynamic_cast<const dd::SphereShape*>(&shape)) return sphere_mesh(s->getRadius());
  if (const auto* c = dynamic_cast<const dd::CapsuleShape*>(&shape)) {
    return capsule_mesh(c->getRadius(), c->getHeight());
  }
  if (const auto* c = dynamic_cast<const dd::CylinderShape*>(&shape)) {
    return cylinder_mesh(c->getRadius(), c->getHeight());
  }
  if (const auto* m = dynamic_cast<const dd::MeshShape*>(&shape)) {
    const aiScene* scene = m->getMesh();
    if (scene == nullptr) return std::nullopt;
    LocalMesh out;
    const Vec3 scale = m->getScale();
    for (unsigned k = 0; k < scene->mNumMeshes; ++k) {
      const aiMesh* mesh = scene->mMeshes[k];
      LocalMesh part;
      part.x.resize(mesh->mNumVertices, 3);
      for (unsigned i = 0; i < mesh->mNumVertices; ++i) {
        const aiVector3D& p = mesh->mVertices[i];
        part.x.row(i) << scale.x() * p.x, scale.y() * p.y, scale.z() * p.z;
      }
      int nf = 0;
      for (unsigned f = 0; f < mesh->mNumFaces; ++f) nf += mesh->mFaces[f].mNumIndices == 3 ? 1 : 0;
      part.faces.resize(nf, 3);
      int row = 0;
      for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
        const aiFace& face = mesh->mFaces[f];
        if (face.mNumIndices != 3) continue;
        part.faces.row(row++) << static_cast<int>(face.mIndices[0]), static_cast<int>(face.mIndices[1]),
            static_cast<int>(face.mIndices[2]);
      }
      append_mesh(out, part, Eigen::Isometry3d::Identity());
    }
    return out;
  }
  return std::nullopt;
}

}  // namespace

// ---- detail ------------------------------------------------------------------------------------

namespace detail {

bool CollisionFilter::ignoresCollision(const dart::collision::CollisionObject* object1,
                                       const dart::collision::CollisionObject* object2) const {
  const auto* node1 = object1->getShapeFrame()->asShapeNode();
  const auto* node2 = object2->getShapeFrame()->asShapeNode();
  if (node1 != nullptr && node2 != nullptr) {
    const int b1 = m_world->body_index(node1->getBodyNodePtr().get());
    const int b2 = m_world->body_index(node2->getBodyNodePtr().get());
    const int p1 = b1 >= 0 ? m_world->bodies[static_cast<std::size_t>(b1)].patch : -1;
    const int p2 = b2 >= 0 ? m_world->bodies[static_cast<std::size_t>(b2)].patch : -1;
    // Patch rules (paper §5): no pairs of patches of one layer (one cloth); inactive patches
    // collide with nothing.
    if (p1 >= 0 && p2 >= 0 &&
        m_world->patches[static_cast<std::size_t>(p1)].layer == m_world->patches[static_cast<std::size_t>(p2)].layer)
      return true;
    if (p1 >= 0 && !m_world->patches[static_cast<std::size_t>(p1)].active) return true;
    if (p2 >= 0 && !m_world->patches[static_cast<std::size_t>(p2)].active) return true;
  }
  return BodyNodeCollisionFilter::ignoresCollision(object1, object2);
}

int WorldImpl::register_skeleton(dd::SkeletonPtr skel, std::string file) {
  const int s = static_cast<int>(skeletons.size());
  SkeletonRecord rec;
  rec.name = skel->getName();
  rec.file = std::move(file);
  rec.skel = skel;
  for (std::size_t i = 0; i < skel->getNumBodyNodes(); ++i) {
    dd::BodyNode* node = skel->getBodyNode(i);
    const int b = static_cast<int>(bodies.size());
    bodies.push_back({rec.name + "/" + node->getName(), node, s, -1, {}});
    body_of_node.emplace(node, b);
    rec.bodies.push_back(b);
  }
  // Joint PD state: DART's implicit springs and dampers (URDF <dynamics damping>) move into
  // our stable PD and are zeroed in DART (see apply_stable_pd for why).
  const auto n = static_cast<Eigen::Index>(skel->getNumDofs());
  rec.pd_kp.resize(n);
  rec.pd_kd.resize(n);
  rec.pd_target.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    dd::DegreeOfFreedom* d = skel->getDof(static_cast<std::size_t>(i));
    rec.pd_kp[i] = d->getSpringStiffness();
    rec.pd_kd[i] = d->getDampingCoefficient();
    rec.pd_target[i] = d->getRestPosition();
    d->setSpringStiffness(0.0);
    d->setDampingCoefficient(0.0);
  }
  rec.pd_applied.resize(n);
  rec.pd_rhs.resize(n);
  rec.pd_qdd.resize(n);
  skeletons.push_back(std::move(rec));
  world->addSkeleton(skel);
  DEXCLOTH_DEMAND(world->getSkeleton(skeletons.back().name) == skel);
  return s;
}

int WorldImpl::body_index(const dd::BodyNode* node) const {
  const auto it = body_of_node.find(node);
  return it == body_of_node.end() ? -1 : it->second;
}

namespace {

/// Sets the joint damping coefficients of `skel` to `kd` (per DOF), or with `on` false to zero.
/// DART does not recompute its articulated inertias (which hold h·kd) for such a change by
/// itself.
void set_dampers(dd::Skeleton& skel, const Eigen::VectorXd& kd, bool on) {
  for (std::size_t i = 0; i < skel.getNumDofs(); ++i)
    skel.getDof(i)->setDampingCoefficient(on ? kd[static_cast<Eigen::Index>(i)] : 0.0);
  for (std::size_t t = 0; t < skel.getNumTrees(); ++t) skel.dirtyArticulatedInertia(t);
}

}  // namespace

void WorldImpl::apply_stable_pd() {
  // Stable PD (Tan, Liu, Turk 2011) with the skeleton's full dynamics, as explicit torques:
  //   τ = −Kp (q + h q̇ − q*) − Kd (q̇ + h q̈),  (M + h Kd) q̈ = τ_a + P − c(q, q̇) + τ_c,
  // P = −Kp (q + h q̇ − q*) − Kd q̇, τ_a the forces added for this step, c Coriolis and gravity,
  // τ_c the constraint (contact, joint limit) forces of the last step. DART's implicit joint
  // springs and dampers are not used in its step: DART integrates them with M + h D + h² K
  // but applies contact and limit impulses through M alone, so at rest a constraint force f
  // leaves (h D + h² K) M⁻¹ f pushing the other joints (0.2 rad on a ring finger with one joint
  // at its limit, fingertip contact forces attenuated by M (M + h D)⁻¹). Here the LCP sees the
  // whole torque; with τ_c in the prediction, at rest q̈ = 0 and τ = −Kp (q − q*) exactly.
  const double h = world->getTimeStep();
  for (auto& rec : skeletons) {
    const bool active = (rec.pd_kp.array() > 0.0).any() || (rec.pd_kd.array() > 0.0).any();
    if (!active || !rec.skel->isMobile()) continue;
    dd::Skeleton& skel = *rec.skel;
    const Eigen::VectorXd& q = skel.getPositions();
    const Eigen::VectorXd& qd = skel.getVelocities();
    // Explicit part at the predicted position.
    rec.pd_rhs = -rec.pd_kp.cwiseProduct(q + h * qd - rec.pd_target) - rec.pd_kd.cwiseProduct(qd);
    const Eigen::VectorXd& p = rec.pd_rhs;
    // Predicted acceleration with the damping implicit, by DART's articulated-body pass with
    // its joint dampers set to Kd for it alone: that pass solves (M + h D) q̈ = τ − D q̇ − c, so
    // τ = τ_a + p + τ_c + Kd q̇ gives the prediction in O(n), without forming M.
    rec.pd_applied = skel.getForces();
    set_dampers(skel, rec.pd_kd, true);
    skel.setForces(rec.pd_applied + p + skel.getConstraintForces() + rec.pd_kd.cwiseProduct(qd));
    skel.computeForwardDynamics();
    rec.pd_qdd = skel.getAccelerations();
    set_dampers(skel, rec.pd_kd, false);
    skel.setForces(rec.pd_applied + p - h * rec.pd_kd.cwiseProduct(rec.pd_qdd));
  }
}

void WorldImpl::park_patch(int i) {
  PatchRecord& p = patches[static_cast<std::size_t>(i)];
  p.active = false;
  auto& skel = *skeletons[static_cast<std::size_t>(p.skeleton)].skel;
  set_free_root_state(skel, p.X_W_park, Vec3::Zero(), Vec3::Zero());
  skel.setGravity(Vec3::Zero());
}

// A patch's box changes size every step. Through its skeleton's subscription, DART would
// rebuild the resized boxes' collision objects while iterating an unordered_map keyed by
// skeleton addresses, so Bullet's object and pair order (hence DART's contact order and the LCP
// solution) would depend on where the heap put the skeletons: the same scene gave different
// results for different output paths. As plain members of the group, the boxes are rebuilt here,
// one at a time in pool order.
void WorldImpl::detach_patch_shape(int i) {
  const auto& group = world->getConstraintSolver()->getCollisionGroup();
  const dd::ShapeNode* node = patch_shape_node(i);
  group->removeShapeFrame(node);  // also ends the skeleton's subscription
  group->addShapeFrame(node);
}

void WorldImpl::resize_patch(int i, const Vec3& size) {
  PatchRecord& p = patches[static_cast<std::size_t>(i)];
  if (p.box->getSize().isApprox(size)) return;
  p.box->setSize(size);
  const auto& group = world->getConstraintSolver()->getCollisionGroup();
  const dd::ShapeNode* node = patch_shape_node(i);
  group->removeShapeFrame(node);
  group->addShapeFrame(node);
}

const dd::ShapeNode* WorldImpl::patch_shape_node(int i) const {
  const PatchRecord& p = patches[static_cast<std::size_t>(i)];
  return bodies[static_cast<std::size_t>(p.body)].node->getShapeNode(0);
}

void set_free_root_state(dd::Skeleton& skel, const Eigen::Isometry3d& X_WB, const Vec3& v_W,
                         const Vec3& w_W) {
  auto* joint = dynamic_cast<dd::FreeJoint*>(skel.getRootJoint());
  DEXCLOTH_DEMAND(joint != nullptr);
  joint->setPositions(dd::FreeJoint::convertToPositions(X_WB));
  // FreeJoint velocities are the body's spatial velocity in body coordinates [ω_B; v_B].
  const Mat3 R_BW = X_WB.linear().transpose();
  Eigen::Matrix<double, 6, 1> qd;
  qd << R_BW * w_W, R_BW * v_W;
  joint->setVelocities(qd);
}

}  // namespace detail

// ---- construction ------------------------------------------------------------------------------

RigidWorld::RigidWorld(const RigidWorldOptions& options) : m_impl(std::make_unique<detail::WorldImpl>()) {
  DEXCLOTH_DEMAND(options.time_step > 0.0 && options.substeps >= 1 && options.max_contacts > 0 &&
                  options.patch_capacity >= 0);
  auto& w = *m_impl;
  w.options = options;
  w.world = dart::simulation::World::create("dexcloth_rigid");
  w.world->setTimeStep(options.time_step / options.substeps);
  w.world->setGravity(options.gravity_W);
  // Bullet detector (capsules exact), a larger contact cap, our filter.
  auto* solver = w.world->getConstraintSolver();
  solver->setCollisionDetector(dart::collision::BulletCollisionDetector::create());
  w.filter = std::make_shared<detail::CollisionFilter>(w);
  auto& option = solver->getCollisionOption();
  option.maxNumContacts = static_cast<std::size_t>(options.max_contacts);
  option.collisionFilter = w.filter;
  option.enableContact = true;
  // Penetration recovery (DART's contact settings are process-wide statics). The defaults
  // (ERP 0.01, at most 1 mm/s) leave a jaw that closed onto a thin cloth patch embedded in it for
  // seconds, so the jaws squeeze the cloth closer than its repulsion thickness on both sides
  // (paper §5: the patch's thickness is what keeps the body off the cloth). Here a penetration
  // beyond 0.25 mm is pushed out at 10% per step, up to 5 mm/s (faster makes a force-driven jaw
  // bounce off the light patch and the contact force come in spikes); the allowance keeps a
  // resting jaw in contact while the patch, rebuilt each step, jitters by a fraction of it.
  dart::constraint::ContactConstraint::setErrorReductionParameter(kContactErrorReduction);
  dart::constraint::ContactConstraint::setMaxErrorReductionVelocity(kContactMaxErrorVelocity);
  dart::constraint::ContactConstraint::setErrorAllowance(kContactErrorAllowance);
  // Patch pool: thin free boxes parked far below the scene, 1 m apart.
  w.pool = std::make_unique<PatchPool>(w);
  for (int i = 0; i < options.patch_capacity; ++i) {
    auto box = std::make_shared<dd::BoxShape>(Vec3(0.01, 0.01, 0.001));
    auto skel = make_free_body("patch_" + std::to_string(i), box, 1.0e-3, 1.0, Eigen::Isometry3d::Identity());
    detail::PatchRecord rec;
    rec.skeleton = static_cast<int>(w.skeletons.size());
    rec.box = box;
    rec.X_W_park.translation() = Vec3(1000.0 + static_cast<double>(i), 1000.0, -1000.0);
    skel->setName("patches_" + std::to_string(i));
    // Register under the "patches" namespace: body path "patches/patch_<i>".
    const int s = w.register_skeleton(skel, "");
    const int b = w.skeletons[static_cast<std::size_t>(s)].bodies.front();
    w.bodies[static_cast<std::size_t>(b)].name = "patches/patch_" + std::to_string(i);
    w.bodies[static_cast<std::size_t>(b)].patch = i;
    rec.body = b;
    w.patches.push_back(rec);
    w.detach_patch_shape(i);
    w.park_patch(i);
  }
}

RigidWorld::~RigidWorld() = default;
RigidWorld::RigidWorld(RigidWorld&&) noexcept = default;
RigidWorld& RigidWorld::operator=(RigidWorld&&) noexcept = default;

SkeletonId RigidWorld::add_urdf(const std::string& name, const std::string& urdf_path,
                                const UrdfOptions& options) {
  auto& w = *m_impl;
  // Check the file and the name before DART sees them.
  std::error_code ec;
  if (!std::filesystem::is_regular_file(urdf_path, ec)) reject(urdf_path, "URDF file not found");
  if (name.empty() || name.find('/') != std::string::npos) {
    reject(urdf_path, "skeleton name '" + name + "' must be non-empty and contain no '/'");
  }
  if (find_skeleton(name)) reject(urdf_path, "duplicate skeleton name '" + name + "'");
  // Parse with DART's URDF loader (urdfdom).
  dart::utils::DartLoader::Options loader_options;
  loader_options.mDefaultRootJointType = options.fixed_root
                                             ? dart::utils::DartLoader::RootJointType::FIXED
                                             : dart::utils::DartLoader::RootJointType::FLOATING;
  dart::utils::DartLoader loader(loader_options);
  const std::string absolute = std::filesystem::absolute(urdf_path, ec).string();
  dd::SkeletonPtr skel = loader.parseSkeleton(dart::common::Uri::createFromPath(absolute));
  if (!skel) reject(urdf_path, "malformed URDF (DART's URDF parser rejected it)");
  if (skel->getNumBodyNodes() == 0) reject(urdf_path, "URDF has no links");
  skel->setName(name);
  skel->setSelfCollisionCheck(options.self_collision);
  skel->setAdjacentBodyCheck(false);
  // Root placement: free root through its coordinates, welded root through its parent offset.
  dd::Joint* root = skel->getRootJoint();
  if (auto* free = dynamic_cast<dd::FreeJoint*>(root)) {
    free->setPositions(dd::FreeJoint::convertToPositions(options.X_WR));
  } else {
    root->setTransformFromParentBodyNode(options.X_WR * root->getTransformFromParentBodyNode());
  }
  // Joints: hard position limits; velocity and force limits are not used (controllers decide).
  for (std::size_t j = 0; j < skel->getNumJoints(); ++j) {
    dd::Joint* joint = skel->getJoint(j);
    joint->setLimitEnforcement(options.enforce_joint_limits && joint != root);
    for (std::size_t k = 0; k < joint->getNumDofs(); ++k) {
      joint->setVelocityLowerLimit(k, -kInf);
      joint->setVelocityUpperLimit(k, kInf);
      joint->setForceLowerLimit(k, -kInf);
      joint->setForceUpperLimit(k, kInf);
    }
  }
  // Collision shapes: cylinders become capsules (URDF has no capsule); friction on all.
  for (std::size_t i = 0; i < skel->getNumBodyNodes(); ++i) {
    dd::BodyNode* body = skel->getBodyNode(i);
    for (dd::ShapeNode* node : body->getShapeNodesWith<dd::CollisionAspect>()) {
      if (options.cylinders_as_capsules) {
        if (auto cyl = std::dynamic_pointer_cast<dd::CylinderShape>(node->getShape())) {
          node->setShape(std::make_shared<dd::CapsuleShape>(cyl->getRadius(), cyl->getHeight()));
        }
      }
      if (!node->getDynamicsAspect()) node->createDynamicsAspect();
      node->getDynamicsAspect()->setFrictionCoeff(options.friction);
    }
  }
  return SkeletonId{w.register_skeleton(skel, urdf_path)};
}

SkeletonId RigidWorld::add_prop(const PropSpec& prop) {
  auto& w = *m_impl;
  const std::string where = "prop '" + prop.name + "'";
  if (prop.name.empty() || prop.name.find('/') != std::string::npos) {
    reject(prop.mesh_path, where + ": name must be non-empty and contain no '/'");
  }
  if (find_skeleton(prop.name)) reject(prop.mesh_path, where + ": duplicate skeleton name");
  if (!(prop.mass >= 0.0) || !(prop.friction >= 0.0)) reject(prop.mesh_path, where + ": mass and friction must be ≥ 0");
  // Shape and its offset in the body frame.
  std::shared_ptr<dd::Shape> shape;
  Eigen::Isometry3d X_BS = Eigen::Isometry3d::Identity();
  using S = PropSpec::Shape;
  switch (prop.shape) {
    case S::box:
      if (!(prop.size.minCoeff() > 0.0)) reject("", where + ": box size must be > 0");
      shape = std::make_shared<dd::BoxShape>(prop.size);
      break;
    case S::plane: {
      if (!(prop.size.x() > 0.0 && prop.size.y() > 0.0)) reject("", where + ": plane size must be > 0");
      constexpr double kThickness = 0.05;
      shape = std::make_shared<dd::BoxShape>(Vec3(prop.size.x(), prop.size.y(), kThickness));
      X_BS.translation().z() = -0.5 * kThickness;
      break;
    }
    case S::sphere:
      if (!(prop.radius > 0.0)) reject("", where + ": radius must be > 0");
      shape = std::make_shared<dd::SphereShape>(prop.radius);
      break;
    case S::capsule:
    case S::cylinder:
      if (!(prop.radius > 0.0 && prop.length >= 0.0)) reject("", where + ": radius must be > 0, length ≥ 0");
      if (prop.shape == S::capsule) {
        shape = std::make_shared<dd::CapsuleShape>(prop.radius, prop.length);
      } else {
        shape = std::make_shared<dd::CylinderShape>(prop.radius, prop.length);
      }
      break;
    case S::mesh: {
      std::error_code ec;
      if (!std::filesystem::is_regular_file(prop.mesh_path, ec)) reject(prop.mesh_path, where + ": mesh file not found");
      const aiScene* scene = dd::MeshShape::loadMesh(std::filesystem::absolute(prop.mesh_path, ec).string());
      if (scene == nullptr) reject(prop.mesh_path, where + ": cannot read mesh");
      if (const std::string problem = mesh_problem(*scene); !problem.empty()) {
        aiReleaseImport(scene);  // a MeshShape would own it
        reject(prop.mesh_path, where + ": " + problem);
      }
      shape = std::make_shared<dd::MeshShape>(prop.mesh_scale, scene);
      break;
    }
  }
  auto skel = make_free_body(prop.name, shape, prop.mass, prop.friction, X_BS);
  for (std::size_t k = 1; k < prop.motion.size(); ++k) {
    if (!(prop.motion[k].t > prop.motion[k - 1].t)) reject("", where + ": keyframe times must increase");
  }
  const bool dynamic = prop.mass > 0.0;
  skel->setMobile(dynamic);
  const PoseSample start = prop.motion.empty() ? PoseSample{prop.X_WP, Vec3::Zero(), Vec3::Zero()} : sample_pose(prop.motion, 0.0);
  detail::set_free_root_state(*skel, start.X_WF, start.v_W, start.w_W);
  const int s = w.register_skeleton(skel, prop.shape == S::mesh ? prop.mesh_path : "");
  if (!dynamic) w.skeletons[static_cast<std::size_t>(s)].motion = prop.motion;
  return SkeletonId{s};
}

// ---- time --------------------------------------------------------------------------------------

void RigidWorld::step() {
  auto& w = *m_impl;
  for (auto& b : w.bodies) b.contacts.clear();
  w.num_contacts = 0;
  // The forces added for this step act over all its substeps (zero-order hold).
  const int substeps = w.options.substeps;
  if (substeps > 1) {
    w.held_forces.resize(w.skeletons.size());
    for (std::size_t s = 0; s < w.skeletons.size(); ++s)
      w.held_forces[s] = w.skeletons[s].skel->getForces();
  }
  for (int k = 0; k < substeps; ++k) {
    if (k > 0)
      for (std::size_t s = 0; s < w.skeletons.size(); ++s)
        w.skeletons[s].skel->setForces(w.held_forces[s]);
    w.apply_stable_pd();
    w.world->step(k + 1 == substeps);
    w.record_contacts(1.0 / substeps);
    // Keyframed props move to their pose at the new time.
    const double t = w.world->getTime();
    for (auto& s : w.skeletons) {
      if (s.motion.empty()) continue;
      const PoseSample p = sample_pose(s.motion, t);
      detail::set_free_root_state(*s.skel, p.X_WF, p.v_W, p.w_W);
    }
  }
  ++w.steps;
}

void detail::WorldImpl::record_contacts(double weight) {
  // Contacts with forces, per body, before anything in the world changes (paper §4.1). Over
  // substeps, each substep's contacts with its share of the step's mean force.
  const auto& result = world->getLastCollisionResult();
  num_contacts = std::max(num_contacts, static_cast<int>(result.getNumContacts()));
  for (const auto& c : result.getContacts()) {
    const auto* s1 = c.collisionObject1->getShapeFrame()->asShapeNode();
    const auto* s2 = c.collisionObject2->getShapeFrame()->asShapeNode();
    if (s1 == nullptr || s2 == nullptr) continue;
    const int b1 = body_index(s1->getBodyNodePtr().get());
    const int b2 = body_index(s2->getBodyNodePtr().get());
    // DART: normal from body 2 to body 1, force acts on body 1.
    ContactPoint cp;
    cp.p_W = c.point;
    cp.depth = c.penetrationDepth;
    const Vec3 f = weight * c.force;
    if (b1 >= 0) {
      cp.n_W = c.normal;
      cp.f_W = f;
      cp.f_n = std::max(0.0, f.dot(c.normal));
      cp.other = BodyId{b2};
      bodies[static_cast<std::size_t>(b1)].contacts.push_back(cp);
    }
    if (b2 >= 0) {
      cp.n_W = -c.normal;
      cp.f_W = -f;
      cp.f_n = std::max(0.0, f.dot(c.normal));
      cp.other = BodyId{b1};
      bodies[static_cast<std::size_t>(b2)].contacts.push_back(cp);
    }
  }
}

double RigidWorld::time() const { return m_impl->world->getTime(); }
double RigidWorld::time_step() const { return m_impl->options.time_step; }
double RigidWorld::contact_allowance() const { return kContactErrorAllowance; }
int RigidWorld::substeps() const { return m_impl->options.substeps; }
long RigidWorld::step_count() const { return m_impl->steps; }

// ---- lookup ------------------------------------------------------------------------------------

int RigidWorld::num_skeletons() const { return static_cast<int>(m_impl->skeletons.size()); }

std::optional<SkeletonId> RigidWorld::find_skeleton(std::string_view name) const {
  const auto& sk = m_impl->skeletons;
  for (std::size_t i = 0; i < sk.size(); ++i) {
    if (sk[i].name == name) return SkeletonId{static_cast<int>(i)};
  }
  return std::nullopt;
}

SkeletonId RigidWorld::skeleton(std::string_view name) const {
  if (auto s = find_skeleton(name)) return *s;
  reject("", "no skeleton named '" + std::string(name) + "'");
}

const std::string& RigidWorld::skeleton_name(SkeletonId s) const {
  return m_impl->skeletons.at(static_cast<std::size_t>(s.index)).name;
}

const std::string& RigidWorld::skeleton_file(SkeletonId s) const {
  return m_impl->skeletons.at(static_cast<std::size_t>(s.index)).file;
}

std::optional<BodyId> RigidWorld::find_body(std::string_view path) const {
  const auto& bodies = m_impl->bodies;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (bodies[i].name == path) return BodyId{static_cast<int>(i)};
  }
  return std::nullopt;
}

BodyId RigidWorld::body(std::string_view path) const {
  if (auto b = find_body(path)) return *b;
  // Name the file of the skeleton the path points into, when there is one.
  const auto slash = path.find('/');
  std::string file;
  if (slash != std::string_view::npos) {
    if (auto s = find_skeleton(path.substr(0, slash))) file = skeleton_file(*s);
  }
  reject(file, "no body '" + std::string(path) + "' (expected \"skeleton/body_node\")");
}

BodyId RigidWorld::body(SkeletonId s, std::string_view body_node) const {
  const auto& rec = m_impl->skeletons.at(static_cast<std::size_t>(s.index));
  for (int b : rec.bodies) {
    if (m_impl->bodies[static_cast<std::size_t>(b)].node->getName() == body_node) return BodyId{b};
  }
  reject(rec.file, "skeleton '" + rec.name + "' has no body node '" + std::string(body_node) + "'");
}

int RigidWorld::num_bodies() const { return static_cast<int>(m_impl->bodies.size()); }

const std::string& RigidWorld::body_name(BodyId b) const {
  return m_impl->bodies.at(static_cast<std::size_t>(b.index)).name;
}

SkeletonId RigidWorld::body_skeleton(BodyId b) const {
  return SkeletonId{m_impl->bodies.at(static_cast<std::size_t>(b.index)).skeleton};
}

std::vector<BodyId> RigidWorld::skeleton_bodies(SkeletonId s) const {
  std::vector<BodyId> out;
  for (int b : m_impl->skeletons.at(static_cast<std::size_t>(s.index)).bodies) out.push_back(BodyId{b});
  return out;
}

BodyId RigidWorld::root_body(SkeletonId s) const {
  return BodyId{m_impl->skeletons.at(static_cast<std::size_t>(s.index)).bodies.front()};
}

// ---- generalized coordinates -------------------------------------------------------------------

namespace {
dd::Skeleton& skel_of(const detail::WorldImpl& w, SkeletonId s) {
  return *w.skeletons.at(static_cast<std::size_t>(s.index)).skel;
}
dd::BodyNode& node_of(const detail::WorldImpl& w, BodyId b) {
  return *w.bodies.at(static_cast<std::size_t>(b.index)).node;
}
}  // namespace

int RigidWorld::num_dofs(SkeletonId s) const { return static_cast<int>(skel_of(*m_impl, s).getNumDofs()); }

std::optional<int> RigidWorld::find_dof(SkeletonId s, std::string_view joint, int k) const {
  const dd::Joint* j = skel_of(*m_impl, s).getJoint(std::string(joint));
  if (j == nullptr || k < 0 || static_cast<std::size_t>(k) >= j->getNumDofs()) return std::nullopt;
  return static_cast<int>(j->getDof(static_cast<std::size_t>(k))->getIndexInSkeleton());
}

int RigidWorld::dof_index(SkeletonId s, std::string_view joint, int k) const {
  if (auto i = find_dof(s, joint, k)) return *i;
  const auto& rec = m_impl->skeletons.at(static_cast<std::size_t>(s.index));
  reject(rec.file, "skeleton '" + rec.name + "' has no joint '" + std::string(joint) + "' with DOF " + std::to_string(k));
}

std::string RigidWorld::dof_name(SkeletonId s, int i) const {
  return skel_of(*m_impl, s).getDof(static_cast<std::size_t>(i))->getName();
}

std::string RigidWorld::dof_joint(SkeletonId s, int i) const {
  return skel_of(*m_impl, s).getDof(static_cast<std::size_t>(i))->getJoint()->getName();
}

int RigidWorld::root_dofs(SkeletonId s) const {
  return static_cast<int>(skel_of(*m_impl, s).getRootJoint()->getNumDofs());
}

Eigen::VectorXd RigidWorld::positions(SkeletonId s) const { return skel_of(*m_impl, s).getPositions(); }
Eigen::VectorXd RigidWorld::velocities(SkeletonId s) const { return skel_of(*m_impl, s).getVelocities(); }

void RigidWorld::set_positions(SkeletonId s, const Eigen::VectorXd& q) {
  DEXCLOTH_DEMAND(q.size() == num_dofs(s) && q.allFinite());
  skel_of(*m_impl, s).setPositions(q);
}

void RigidWorld::set_velocities(SkeletonId s, const Eigen::VectorXd& qd) {
  DEXCLOTH_DEMAND(qd.size() == num_dofs(s) && qd.allFinite());
  skel_of(*m_impl, s).setVelocities(qd);
}

Eigen::VectorXd RigidWorld::position_lower_limits(SkeletonId s) const {
  return skel_of(*m_impl, s).getPositionLowerLimits();
}
Eigen::VectorXd RigidWorld::position_upper_limits(SkeletonId s) const {
  return skel_of(*m_impl, s).getPositionUpperLimits();
}

void RigidWorld::add_forces(SkeletonId s, const Eigen::VectorXd& tau) {
  auto& skel = skel_of(*m_impl, s);
  DEXCLOTH_DEMAND(tau.size() == static_cast<Eigen::Index>(skel.getNumDofs()) && tau.allFinite());
  skel.setForces(skel.getForces() + tau);
}

Eigen::VectorXd RigidWorld::forces(SkeletonId s) const { return skel_of(*m_impl, s).getForces(); }

void RigidWorld::set_joint_pd(SkeletonId s, int dof, double kp, double kd, double q_target) {
  DEXCLOTH_DEMAND(kp >= 0.0 && kd >= 0.0 && std::isfinite(q_target));
  dd::DegreeOfFreedom* d = skel_of(*m_impl, s).getDof(static_cast<std::size_t>(dof));
  DEXCLOTH_DEMAND(d != nullptr);
  auto& rec = m_impl->skeletons.at(static_cast<std::size_t>(s.index));
  rec.pd_kp[dof] = kp;
  rec.pd_kd[dof] = kd;
  rec.pd_target[dof] = q_target;
}

Eigen::VectorXd RigidWorld::gravity_compensation(SkeletonId s) const {
  return skel_of(*m_impl, s).getGravityForces();
}

double RigidWorld::mass(SkeletonId s) const { return skel_of(*m_impl, s).getMass(); }

// ---- bodies ------------------------------------------------------------------------------------

Eigen::Isometry3d RigidWorld::pose_W(BodyId b) const { return node_of(*m_impl, b).getWorldTransform(); }

Vec3 RigidWorld::point_W(BodyId b, const Vec3& p_B) const { return node_of(*m_impl, b).getWorldTransform() * p_B; }

Vec3 RigidWorld::point_velocity_W(BodyId b, const Vec3& p_B) const {
  return node_of(*m_impl, b).getLinearVelocity(p_B, dd::Frame::World(), dd::Frame::World());
}

Vec3 RigidWorld::angular_velocity_W(BodyId b) const {
  return node_of(*m_impl, b).getAngularVelocity(dd::Frame::World(), dd::Frame::World());
}

Vec3 RigidWorld::com_W(BodyId b) const { return node_of(*m_impl, b).getCOM(dd::Frame::World()); }

double RigidWorld::body_mass(BodyId b) const { return node_of(*m_impl, b).getMass(); }

Eigen::MatrixXd RigidWorld::point_jacobian_W(BodyId b, const Vec3& p_B) const {
  const auto& node = node_of(*m_impl, b);
  return node.getSkeleton()->getLinearJacobian(&node, p_B, dd::Frame::World());
}

Eigen::MatrixXd RigidWorld::jacobian_W(BodyId b, const Vec3& p_B) const {
  const auto& node = node_of(*m_impl, b);
  return node.getSkeleton()->getWorldJacobian(&node, p_B);
}

void RigidWorld::add_force_at(BodyId b, const Vec3& p_B, const Vec3& f_W) {
  add_forces(body_skeleton(b), point_jacobian_W(b, p_B).transpose() * f_W);
}

void RigidWorld::add_wrench_at(BodyId b, const Vec3& p_B, const Vec3& f_W, const Vec3& t_W) {
  Vec6 wrench;
  wrench << t_W, f_W;
  add_forces(body_skeleton(b), jacobian_W(b, p_B).transpose() * wrench);
}

void RigidWorld::set_friction(BodyId b, double mu) {
  DEXCLOTH_DEMAND(mu >= 0.0);
  for (dd::ShapeNode* node : node_of(*m_impl, b).getShapeNodesWith<dd::CollisionAspect>()) {
    if (!node->getDynamicsAspect()) node->createDynamicsAspect();
    node->getDynamicsAspect()->setFrictionCoeff(mu);
  }
}

double RigidWorld::friction(BodyId b) const {
  for (const dd::ShapeNode* node : node_of(*m_impl, b).getShapeNodesWith<dd::CollisionAspect>()) {
    if (node->getDynamicsAspect()) return node->getDynamicsAspect()->getFrictionCoeff();
  }
  return 0.0;
}

void RigidWorld::set_free_body_state(BodyId b, const Eigen::Isometry3d& X_WB, const Vec3& v_W, const Vec3& w_W) {
  auto& node = node_of(*m_impl, b);
  DEXCLOTH_DEMAND(node.getSkeleton()->getNumBodyNodes() == 1);
  detail::set_free_root_state(*node.getSkeleton(), X_WB, v_W, w_W);
}

// ---- contacts ----------------------------------------------------------------------------------

const std::vector<ContactPoint>& RigidWorld::contacts(BodyId b) const {
  return m_impl->bodies.at(static_cast<std::size_t>(b.index)).contacts;
}

Vec3 RigidWorld::contact_force_W(BodyId b) const {
  Vec3 f = Vec3::Zero();
  for (const auto& c : contacts(b)) f += c.f_W;
  return f;
}

double RigidWorld::normal_force_sum(BodyId b) const {
  double f = 0.0;
  for (const auto& c : contacts(b)) f += c.f_n;
  return f;
}

int RigidWorld::num_contacts() const { return m_impl->num_contacts; }

// ---- patches, obstacle meshes, probes ----------------------------------------------------------

PatchPool& RigidWorld::patches() { return *m_impl->pool; }
const PatchPool& RigidWorld::patches() const { return *m_impl->pool; }

void RigidWorld::export_obstacle_meshes(std::vector<ObstacleMesh>& meshes) const {
  auto& w = *m_impl;
  // Body-frame meshes of the exportable bodies, built once per set of skeletons.
  if (w.obstacle_cache_bodies != w.bodies.size()) {
    w.obstacle_bodies.clear();
    w.obstacle_local.clear();
    for (std::size_t i = 0; i < w.bodies.size(); ++i) {
      const auto& b = w.bodies[i];
      if (b.patch >= 0) continue;
      LocalMesh local;
      for (const dd::ShapeNode* sn : b.node->getShapeNodesWith<dd::CollisionAspect>()) {
        if (auto part = tessellate(*sn->getShape())) append_mesh(local, *part, sn->getRelativeTransform());
      }
      if (local.x.rows() == 0) continue;
      w.obstacle_bodies.push_back(static_cast<int>(i));
      w.obstacle_local.push_back(std::move(local));
    }
    w.obstacle_cache_bodies = w.bodies.size();
  }
  // Topology into `meshes` unless it already matches.
  const std::size_t n = w.obstacle_bodies.size();
  bool reuse = meshes.size() == n;
  for (std::size_t k = 0; reuse && k < n; ++k) {
    reuse = meshes[k].name == w.bodies[static_cast<std::size_t>(w.obstacle_bodies[k])].name &&
            meshes[k].x.rows() == w.obstacle_local[k].x.rows();
  }
  if (!reuse) {
    meshes.assign(n, ObstacleMesh{});
    for (std::size_t k = 0; k < n; ++k) {
      meshes[k].name = w.bodies[static_cast<std::size_t>(w.obstacle_bodies[k])].name;
      meshes[k].faces = w.obstacle_local[k].faces;
      meshes[k].x.resize(w.obstacle_local[k].x.rows(), 3);
      meshes[k].v.resize(w.obstacle_local[k].x.rows(), 3);
    }
  }
  // World positions and rigid-body velocities v = v_o + ω × (x − o).
  for (std::size_t k = 0; k < n; ++k) {
    const BodyId b{w.obstacle_bodies[k]};
    const dd::BodyNode& node = node_of(w, b);
    const Eigen::Isometry3d X_WB = node.getWorldTransform();
    const Vec3 v_o = node.getLinearVelocity(dd::Frame::World(), dd::Frame::World());
    const Vec3 w_W = node.getAngularVelocity(dd::Frame::World(), dd::Frame::World());
    const Points& local = w.obstacle_local[k].x;
    ObstacleMesh& out = meshes[k];
    for (Eigen::Index i = 0; i < local.rows(); ++i) {
      const Vec3 r_W = X_WB.linear() * local.row(i).transpose();
      out.x.row(i) = (X_WB.translation() + r_W).transpose();
      out.v.row(i) = (v_o + w_W.cross(r_W)).transpose();
    }
    out.friction = friction(b);
  }
}

Vec3 RigidWorld::probe_W(std::string_view body_path, const Vec3& p_B) const { return point_W(body(body_path), p_B); }

}  // namespace dexcloth::rigid
