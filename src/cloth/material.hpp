#pragma once
/// Cloth material: areal density, membrane, bending and damping parameters (DESIGN.md, cloth).

namespace dexcloth::cloth {

/// Isotropic cloth material. The cloth is a surface: density is per area, the membrane
/// stiffness is Young's modulus times thickness.
struct Material {
  double density{0.15};            ///< areal density [kg/m²]
  double youngs_modulus{5e5};      ///< Young's modulus of the 3D material [Pa]
  double poisson{0.3};             ///< Poisson ratio [-], in [0, 0.5)
  double thickness{1e-3};          ///< thickness [m]
  double bending_stiffness{1e-6};  ///< plate bending stiffness D [N·m]
  double damping{0.005};           ///< stiffness-proportional damping β [s]: f_d = −β·K·v
  double friction{0.5};            ///< Coulomb friction coefficient μ [-] (used by contacts)
};

}  // namespace dexcloth::cloth
