// Slider-crank geometry of the thesis mechanism (thesis §4, eq. 4.1-4.3, 4.17-4.21;
// model-notes §5).
//
// Frame: the origin is the rod-end at actuator zero (both spheres start there, thesis §5),
// x along the actuator rod at zero (pointing from its base O to the rod end P), y up, z out of
// the mechanism plane. Extension of the actuator rotates the crank counter-clockwise (the
// surface angle increases), and at the start of the stroke pushes the rod end along +x, turning
// towards +y as the crank rotates (thesis §5.1).
//
//   O = (-l0, 0, 0)                actuator base (rod pivot)
//   Q = s (-cos b0, sin b0, 0)     crank pivot, b0 the angle at P between PO and PQ (eq. 4.3)
//   |OQ| = t (frame), |QP| = s (crank), |OP| = l (rod, l0 + actuator extension)
#pragma once

#include <cmath>

#include "core/dual.hpp"
#include "core/math.hpp"

namespace rodend {

/// The rod at one instant: its direction and the rod end's motion (eq. 4.1-4.3 differentiated),
/// from one law of cosines, without inverse trigonometry. On a scalar S (double, or a dual
/// number of core/dual.hpp); RodKinematics is the double one.
template <class S>
struct RodKinematicsT {
  S cos_angle = 1.0, sin_angle = 0.0;        ///< direction of the rod O -> P: (cos, sin) [-]
  S angle_rate = 0.0;                        ///< d(rod angle)/dt [rad/s]
  Vec3T<S> end = Vec3T<S>::Zero();           ///< rod end (slider end) P [m]
  Vec3T<S> end_velocity = Vec3T<S>::Zero();  ///< [m/s]
  Vec3T<S> direction() const { return Vec3T<S>(cos_angle, sin_angle, S(0.0)); }
  /// The rod angle itself [rad] (an output; nothing in the dynamics needs it).
  double angle() const { return std::atan2(value_of(sin_angle), value_of(cos_angle)); }
};
using RodKinematics = RodKinematicsT<double>;

/// The crank at one instant (eq. 4.17-4.21), from one sine-cosine pair of half the crank angle.
template <class S>
struct CrankKinematicsT {
  S cos_half = 1.0, sin_half = 0.0;          ///< of theta / 2: the crank's rotation about z is the
                                             ///< unit quaternion (cos_half, 0, 0, sin_half)
  Vec3T<S> end = Vec3T<S>::Zero();           ///< crank end [m]
  Vec3T<S> end_velocity = Vec3T<S>::Zero();  ///< [m/s]
};
using CrankKinematics = CrankKinematicsT<double>;

class SliderCrank {
 public:
  /// s crank [m], t frame [m], l0 rod length at actuator zero [m]; requires a closed triangle.
  SliderCrank(double s, double t, double l0);

  double crank() const { return s_; }
  double frame() const { return t_; }
  double rod_zero() const { return l0_; }
  /// Shortest and longest rod lengths that close the triangle [m].
  double min_rod() const { return std::abs(t_ - s_); }
  double max_rod() const { return t_ + s_; }
  bool closes(double l) const { return l > min_rod() && l < max_rod(); }

  const Vec3& base() const { return O_; }
  const Vec3& crank_pivot() const { return Q_; }

  /// Rod inclination to the x-axis for rod length l [rad] (from eq. 4.2: the angle at O).
  double rod_angle(double l) const;
  /// d(rod angle)/dl [rad/m], by differentiating eq. 4.2 (not eq. 4.8-4.9 as printed).
  double rod_angle_slope(double l) const;
  /// Rod-end (slider end) position for rod length l, and its velocity for rate l' [m, m/s].
  Vec3 rod_end(double l) const;
  Vec3 rod_end_velocity(double l, double l_dot) const;
  /// Everything above at once, for rod length l and rate l' (what the right-hand side uses).
  template <class S>
  RodKinematicsT<S> rod_kinematics(const S& l, const S& l_dot) const;

  /// Crank angle from its initial position for which the ideal mechanism closes at length l:
  /// the law-of-cosines angle gamma(l) - gamma(l0) of eq. 4.1 [rad].
  double ideal_crank_angle(double l) const;
  /// Crank end position and velocity at crank angle theta (from its initial position) and rate
  /// theta' (eq. 4.17-4.21) [m, m/s].
  Vec3 crank_end(double theta) const;
  Vec3 crank_end_velocity(double theta, double theta_dot) const;
  /// Both at once, and the crank's rotation, for crank angle theta and rate theta'.
  template <class S>
  CrankKinematicsT<S> crank_kinematics(const S& theta, const S& theta_dot) const;

 private:
  double s_, t_, l0_;
  Vec3 O_, Q_;
  double frame_angle_;                          ///< direction of OQ [rad]
  double crank_angle0_;                         ///< direction of QP at actuator zero [rad]
  double gamma0_;                               ///< angle at Q at actuator zero [rad]
  double cos_frame_ = 1.0, sin_frame_ = 0.0;    ///< of frame_angle_
  double cos_crank0_ = 1.0, sin_crank0_ = 0.0;  ///< of crank_angle0_
};

template <class S>
RodKinematicsT<S> SliderCrank::rod_kinematics(const S& l, const S& l_dot) const {
  using std::sqrt;
  // eq. 4.2: alpha, the angle at O between OQ and OP (P clockwise of OQ); the rod direction is
  // OQ's turned back by alpha: (cos, sin)(frame - alpha) by the angle-difference identities
  S cos_a = (l * l + t_ * t_ - s_ * s_) / (2.0 * l * t_);
  cos_a = cos_a < -1.0 ? S(-1.0) : (1.0 < cos_a ? S(1.0) : cos_a);  // std::clamp
  const S sin_a = sqrt(max_of(1.0 - cos_a * cos_a, 0.0));
  RodKinematicsT<S> r;
  r.cos_angle = cos_frame_ * cos_a + sin_frame_ * sin_a;
  r.sin_angle = sin_frame_ * cos_a - cos_frame_ * sin_a;
  // d(rod angle)/dl = -d(alpha)/dl = (d cos(alpha)/dl) / sin(alpha) (rod_angle_slope)
  const S dcos_dl = (l * l - t_ * t_ + s_ * s_) / (2.0 * l * l * t_);
  r.angle_rate = dcos_dl / sin_a * l_dot;
  const Vec3T<S> u = r.direction();
  const Vec3T<S> u_perp(-r.sin_angle, r.cos_angle, S(0.0));
  r.end = O_ + l * u;
  r.end_velocity = l_dot * u + l * r.angle_rate * u_perp;
  return r;
}

template <class S>
CrankKinematicsT<S> SliderCrank::crank_kinematics(const S& theta, const S& theta_dot) const {
  using std::cos, std::sin;
  CrankKinematicsT<S> c;
  c.sin_half = sin(0.5 * theta);
  c.cos_half = cos(0.5 * theta);
  // theta from its half angle, then the crank direction crank_angle0 + theta
  const S cos_t = 1.0 - 2.0 * c.sin_half * c.sin_half;
  const S sin_t = 2.0 * c.sin_half * c.cos_half;
  const S cos_a = cos_crank0_ * cos_t - sin_crank0_ * sin_t;
  const S sin_a = sin_crank0_ * cos_t + cos_crank0_ * sin_t;
  c.end = Q_ + s_ * Vec3T<S>(cos_a, sin_a, S(0.0));
  c.end_velocity = s_ * theta_dot * Vec3T<S>(-sin_a, cos_a, S(0.0));  // eq. 4.21: |v| = theta' s
  return c;
}

}  // namespace rodend
