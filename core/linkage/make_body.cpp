// The body factory: one line per kind of body.
#include "core/linkage/make_body.hpp"

#include "core/linkage/linkage_choices.hpp"
#include "core/linkage/read_flexible_body.hpp"
#include "core/linkage/rigid_body.hpp"
#include "core/scenes/parts.hpp"

namespace rodend::linkage {
namespace {

/// kind "rigid": mass [kg], inertia [kg m^2] about the mass centre, center_of_mass [m].
std::unique_ptr<Body> make_rigid_body(const ParameterSet& p, const std::string& prefix,
                                      std::vector<Eigen::Vector2d> points) {
  const double mass = read_positive(p, prefix + ".mass");
  const double inertia = read_positive(p, prefix + ".inertia");
  const Eigen::Vector2d com = read_plane_point(p, prefix + ".center_of_mass");
  return std::make_unique<RigidBody>(mass, inertia, com, std::move(points));
}

}  // namespace

Eigen::Vector2d read_plane_point(const ParameterSet& p, const std::string& path) {
  const Vec3 v = p.vec3(path);
  if (v.z() != 0.0) throw InputError(path, "expected a point of the plane, z = 0 [m]");
  return {v.x(), v.y()};
}

std::unique_ptr<Body> make_body(const ParameterSet& p, const std::string& prefix,
                                const std::vector<std::string>& point_names) {
  std::vector<Eigen::Vector2d> points;
  for (const std::string& n : point_names)
    points.push_back(read_plane_point(p, prefix + ".points." + n));
  // a new kind of body: its line in core/linkage/body_kinds.def and its case here
  switch (read_choice<BodyKind>(p, prefix + ".kind")) {
    case BodyKind::rigid:
      return make_rigid_body(p, prefix, std::move(points));
    case BodyKind::flexible:
      return make_flexible_body(p, prefix, std::move(points));
  }
  throw InputError(prefix + ".kind", "a kind of body without its maker");
}

}  // namespace rodend::linkage
