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
  int cloth{-1};   ///< cloth index, or -1 for a body probe
  int vertex{-1};  ///< cloth vertex index
};

/// A compiled scene: world model, its initial data, and resolved probes.
struct CompiledScene {
  coupling::WorldModel model;
  std::vector<CompiledProbe> probes;
};

/// Builds meshes, models and handles. Throws InputRejected (naming the scene file and the JSON
/// pointer) for problems only visible once meshes are loaded: an OBJ that does not parse, a handle
/// index past the mesh, a handle box that selects nothing, a degenerate rest triangle.
CompiledScene compile_scene(const SceneSpec& spec);

}  // namespace dexcloth::scene
