#include "core/linkage/read_flexible_body.hpp"

#include <cmath>
#include <stdexcept>

#include "core/linkage/make_body.hpp"
#include "core/scenes/parts.hpp"

namespace rodend::linkage {
namespace {

/// A whole number in [lo, hi].
int read_count(const ParameterSet& p, const std::string& path, int lo, int hi) {
  const double v = p.number(path);
  if (!(v >= lo && v <= hi) || v != std::floor(v))
    throw InputError(path, "expected a whole number from " + std::to_string(lo) + " to " +
                               std::to_string(hi) + ", got " + format_number(v));
  return static_cast<int>(v);
}

}  // namespace

std::unique_ptr<FlexibleBody> make_flexible_body(const ParameterSet& p, const std::string& prefix,
                                                 std::vector<Eigen::Vector2d> points) {
  const Eigen::Vector2d a = read_plane_point(p, prefix + ".axis_start");
  const Eigen::Vector2d b = read_plane_point(p, prefix + ".axis_end");
  if (!((b - a).norm() > 0.0))
    throw InputError(prefix + ".axis_end", "expected a point other than axis_start");
  BeamModes::Spec spec;
  spec.segments = {{(b - a).norm(), read_positive(p, prefix + ".section.area"),
                    read_positive(p, prefix + ".section.second_moment")}};
  spec.material = {read_positive(p, prefix + ".material.youngs_modulus"),
                   read_positive(p, prefix + ".material.density")};
  spec.support = read_choice<BeamSupport>(p, prefix + ".boundary_conditions");
  spec.elements = read_count(p, prefix + ".elements", 1, 400);
  // the mesh's dofs bound the modes: 2 per node for bending, 1 for the axial
  spec.bending_modes = read_count(p, prefix + ".bending_modes", 0, spec.elements);
  spec.axial_modes = read_count(p, prefix + ".axial_modes", 0, spec.elements - 1);
  if (spec.bending_modes + spec.axial_modes == 0)
    throw InputError(prefix + ".bending_modes",
                     "expected at least one mode (a body without modes is kind \"rigid\")");
  const double zeta = read_positive(p, prefix + ".damping_ratio", true);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double s = (points[i] - a).dot((b - a).normalized());
    if (s < -1e-9 * spec.segments[0].length || s > spec.segments[0].length * (1 + 1e-9))
      throw InputError(prefix + ".points",
                       "expected every point within the beam's span from axis_start to axis_end "
                       "(point " +
                           std::to_string(i) + " is " + format_number(s) + " m along it)");
  }
  return std::make_unique<FlexibleBody>(BeamModes::compute(spec), a, b, points, zeta);
}

}  // namespace rodend::linkage
