#pragma once
// One body of the planar linkage (the planar-linkage scene family, docs/planar-linkage.md): its
// generalised coordinates, mass matrix, internal forces and the kinematics of its material
// points. The contract between the linkage assembly (joints, drives, the scene) and the kinds
// of body (rigid, flexible by modal reduction in a floating frame).
//
// Coordinates of every body start with its floating frame: x, y of the frame origin [m] and the
// frame angle phi [rad], in the world's xy-plane. A rigid body has only these three; a
// flexible body adds its modal amplitudes (the mode shapes carry the units, the amplitudes are
// dimensionless or [m] as the body documents).
//
// Points are declared when the body is built (joint points, the mass centre, sensor points),
// in the body frame of the undeformed body [m], and addressed by their index from then on, so a
// flexible body can precompute its mode shapes there.
#include <Eigen/Dense>

namespace rodend::linkage {

using ConstVectorRef = Eigen::Ref<const Eigen::VectorXd>;

/// Where a material point is and how it moves, with what the assembly needs to project forces
/// and constraints onto the body's coordinates.
struct PointKinematics {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  ///< world position [m]
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();  ///< world velocity [m/s]
  /// d position / d q (2 x coordinate_count()): projects a force [N] on the point onto the
  /// body's generalised forces, Q = J^T F.
  Eigen::Matrix<double, 2, Eigen::Dynamic> jacobian;
  /// (dJ/dt) q': the velocity-product part of the point's acceleration [m/s^2].
  Eigen::Vector2d jacobian_dot_qdot = Eigen::Vector2d::Zero();
  double angle = 0.0;             ///< rotation of the material cross-section there [rad]
  double angular_velocity = 0.0;  ///< its rate [rad/s]
  /// d angle / d q (1 x coordinate_count()): projects a moment [N m] on the point.
  Eigen::RowVectorXd angle_jacobian;
  double angle_jacobian_dot_qdot = 0.0;  ///< velocity-product angular acceleration [rad/s^2]
};

class Body {
 public:
  virtual ~Body() = default;
  /// Number of generalised coordinates: 3 (rigid) or 3 + the modal amplitudes.
  virtual int coordinate_count() const = 0;
  /// Number of material points declared at construction.
  virtual int point_count() const = 0;
  /// Mass matrix M(q) of the body's coordinates [kg, kg m, kg m^2 by block].
  virtual Eigen::MatrixXd mass_matrix(ConstVectorRef q) const = 0;
  /// Generalised forces other than the joints' and drives': the velocity-product (quadratic
  /// velocity) terms, the elastic and modal damping forces, and gravity [m/s^2, world frame].
  /// M(q) q'' = internal_forces + sum of J^T F over the applied point forces.
  virtual Eigen::VectorXd internal_forces(ConstVectorRef q, ConstVectorRef qdot,
                                          const Eigen::Vector2d& gravity) const = 0;
  /// Kinematics of point `index` (0 <= index < point_count()).
  virtual PointKinematics point(int index, ConstVectorRef q, ConstVectorRef qdot) const = 0;
  /// Kinetic energy [J].
  virtual double kinetic_energy(ConstVectorRef q, ConstVectorRef qdot) const = 0;
  /// Potential energy, elastic plus gravity [J] (zero height at y = 0).
  virtual double potential_energy(ConstVectorRef q, const Eigen::Vector2d& gravity) const = 0;
  /// Power of the body's own dissipative forces (modal damping) [W], >= 0: what the energy
  /// audit counts as dissipated inside the body. A rigid body has none.
  virtual double dissipated_power(ConstVectorRef /*q*/, ConstVectorRef /*qdot*/) const {
    return 0.0;
  }
};

}  // namespace rodend::linkage
