// Slider-crank geometry of the thesis mechanism (thesis §4, eq. 4.1-4.3, 4.17-4.21; model-notes
// §5): s = 0.11 m crank, t = 0.38 m frame, l0 = 0.37 m rod at actuator zero. Geometry only: no
// integration, every check is against an independent construction (distances, finite
// differences, the closed triangle).
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/scenes/slider_crank.hpp"
#include "fixture.hpp"

using namespace rodend;
using namespace rodend::test;

namespace {

constexpr double kCrank = 0.11, kFrame = 0.38, kRod = 0.37;  // thesis §4 [m]
constexpr double kDeg = 180.0 / std::numbers::pi;

/// Rod lengths across the closing range (|t - s|, t + s) = (0.27, 0.49) m, the stroke ends
/// l0 +- 0.06 m included, staying 10 mm clear of the flat triangles at the range ends.
std::vector<double> rod_lengths() {
  std::vector<double> l = {0.28, 0.30, 0.34, 0.40, 0.46, 0.48};            // across the range
  for (double d : {-0.06, -0.01, 0.0, 0.01, 0.06}) l.push_back(kRod + d);  // around l0
  return l;
}

/// Distances are built from the lengths 0.11-0.49 m; 1e-12 m is ~1e4 ulp of those, far above
/// the round-off of the law-of-cosines construction (measured <= 3.3e-16 m) and far below any
/// geometric mistake (a wrong sign of an angle moves points by centimetres).
constexpr double kDistanceAbs = 1e-12;  // [m]

}  // namespace

TEST_CASE("slider-crank: frame and crank lengths at actuator zero", "[slider-crank]") {
  const SliderCrank g(kCrank, kFrame, kRod);
  const Vec3 O = g.base(), Q = g.crank_pivot(), P0 = g.rod_end(kRod);
  const double err_frame = std::abs((Q - O).norm() - kFrame);
  const double err_crank = std::abs((P0 - Q).norm() - kCrank);
  const double err_rod = std::abs((P0 - O).norm() - kRod);
  measured("slider-crank: | |OQ| - t | [m]", err_frame, kDistanceAbs);
  measured("slider-crank: | |QP| - s | at l0 [m]", err_crank, kDistanceAbs);
  CHECK(err_frame <= kDistanceAbs);
  CHECK(err_crank <= kDistanceAbs);
  CHECK(err_rod <= kDistanceAbs);
  // the frame's origin is the rod end at actuator zero, the rod along +x (slider_crank.hpp)
  CHECK(P0.norm() <= kDistanceAbs);
  CHECK(std::abs(g.rod_angle(kRod)) <= 1e-15);
  CHECK(O.isApprox(Vec3(-kRod, 0.0, 0.0), 1e-15));
  // everything in the mechanism plane
  CHECK(O.z() == 0.0);
  CHECK(Q.z() == 0.0);
  CHECK(g.min_rod() == Approx(kFrame - kCrank).epsilon(1e-15));
  CHECK(g.max_rod() == Approx(kFrame + kCrank).epsilon(1e-15));
}

TEST_CASE("slider-crank: the rod end closes the triangle for every rod length", "[slider-crank]") {
  const SliderCrank g(kCrank, kFrame, kRod);
  double worst = 0.0;
  for (double l : rod_lengths()) {
    const Vec3 P = g.rod_end(l);
    const double e_rod = std::abs((P - g.base()).norm() - l);
    const double e_crank = std::abs((P - g.crank_pivot()).norm() - kCrank);
    CAPTURE(l, e_rod, e_crank);
    CHECK(e_rod <= kDistanceAbs);
    CHECK(e_crank <= kDistanceAbs);
    CHECK(P.z() == 0.0);
    worst = std::max({worst, e_rod, e_crank});
  }
  measured("slider-crank: worst |OP| - l, |QP| - s over l [m]", worst, kDistanceAbs);
}

TEST_CASE("slider-crank: rod-end velocity is the derivative of the rod-end position",
          "[slider-crank]") {
  const SliderCrank g(kCrank, kFrame, kRod);
  // Central difference with h = 1e-6 m: the truncation h^2/6 |P'''| grows towards the ends of
  // the closing range, where the rod angle's slope (1/sin alpha) blows up: at 10 mm from them it
  // is ~1.3e-9 relative (1.3e-7 measured with h = 1e-5, scaling as h^2); round-off eps |P|/h is
  // ~1e-10. Bound 1e-7 relative to |v|: measured 1.26e-9 (worst, l = 0.48 m). A velocity built
  // from eq. 4.8-4.9 as printed (sines and cosines swapped) is off by tens of percent.
  const double h = 1e-6, l_dot = 0.1;  // l' = 0.1 m/s, the default actuator's peak rate
  constexpr double kFiniteDifferenceRel = 1e-7;
  double worst = 0.0;
  for (double l : rod_lengths()) {
    const Vec3 fd = (g.rod_end(l + h) - g.rod_end(l - h)) / (2.0 * h) * l_dot;
    const Vec3 v = g.rod_end_velocity(l, l_dot);
    const double rel = (v - fd).norm() / fd.norm();
    CAPTURE(l, v.transpose(), fd.transpose(), rel);
    CHECK(rel <= kFiniteDifferenceRel);
    CHECK(v.z() == 0.0);
    worst = std::max(worst, rel);
  }
  measured("slider-crank: rod_end_velocity vs central difference (rel)", worst,
           kFiniteDifferenceRel);
  // at actuator zero the rod end moves along the rod, +x, on extension (slider_crank.hpp)
  const Vec3 v0 = g.rod_end_velocity(kRod, 1.0);
  CHECK(v0.x() == Approx(1.0).epsilon(1e-12));
  // and the rod turns counter-clockwise as it extends (thesis §5.1: "turning towards +y")
  CHECK(g.rod_angle_slope(kRod) > 0.0);
}

TEST_CASE("slider-crank: crank-end velocity is the derivative of the crank-end position",
          "[slider-crank]") {
  const SliderCrank g(kCrank, kFrame, kRod);
  // Central difference in theta with h = 1e-6 rad: truncation h^2/6 ~ 2e-13 relative, round-off
  // eps |P|/(h s) ~ 1e-10 relative. Bound 1e-7 relative: measured 1.56e-10.
  const double h = 1e-6, theta_dot = 0.9;  // ~ the default run's peak surface rate [rad/s]
  constexpr double kFiniteDifferenceRel = 1e-7;
  double worst = 0.0;
  for (double theta_deg : {-40.0, -20.0, -5.0, 0.0, 5.0, 20.0, 40.0}) {
    const double theta = theta_deg / kDeg;
    const Vec3 fd = (g.crank_end(theta + h) - g.crank_end(theta - h)) / (2.0 * h) * theta_dot;
    const Vec3 v = g.crank_end_velocity(theta, theta_dot);
    const double rel = (v - fd).norm() / fd.norm();
    CAPTURE(theta_deg, rel);
    CHECK(rel <= kFiniteDifferenceRel);
    // eq. 4.21: |v| = theta' s, perpendicular to the crank
    CHECK(v.norm() == Approx(theta_dot * kCrank).epsilon(1e-14));
    CHECK(std::abs(v.dot(g.crank_end(theta) - g.crank_pivot())) <= 1e-15);
    // the crank end stays on its circle
    CHECK(std::abs((g.crank_end(theta) - g.crank_pivot()).norm() - kCrank) <= kDistanceAbs);
    worst = std::max(worst, rel);
  }
  measured("slider-crank: crank_end_velocity vs central difference (rel)", worst,
           kFiniteDifferenceRel);
  // theta = 0 is the crank's initial position: its end is the rod end at actuator zero
  CHECK(g.crank_end(0.0).norm() <= kDistanceAbs);
}

TEST_CASE("slider-crank: the ideal crank angle closes the mechanism", "[slider-crank]") {
  const SliderCrank g(kCrank, kFrame, kRod);
  double worst = 0.0;
  for (double l : rod_lengths()) {
    const double theta = g.ideal_crank_angle(l);
    const double gap = (g.crank_end(theta) - g.rod_end(l)).norm();
    CAPTURE(l, theta, gap);
    CHECK(gap <= kDistanceAbs);
    worst = std::max(worst, gap);
  }
  measured("slider-crank: |crank_end(ideal angle) - rod_end| [m]", worst, kDistanceAbs);
  CHECK(g.ideal_crank_angle(kRod) == 0.0);
}

TEST_CASE("slider-crank: +-0.06 m of stroke swings the surface about +-35 deg", "[slider-crank]") {
  // model-notes §5 / thesis §4: "the actuator stroke is 0.06 m so as to have a control surface
  // angle equal to +-35 deg", read as l0 +- 0.06 m. The law of cosines gives +33.42 and -32.70
  // deg (measured); the band 30-37 deg holds the thesis's "about 35" and excludes a radian/degree
  // slip, the wrong angle of the triangle (eq. 4.2's rod angle changes by only ~3 deg) or a sign
  // error.
  const SliderCrank g(kCrank, kFrame, kRod);
  const double up = g.ideal_crank_angle(kRod + 0.06) * kDeg;
  const double down = g.ideal_crank_angle(kRod - 0.06) * kDeg;
  CAPTURE(up, down);
  measured("slider-crank: surface angle at l0 + 0.06 m [deg]", up, 37.0);
  measured("slider-crank: surface angle at l0 - 0.06 m [deg]", down, -37.0);
  CHECK(up > 30.0);
  CHECK(up < 37.0);
  CHECK(down < -30.0);
  CHECK(down > -37.0);
}

TEST_CASE("slider-crank: extension turns the crank counter-clockwise", "[slider-crank]") {
  const SliderCrank g(kCrank, kFrame, kRod);
  // strictly increasing in l over the whole closing range (eq. 4.1: gamma grows with l)
  double previous = -INFINITY;
  for (int i = 1; i < 200; ++i) {
    const double l = g.min_rod() + (g.max_rod() - g.min_rod()) * i / 200.0;
    const double theta = g.ideal_crank_angle(l);
    CAPTURE(l, theta, previous);
    CHECK(theta > previous);
    previous = theta;
  }
  // counter-clockwise: the crank end turns positively about +z around the pivot
  const Vec3 r0 = g.rod_end(kRod) - g.crank_pivot();
  const Vec3 r1 = g.rod_end(kRod + 0.01) - g.crank_pivot();
  CHECK(r0.cross(r1).z() > 0.0);
  CHECK(g.ideal_crank_angle(kRod + 0.01) > 0.0);
}

TEST_CASE("slider-crank: the right-hand side's one-pass kinematics equal the per-quantity ones",
          "[slider-crank]") {
  // rod_kinematics / crank_kinematics (law of cosines and angle identities, no inverse
  // trigonometry) against rod_angle, rod_end, rod_end_velocity, crank_end, crank_end_velocity
  // (acos and sin/cos of the angles): the same quantities to round-off. Measured: largest
  // difference 2.8e-16 (m, m/s, rad); bound 1e-15 (a few ulp of the 0.1-0.5 m lengths).
  const SliderCrank g(kCrank, kFrame, kRod);
  double worst = 0.0;
  for (double l : rod_lengths()) {
    CAPTURE(l);
    const double l_dot = 0.1;
    const RodKinematics r = g.rod_kinematics(l, l_dot);
    worst = std::max({worst, (r.end - g.rod_end(l)).norm(),
                      (r.end_velocity - g.rod_end_velocity(l, l_dot)).norm(),
                      std::abs(r.angle() - g.rod_angle(l)),
                      std::abs(r.angle_rate - g.rod_angle_slope(l) * l_dot)});
    CHECK(std::abs(std::hypot(r.cos_angle, r.sin_angle) - 1.0) <= 1e-15);
  }
  for (double theta : {-1.0, -0.3, 0.0, 1e-9, 0.2, 0.7, 2.5}) {
    CAPTURE(theta);
    const CrankKinematics c = g.crank_kinematics(theta, -0.4);
    worst = std::max({worst, (c.end - g.crank_end(theta)).norm(),
                      (c.end_velocity - g.crank_end_velocity(theta, -0.4)).norm()});
    const Quat q(Eigen::AngleAxisd(theta, Vec3::UnitZ()));
    worst = std::max(worst, (Quat(c.cos_half, 0.0, 0.0, c.sin_half).coeffs() - q.coeffs()).norm());
  }
  measured("slider-crank: one-pass kinematics vs per-quantity (abs)", worst, 1e-15);
  CHECK(worst <= 1e-15);
}

TEST_CASE("rotation vector of a unit quaternion: the series branch equals atan2", "[math]") {
  // rotation_vector_of_unit sums atan(x)/x as a series for angles up to 2 atan(1/8); against
  // 2 atan2(|v|, w) |v|^-1 v, for angles across the switch: measured 0 (bit-identical here)
  // relative to the angle; bound 1e-15
  double worst = 0.0;
  const Vec3 axis = Vec3(1.0, -2.0, 0.5).normalized();
  for (double angle : {1e-12, 1e-7, 1e-3, 0.05, 0.2, 0.24, 0.2487, 0.2488, 0.25, 0.5, 1.0, 3.0}) {
    const Quat q(Eigen::AngleAxisd(angle, axis));
    const Vec3 rv = rotation_vector_of_unit(q);
    const double s = q.vec().norm();
    const Vec3 ref = 2.0 * std::atan2(s, q.w()) / s * q.vec();
    worst = std::max(worst, (rv - ref).norm() / angle);
  }
  measured("rotation_vector_of_unit vs atan2 (rel)", worst, 1e-15);
  CHECK(worst <= 1e-15);
}
