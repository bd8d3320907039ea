#pragma once
// A flexible planar body of the planar linkage by modal reduction in a floating frame of
// reference (Shabana, Dynamics of Multibody Systems, 4th ed., ch. 5 and 6; the planar case).
//
// Coordinates q = (x, y, phi, eta_1 .. eta_n): the frame's origin [m] and angle [rad] in the
// world, then the amplitudes of the beam's elastic modes (core/linkage/beam_modes.hpp). Each mode
// is scaled so that its largest nodal displacement (axial or transverse) is 1, so eta_i is that
// displacement [m]. The beam's axis runs in the body frame from the point a (s = 0) to the point
// b (s = L), along e = (b - a) / L, with n = J e its normal in the plane. A material point p of
// the body frame belongs to the cross-section at s = (p - a).e and, at the offset
// d = (p - a).n from the axis, moves with it as a rigid cross-section:
//   u_f(p) = sum_i eta_i ((u_i(s) - d v_i'(s)) e + v_i(s) n),  its rotation sum_i eta_i v_i'(s),
// and its world position is r = R + A(phi) (p + u_f(p)).
//
// Assumptions: small elastic displacements (linear modes, no geometric stiffening besides the
// inertial coupling; the frame carries the large motion), Euler-Bernoulli modes without rotary
// inertia in the deformation (the sections' rotary inertia rho I L is kept in the rigid body's
// inertia), modal damping 2 zeta m_i omega_i, and the frame defined by the modes' boundary
// conditions (free-free: mean axis; pinned-pinned: chord through both ends; clamped-free:
// tangent at s = 0).
//
// The mass matrix is the exact one of the kinetic energy 1/2 int rho |r'|^2 dV with the inertia
// invariants integrated once over the beam's elements (4-point Gauss per element, exact for the
// element's polynomials):
//   m, S0 = int rho u0, Sbar = int rho S, I00 = int rho u0.u0 (+ sections' rho I L),
//   I1 = int rho S^T u0, I2 = int rho S^T J u0, Mff = int rho S^T S, Stilde = int rho S^T J S,
// with J the 90-degree rotation. With s(q) = S0 + Sbar eta:
//   M = [ m I      A J s        A Sbar                ]
//       [ .        I00 + 2 I1.eta + eta.Mff.eta   I2^T - eta^T Stilde ]
//       [ .        .            Mff                   ]
// and the quadratic velocity vector Q_v = -int rho (dr/dq)^T (velocity-product acceleration):
//   R:   A (phi'^2 s - 2 phi' J Sbar eta')
//   phi: -2 phi' (I1 + Mff eta) . eta'
//   eta: phi'^2 (I1 + Mff eta) - 2 phi' Stilde eta'.
#include <vector>

#include "core/linkage/beam_modes.hpp"
#include "core/linkage/body.hpp"

namespace rodend::linkage {

class FlexibleBody : public Body {
 public:
  /// modes: the reduction basis (rescaled here to a unit largest displacement); axis_start,
  /// axis_end: the body-frame points of the beam's ends s = 0 and s = L [m] (their distance is
  /// the modes' length); points: body-frame points of the undeformed body [m] (each within the
  /// beam's span along its axis); damping_ratio: each mode's zeta [-]. Throws
  /// std::invalid_argument on a point outside the span or an axis of another length.
  FlexibleBody(BeamModes modes, const Eigen::Vector2d& axis_start, const Eigen::Vector2d& axis_end,
               const std::vector<Eigen::Vector2d>& points, double damping_ratio);

  int coordinate_count() const override { return 3 + n_; }
  int point_count() const override { return static_cast<int>(points_.size()); }
  Eigen::MatrixXd mass_matrix(ConstVectorRef q) const override;
  Eigen::VectorXd internal_forces(ConstVectorRef q, ConstVectorRef qdot,
                                  const Eigen::Vector2d& gravity) const override;
  PointKinematics point(int index, ConstVectorRef q, ConstVectorRef qdot) const override;
  double kinetic_energy(ConstVectorRef q, ConstVectorRef qdot) const override;
  double potential_energy(ConstVectorRef q, const Eigen::Vector2d& gravity) const override;
  double dissipated_power(ConstVectorRef q, ConstVectorRef qdot) const override;

  int mode_count() const { return n_; }
  const BeamModes& modes() const { return modes_; }
  double mass() const { return mass_; }  ///< [kg]
  /// Modal mass m_i [kg] and stiffness m_i omega_i^2 [N/m] of mode i.
  double modal_mass(int i) const { return mff_(i, i); }
  double modal_stiffness(int i) const { return stiffness_(i); }

 private:
  struct PointShape {
    Eigen::Vector2d u0;                          ///< undeformed body-frame position [m]
    Eigen::Matrix<double, 2, Eigen::Dynamic> s;  ///< displacement per unit amplitude
    Eigen::RowVectorXd slope;                    ///< cross-section rotation per amplitude
  };
  void integrate_invariants();
  void add_point(const Eigen::Vector2d& p);

  BeamModes modes_;
  int n_ = 0;
  Eigen::Vector2d axis_start_, axis_, normal_;  ///< a [m], e and n (unit)
  std::vector<PointShape> points_;
  double mass_ = 0.0, i00_ = 0.0;
  Eigen::Vector2d s0_ = Eigen::Vector2d::Zero();
  Eigen::Matrix<double, 2, Eigen::Dynamic> sbar_;
  Eigen::VectorXd i1_, i2_, stiffness_, damping_;
  Eigen::MatrixXd mff_, stilde_;
};

}  // namespace rodend::linkage
