#pragma once
/// The mutable cloth state: positions, velocities, external forces and solver scratch
/// (STYLE.md, model/data split).
#include <memory>

#include "cloth/model.hpp"
#include "core/types.hpp"

namespace dexcloth::cloth {

struct DynamicsWorkspace;  // defined in cloth/dynamics_workspace.hpp

/// Owner of the implicit solver's buffers (system values, factorisation, vectors), allocated on
/// the first step. Copies start empty (the buffers are rebuilt on the copy's first step), so a
/// ClothState can be copied to checkpoint a run.
class DynamicsScratch {
 public:
  DynamicsScratch();
  ~DynamicsScratch();
  DynamicsScratch(const DynamicsScratch&);
  DynamicsScratch& operator=(const DynamicsScratch&);
  DynamicsScratch(DynamicsScratch&&) noexcept;
  DynamicsScratch& operator=(DynamicsScratch&&) noexcept;

  /// The workspace, created empty on first use.
  DynamicsWorkspace& get();

 private:
  std::unique_ptr<DynamicsWorkspace> m_workspace;
};

/// Mutable state of one cloth.
struct ClothState {
  Points x;      ///< |V|×3 positions [m]
  Points v;      ///< |V|×3 velocities [m/s]
  Points f_ext;  ///< |V|×3 extra forces [N] added by the dynamics each step; caller-owned
  /// |V|×3 impulse [N·s] each velocity constraint applied in the last solve (zero for free
  /// vertices): what holding the vertex at its prescribed velocity took, e.g. from friction.
  Points constraint_impulse;
  DynamicsScratch scratch;  ///< solver buffers
};

/// State of `model` at positions `x0` (|V|×3) [m], at rest (v = 0) and with f_ext = 0.
ClothState make_state(const ClothModel& model, const Points& x0);

}  // namespace dexcloth::cloth
