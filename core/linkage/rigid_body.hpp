#pragma once
// A rigid planar body of the linkage (docs/planar-linkage.md): mass, moment of inertia about
// the mass centre, the mass centre and the material points in the body frame. Its coordinates
// are the body frame's origin x, y [m] and angle phi [rad] (core/linkage/body.hpp).
#include <vector>

#include "core/linkage/body.hpp"

namespace rodend::linkage {

class RigidBody final : public Body {
 public:
  /// mass [kg] > 0, inertia [kg m^2] > 0 about the mass centre, centre_of_mass and points in
  /// the body frame [m].
  RigidBody(double mass, double inertia, const Eigen::Vector2d& centre_of_mass,
            std::vector<Eigen::Vector2d> points);

  int coordinate_count() const override { return 3; }
  int point_count() const override { return static_cast<int>(points_.size()); }
  Eigen::MatrixXd mass_matrix(ConstVectorRef q) const override;
  Eigen::VectorXd internal_forces(ConstVectorRef q, ConstVectorRef qdot,
                                  const Eigen::Vector2d& gravity) const override;
  PointKinematics point(int index, ConstVectorRef q, ConstVectorRef qdot) const override;
  double kinetic_energy(ConstVectorRef q, ConstVectorRef qdot) const override;
  double potential_energy(ConstVectorRef q, const Eigen::Vector2d& gravity) const override;

  double mass() const { return mass_; }
  double inertia() const { return inertia_; }

 private:
  /// Kinematics of a body-frame position (a point or the mass centre).
  PointKinematics at(const Eigen::Vector2d& local, ConstVectorRef q, ConstVectorRef qdot) const;
  double mass_, inertia_;
  Eigen::Vector2d com_;
  std::vector<Eigen::Vector2d> points_;
};

}  // namespace rodend::linkage
