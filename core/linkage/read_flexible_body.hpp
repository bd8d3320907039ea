#pragma once
// The flexible body of a linkage part file (kind "flexible", docs/flexible-bodies.md): its beam's
// section, material, modes and boundary conditions, read from the keys under a body's prefix.
#include <memory>
#include <string>
#include <vector>

#include "core/linkage/flexible_body.hpp"
#include "core/params.hpp"

namespace rodend::linkage {

/// The flexible body under `prefix` with its material points `points` (body frame [m]). Keys:
///   axis_start, axis_end        the beam's ends s = 0 and s = L in the body frame [m]
///   section.area [m^2], section.second_moment [m^4] (about the axis normal to the plane)
///   material.youngs_modulus [Pa], material.density [kg/m^3]
///   boundary_conditions         core/linkage/beam_supports.def
///   bending_modes, axial_modes  how many of each, elements (along the beam)
///   damping_ratio               each mode's zeta [-]
/// Throws InputError naming the key.
std::unique_ptr<FlexibleBody> make_flexible_body(const ParameterSet& p, const std::string& prefix,
                                                 std::vector<Eigen::Vector2d> points);

}  // namespace rodend::linkage
