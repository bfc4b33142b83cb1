#pragma once
/// Shared fixtures for the rigid tests: asset paths and small scenes.
#include <string>

#include "rigid/world.hpp"

namespace dexcloth::rigid::test {

inline std::string asset(const std::string& name) { return std::string(DEXCLOTH_SOURCE_DIR) + "/assets/hands/" + name; }

/// A table: a plane prop with its top face at z = 0.
inline SkeletonId add_table(RigidWorld& world, double friction = 1.0) {
  PropSpec table;
  table.name = "table";
  table.shape = PropSpec::Shape::plane;
  table.size = Vec3(2.0, 2.0, 0.0);
  table.friction = friction;
  return world.add_prop(table);
}

/// A dynamic box of full extents `size` [m] and `mass` [kg] centred at `center_W`.
inline SkeletonId add_box(RigidWorld& world, const std::string& name, const Vec3& size, double mass,
                          const Vec3& center_W, double friction = 1.0) {
  PropSpec box;
  box.name = name;
  box.shape = PropSpec::Shape::box;
  box.size = size;
  box.mass = mass;
  box.friction = friction;
  box.X_WP.translation() = center_W;
  return world.add_prop(box);
}

}  // namespace dexcloth::rigid::test
