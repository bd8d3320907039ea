#include "core/scenes/slider_crank.hpp"

#include <algorithm>
#include <stdexcept>

namespace rodend {

SliderCrank::SliderCrank(double s, double t, double l0) : s_(s), t_(t), l0_(l0) {
  if (!(s > 0 && t > 0 && l0 > 0) || !closes(l0))
    throw std::invalid_argument("the crank, frame and rod lengths do not close a triangle");
  const double cos_b0 = (l0 * l0 + s * s - t * t) / (2.0 * l0 * s);  // eq. 4.3
  const double b0 = std::acos(std::clamp(cos_b0, -1.0, 1.0));
  O_ = Vec3(-l0, 0.0, 0.0);
  Q_ = Vec3(-s * std::cos(b0), s * std::sin(b0), 0.0);
  frame_angle_ = std::atan2(Q_.y() - O_.y(), Q_.x() - O_.x());
  crank_angle0_ = -b0;  // direction of Q -> P(0, 0)
  gamma0_ = std::acos(std::clamp((t * t + s * s - l0 * l0) / (2.0 * s * t), -1.0, 1.0));
  cos_frame_ = std::cos(frame_angle_);
  sin_frame_ = std::sin(frame_angle_);
  cos_crank0_ = std::cos(crank_angle0_);
  sin_crank0_ = std::sin(crank_angle0_);
}

double SliderCrank::rod_angle(double l) const {
  // eq. 4.2: alpha, the angle at O between OQ and OP; P lies clockwise of OQ
  const double cos_a = (l * l + t_ * t_ - s_ * s_) / (2.0 * l * t_);
  return frame_angle_ - std::acos(std::clamp(cos_a, -1.0, 1.0));
}

double SliderCrank::rod_angle_slope(double l) const {
  const double cos_a = (l * l + t_ * t_ - s_ * s_) / (2.0 * l * t_);
  const double dcos_dl = (l * l - t_ * t_ + s_ * s_) / (2.0 * l * l * t_);
  const double sin_a = std::sqrt(std::max(1.0 - cos_a * cos_a, 0.0));
  // rod angle = frame angle - alpha, d(alpha)/dl = -dcos/dl / sin(alpha)
  return dcos_dl / sin_a;
}

Vec3 SliderCrank::rod_end(double l) const {
  const double a = rod_angle(l);
  return O_ + l * Vec3(std::cos(a), std::sin(a), 0.0);
}

Vec3 SliderCrank::rod_end_velocity(double l, double l_dot) const {
  const double a = rod_angle(l);
  const double a_dot = rod_angle_slope(l) * l_dot;
  const Vec3 u(std::cos(a), std::sin(a), 0.0);
  const Vec3 u_perp(-std::sin(a), std::cos(a), 0.0);
  return l_dot * u + l * a_dot * u_perp;
}

double SliderCrank::ideal_crank_angle(double l) const {
  // eq. 4.1: gamma, the angle at Q between QO and QP, grows with l (counter-clockwise)
  const double cos_g = (t_ * t_ + s_ * s_ - l * l) / (2.0 * s_ * t_);
  return std::acos(std::clamp(cos_g, -1.0, 1.0)) - gamma0_;
}

Vec3 SliderCrank::crank_end(double theta) const {
  const double a = crank_angle0_ + theta;
  return Q_ + s_ * Vec3(std::cos(a), std::sin(a), 0.0);
}

Vec3 SliderCrank::crank_end_velocity(double theta, double theta_dot) const {
  const double a = crank_angle0_ + theta;
  return s_ * theta_dot * Vec3(-std::sin(a), std::cos(a), 0.0);  // eq. 4.21: |v| = theta' s
}

}  // namespace rodend
