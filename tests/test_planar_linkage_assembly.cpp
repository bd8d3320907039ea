// The planar linkage assembly through its C++ interface (core/linkage/assembly.hpp): a
// slider-crank built from rigid bodies, an ideal prismatic guide and revolute joints, driven by
// the slider's displacement, against the closed-form slider-crank.
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>

#include "core/linkage/assembly.hpp"
#include "core/linkage/rigid_body.hpp"

using namespace rodend::linkage;

namespace {

constexpr double kR = 0.05, kL = 0.3;  // crank, rod [m] (the Wang et al. rig's)

/// Crank, rod and slider; the slider's pin driven along x by d(t) = 0.02 sin(10 t) from
/// x0 = 0.3 (crank at 90 deg... solved by the assembly from a rough guess).
Linkage slider_crank() {
  Linkage k;
  const int a = k.add_ground_point({0.0, 0.0});
  const int rest = k.add_ground_point({0.3, 0.0});
  const int crank =
      k.add_body(std::make_unique<RigidBody>(0.343, 2.16e-4, Eigen::Vector2d(kR / 2, 0.0),
                                             std::vector<Eigen::Vector2d>{{0.0, 0.0}, {kR, 0.0}}));
  const int rod =
      k.add_body(std::make_unique<RigidBody>(1.072, 9.88e-3, Eigen::Vector2d(kL / 2, 0.0),
                                             std::vector<Eigen::Vector2d>{{0.0, 0.0}, {kL, 0.0}}));
  const int slider = k.add_body(std::make_unique<RigidBody>(
      0.347, 1.15e-4, Eigen::Vector2d::Zero(), std::vector<Eigen::Vector2d>{{0.0, 0.0}}));
  k.add_revolute({crank, 0}, {-1, a});
  k.add_revolute({crank, 1}, {rod, 0});
  k.add_revolute({rod, 1}, {slider, 0});
  k.add_prismatic({slider, 0}, {-1, rest}, {1.0, 0.0}, 0.0);
  k.add_drive({slider, 0}, {-1, rest}, {1.0, 0.0}, [](double t) {
    return DriveSample{0.02 * std::sin(10.0 * t), 0.2 * std::cos(10.0 * t),
                       -2.0 * std::sin(10.0 * t)};
  });
  k.finish();
  return k;
}

}  // namespace

TEST_CASE("linkage assembly: a slider-crank driven at its slider follows the closed form",
          "[planar-linkage]") {
  const Linkage k = slider_crank();
  // 9 coordinates; 3 revolute x 2 + prismatic 2 + drive 1 = 9 rows: the slider is on the
  // guide, so the drive holds its pin along the guide only (the guide holds it across; both
  // coordinates would give 10 rows, the y row twice, and a singular dynamics solve)
  REQUIRE(k.coordinate_count() == 9);
  CHECK(k.constraint_count() == 9);
  Eigen::VectorXd q(9);
  q << 0.0, 0.0, 1.3, 0.02, 0.05, -0.2, 0.3, 0.0, 0.0;  // rough guess: crank up, rod down
  for (const double t : {0.0, 0.05, 0.1, 0.2}) {
    REQUIRE(k.assemble(t, q) < 1e-13);
    const double x = 0.3 + 0.02 * std::sin(10.0 * t);
    // x = r cos th + sqrt(L^2 - r^2 sin^2 th): cos th = (x^2 + r^2 - L^2) / (2 r x)
    const double th = std::acos((x * x + kR * kR - kL * kL) / (2.0 * kR * x));
    CHECK(q[2] == Approx(th).margin(1e-12));
    // the consistent velocity makes every constraint rate vanish
    const Eigen::VectorXd qd = k.consistent_velocity(t, q);
    const ConstraintRows c = k.constraints(t, q, qd);
    CHECK((c.jacobian * qd + c.b1).cwiseAbs().maxCoeff() < 1e-12);
    CHECK(qd[6] == Approx(0.2 * std::cos(10.0 * t)).margin(1e-12));
    // independent rows: the dynamics' saddle-point solve is regular, and its accelerations
    // keep every constraint's acceleration at zero (C'' = Cq q'' + b2 = 0 on the assembled q)
    CHECK(c.jacobian.fullPivLu().rank() == 9);
    const LinkageDynamics d = k.dynamics(t, q, qd, {});
    CHECK((c.jacobian * d.qdd + c.b2).cwiseAbs().maxCoeff() < 1e-9);
    // the slider's acceleration is the drive's, -2 sin(10 t)
    CHECK(d.qdd[6] == Approx(-2.0 * std::sin(10.0 * t)).margin(1e-9));
  }
}
