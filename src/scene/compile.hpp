#pragma once
/// Compiles a validated SceneSpec into the world's model and initial data.
#include <string>
#include <vector>

#include "coupling/world.hpp"
#include "scene/spec.hpp"

namespace dexcloth::scene {

/// A probe resolved to something trackable.
struct CompiledProbe {
  std::string name;
  int cloth{-1};        ///< cloth index, or -1 for a body probe
  int vertex{-1};       ///< cloth vertex index
  std::string body;     ///< "skeleton/body_node" of a body probe
  Vec3 point{Vec3::Zero()};  ///< point in the body's frame [m]
};

/// A compiled scene: world model, its initial data, and resolved probes.
struct CompiledScene {
  coupling::WorldModel model;
  coupling::WorldData data;
  std::vector<CompiledProbe> probes;
};

/// Builds meshes, models and handles, and the rigid world: scene obstacles as DART props, `bodies`
/// as DART skeletons with their controllers. Throws InputRejected (naming the scene file and the
/// JSON pointer) for problems only visible here: an OBJ that does not parse, a handle index past
/// the mesh, a handle box that selects nothing, a degenerate rest triangle, a bad body spec or
/// URDF, a probe on an unknown body.
CompiledScene compile_scene(const SceneSpec& spec);

}  // namespace dexcloth::scene
