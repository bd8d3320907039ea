// The planar linkage's flexible body by modal reduction in a floating frame
// (core/linkage/flexible_body.hpp): its mass matrix against the kinetic energy of its material
// points, its point kinematics against finite differences, and free flight integrated here by a
// classical Runge-Kutta step: energy and momenta conserved, and a very stiff body moving as the
// rigid body.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "core/linkage/flexible_body.hpp"

using namespace rodend::linkage;

namespace {

// A stubby polymer-like bar 0.3 m long, 20 mm x 20 mm: its first axial frequency is only ~7x its
// first bending one, so the explicit step below resolves every mode (omega_max h ~ 0.1).
constexpr double kL = 0.3, kA = 4e-4, kI = 0.02 * 0.02 * 0.02 * 0.02 / 12.0;
constexpr double kRho = 1000.0;

BeamModes modes(BeamSupport bc, double youngs_modulus, int bending = 3, int axial = 1) {
  BeamModes::Spec s;
  s.segments = {{kL, kA, kI}};
  s.material = {youngs_modulus, kRho};
  s.support = bc;
  s.bending_modes = bending;
  s.axial_modes = axial;
  s.elements = 20;
  return BeamModes::compute(s);
}

/// The beam's axis in the body frame: from kAxisStart along kAxis (30 degrees to the frame's x).
const Eigen::Vector2d kAxisStart(0.02, -0.01), kAxis(std::sqrt(3.0) / 2, 0.5),
    kNormal(-0.5, std::sqrt(3.0) / 2);

/// The body with points at both ends, the middle and 10 mm off the axis 0.1 m along it.
FlexibleBody body(BeamSupport bc, double youngs_modulus = 1e9, double zeta = 0.0) {
  const Eigen::Vector2d a = kAxisStart, e = kAxis;
  return FlexibleBody(modes(bc, youngs_modulus), a, a + kL * e,
                      {a, a + kL * e, a + kL / 2 * e, a + 0.1 * e + 0.01 * kNormal}, zeta);
}

struct State {
  Eigen::VectorXd q, v;
};

State derivative(const FlexibleBody& b, const State& s, const Eigen::Vector2d& g) {
  return {s.v, b.mass_matrix(s.q).ldlt().solve(b.internal_forces(s.q, s.v, g))};
}

/// One classical Runge-Kutta step of M q'' = internal forces (no applied forces).
State rk4(const FlexibleBody& b, const State& s, double h, const Eigen::Vector2d& g) {
  auto add = [](const State& a, const State& d, double f) {
    return State{a.q + f * d.q, a.v + f * d.v};
  };
  const State k1 = derivative(b, s, g), k2 = derivative(b, add(s, k1, h / 2), g);
  const State k3 = derivative(b, add(s, k2, h / 2), g), k4 = derivative(b, add(s, k3, h), g);
  State n = s;
  n.q += h / 6 * (k1.q + 2 * k2.q + 2 * k3.q + k4.q);
  n.v += h / 6 * (k1.v + 2 * k2.v + 2 * k3.v + k4.v);
  return n;
}

State spinning(int n) {
  State s{Eigen::VectorXd::Zero(3 + n), Eigen::VectorXd::Zero(3 + n)};
  s.q.head<3>() << 0.1, -0.2, 0.3;
  s.v.head<3>() << 0.5, -0.3, 200.0;
  for (int i = 0; i < n; ++i) {
    s.q(3 + i) = 1e-4 / (i + 1);  // [m]
    s.v(3 + i) = 0.05 * (i % 2 ? -1 : 1);
  }
  return s;
}

/// Linear momentum (2) and angular momentum about the world origin: the frame rows of M q'
/// are the momentum and the angular momentum about the frame's origin.
Eigen::Vector3d momenta(const FlexibleBody& b, const State& s) {
  const Eigen::VectorXd p = b.mass_matrix(s.q) * s.v;
  return {p(0), p(1), p(2) + s.q(0) * p(1) - s.q(1) * p(0)};
}

/// The largest relative drifts of the energy, the linear momentum (less gravity's impulse m g t)
/// and, without gravity, the angular momentum over 0.1 s of free flight in steps of h.
Eigen::Vector3d drifts(const FlexibleBody& b, double h, const Eigen::Vector2d& g) {
  State s = spinning(b.mode_count());
  const double e0 = b.kinetic_energy(s.q, s.v) + b.potential_energy(s.q, g);
  const Eigen::Vector3d p0 = momenta(b, s);
  Eigen::Vector3d worst = Eigen::Vector3d::Zero();
  const int steps = static_cast<int>(std::lround(0.1 / h));
  for (int k = 1; k <= steps; ++k) {
    s = rk4(b, s, h, g);
    const double e = b.kinetic_energy(s.q, s.v) + b.potential_energy(s.q, g);
    const Eigen::Vector3d p = momenta(b, s);
    const Eigen::Vector2d pg = p0.head<2>() + b.mass() * g * (k * h);
    worst(0) = std::max(worst(0), std::abs(e - e0) / e0);
    worst(1) = std::max(worst(1), (p.head<2>() - pg).norm() / p0.head<2>().norm());
    if (g.isZero()) worst(2) = std::max(worst(2), std::abs(p(2) - p0(2)) / std::abs(p0(2)));
  }
  return worst;
}

}  // namespace

TEST_CASE(
    "flexible body: the mass matrix is symmetric positive definite and the points' "
    "kinetic energy",
    "[flexible_body]") {
  for (BeamSupport bc :
       {BeamSupport::free_free, BeamSupport::pinned_pinned, BeamSupport::clamped_free}) {
    // material points at 4 Gauss stations per element of the beam's mesh, each carrying its
    // share of rho A ds: their kinetic energy is int rho |r'|^2 / 2 (exact for the elements'
    // polynomials), computed from the point velocities alone
    const BeamModes m = modes(bc, 1e9);
    static constexpr double g[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                                    0.8611363115940526};
    static constexpr double w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                                    0.3478548451374538};
    std::vector<Eigen::Vector2d> pts;
    std::vector<double> dm;
    for (std::size_t e = 0; e + 1 < m.nodes().size(); ++e) {
      const double a = m.nodes()[e], h = m.nodes()[e + 1] - a;
      for (int k = 0; k < 4; ++k) {
        pts.emplace_back(-kL / 2 + a + 0.5 * h * (1 + g[k]), 0.0);
        dm.push_back(0.5 * h * w[k] * m.mass_per_length()[e]);
      }
    }
    const FlexibleBody b(m, {-kL / 2, 0.0}, {kL / 2, 0.0}, pts, 0.0);
    CHECK(b.mass() == Approx(kRho * kA * kL).epsilon(1e-12));
    const State s = spinning(b.mode_count());
    const Eigen::MatrixXd mm = b.mass_matrix(s.q);
    CHECK((mm - mm.transpose()).norm() <= 1e-14 * mm.norm());
    CHECK(Eigen::LLT<Eigen::MatrixXd>(mm).info() == Eigen::Success);
    CHECK(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(mm).eigenvalues().minCoeff() > 0.0);
    double t = 0.0;
    for (std::size_t k = 0; k < pts.size(); ++k)
      t += 0.5 * dm[k] * b.point(static_cast<int>(k), s.q, s.v).velocity.squaredNorm();
    // the body adds the sections' own rotary inertia rho I L to the frame's rotation
    const double sections = 0.5 * kRho * kI * kL * s.v(2) * s.v(2);
    CHECK(b.kinetic_energy(s.q, s.v) - sections == Approx(t).epsilon(1e-12));
  }
}

TEST_CASE("flexible body: point Jacobians and velocity products match finite differences",
          "[flexible_body]") {
  const FlexibleBody b = body(BeamSupport::pinned_pinned);
  const State s = spinning(b.mode_count());
  for (int p = 0; p < b.point_count(); ++p) {
    INFO("point " << p);
    const PointKinematics k = b.point(p, s.q, s.v);
    const double h = 1e-6;
    for (int c = 0; c < b.coordinate_count(); ++c) {
      Eigen::VectorXd qp = s.q, qm = s.q;
      qp(c) += h;
      qm(c) -= h;
      const PointKinematics kp = b.point(p, qp, s.v), km = b.point(p, qm, s.v);
      const Eigen::Vector2d fd = (kp.position - km.position) / (2 * h);
      CHECK((fd - k.jacobian.col(c)).norm() < 1e-8);  // central difference: O(h^2 r''') ~ 1e-12
      CHECK((kp.angle - km.angle) / (2 * h) == Approx(k.angle_jacobian(c)).margin(1e-8));
    }
    CHECK((k.jacobian * s.v - k.velocity).norm() < 1e-12 * k.velocity.norm());
    // along q(t) = q + q' t (q'' = 0) the acceleration is (dJ/dt) q'
    const double dt = 1e-5;
    const Eigen::Vector2d a = (b.point(p, s.q + dt * s.v, s.v).position - 2 * k.position +
                               b.point(p, s.q - dt * s.v, s.v).position) /
                              (dt * dt);
    CHECK((a - k.jacobian_dot_qdot).norm() < 1e-4 * k.jacobian_dot_qdot.norm());
  }
}

TEST_CASE("flexible body: free flight conserves energy and momenta without damping",
          "[flexible_body]") {
  // The drifts are the Runge-Kutta step's truncation alone: at omega_max h = 0.1 (the third
  // bending mode, 7.9e3 rad/s, h = 10 us) they are ~1e-7 and halving the step divides them by
  // 2^4 or more (a term missing from the mass matrix or the quadratic velocity vector would
  // leave an O(1) drift that no step removes).
  for (BeamSupport bc :
       {BeamSupport::free_free, BeamSupport::pinned_pinned, BeamSupport::clamped_free}) {
    for (const Eigen::Vector2d& g : {Eigen::Vector2d(0.0, -9.81), Eigen::Vector2d(0.0, 0.0)}) {
      const FlexibleBody b = body(bc);
      const Eigen::Vector3d coarse = drifts(b, 1e-5, g), fine = drifts(b, 5e-6, g);
      INFO("boundary condition " << static_cast<int>(bc) << " gravity " << g.y()
                                 << " drifts (energy, momentum, angular momentum) at 10 us "
                                 << coarse.transpose() << ", at 5 us " << fine.transpose());
      CHECK(coarse.maxCoeff() < 1e-6);
      for (int i = 0; i < 3; ++i)
        if (coarse(i) > 1e-10) CHECK(fine(i) < coarse(i) / 12.0);  // above rounding
    }
  }
}

TEST_CASE("flexible body: a very stiff body moves as the rigid body", "[flexible_body]") {
  // E x 10^4: frequencies x 100 (the first bending ~1.4e5 rad/s against a spin of 50 rad/s, so
  // the centrifugal deflection is ~(50 / 1.4e5)^2 of the length)
  const FlexibleBody b = body(BeamSupport::clamped_free, 1e13);
  const Eigen::Vector2d g(0.0, -9.81);
  State s{Eigen::VectorXd::Zero(b.coordinate_count()), Eigen::VectorXd::Zero(b.coordinate_count())};
  s.q.head<3>() << 0.1, 0.2, 0.3;
  s.v.head<3>() << 1.0, 2.0, 50.0;
  // the rigid body: its mass centre at mid-span (point 2) flies on a parabola,
  // its angle turns uniformly
  const PointKinematics c0 = b.point(2, s.q, s.v);
  const double t_end = 0.02, h = 1e-6;  // omega_max h ~ 0.78 (third bending mode)
  for (int k = 0; k < static_cast<int>(std::lround(t_end / h)); ++k) s = rk4(b, s, h, g);
  const Eigen::Vector2d centre = c0.position + c0.velocity * t_end + 0.5 * g * t_end * t_end;
  const double angle = 0.3 + 50.0 * t_end;
  const Eigen::Vector2d tip =
      centre + Eigen::Rotation2Dd(angle).toRotationMatrix() * kAxis * (kL / 2);
  const PointKinematics k = b.point(1, s.q, s.v);
  INFO("tip " << k.position.transpose() << " rigid " << tip.transpose());
  CHECK((k.position - tip).norm() < 1e-7 * kL);
  CHECK(k.angle == Approx(angle).margin(1e-7));
  CHECK(s.q.tail(b.mode_count()).cwiseAbs().maxCoeff() < 1e-7 * kL);
}

TEST_CASE("flexible body: modal damping dissipates", "[flexible_body]") {
  const FlexibleBody b = body(BeamSupport::free_free, 1e9, 0.02);
  State s = spinning(b.mode_count());
  const Eigen::Vector2d g(0.0, 0.0);
  double e = b.kinetic_energy(s.q, s.v) + b.potential_energy(s.q, g);
  for (int k = 0; k < 2000; ++k) {
    s = rk4(b, s, 1e-5, g);
    const double en = b.kinetic_energy(s.q, s.v) + b.potential_energy(s.q, g);
    REQUIRE(en <= e * (1 + 1e-12));
    e = en;
  }
  // each mode's damping: the modal damping force is 2 zeta m_i omega_i eta_i'
  CHECK(b.modal_stiffness(0) == Approx(b.modal_mass(0) * std::pow(b.modes().frequency(0), 2)));
}

TEST_CASE("flexible body: the quadratic velocity vector is Lagrange's from the mass matrix",
          "[flexible_body]") {
  // Q_v,k = -(dM/dt q')_k + 1/2 q'^T (dM/dq_k) q', the mass matrix differentiated by central
  // differences (its entries are quadratic in eta and trigonometric in phi: the differences'
  // error is ~h^2 |M'''| ~ 1e-12 of the terms); gyroscopic terms, which do no work, are
  // checked here and not by the energy
  for (BeamSupport bc :
       {BeamSupport::free_free, BeamSupport::pinned_pinned, BeamSupport::clamped_free}) {
    const FlexibleBody b = body(bc);
    const State s = spinning(b.mode_count());
    const int n = b.coordinate_count();
    const double h = 1e-6;
    const Eigen::MatrixXd mdot =
        (b.mass_matrix(s.q + h * s.v) - b.mass_matrix(s.q - h * s.v)) / (2 * h);
    Eigen::VectorXd lagrange = -mdot * s.v;
    for (int k = 0; k < n; ++k) {
      Eigen::VectorXd qp = s.q, qm = s.q;
      qp(k) += h;
      qm(k) -= h;
      lagrange(k) += 0.5 * s.v.dot((b.mass_matrix(qp) - b.mass_matrix(qm)) / (2 * h) * s.v);
    }
    Eigen::VectorXd qv = b.internal_forces(s.q, s.v, Eigen::Vector2d::Zero());
    for (int i = 0; i < b.mode_count(); ++i) qv(3 + i) += b.modal_stiffness(i) * s.q(3 + i);
    INFO("boundary condition " << static_cast<int>(bc) << "\nQ_v " << qv.transpose()
                               << "\nLagrange " << lagrange.transpose());
    CHECK((qv - lagrange).norm() < 1e-6 * lagrange.norm());
  }
}

TEST_CASE("flexible body: an off-axis point moves with its cross-section", "[flexible_body]") {
  // an axis along the frame's y (normal n = (-1, 0)), a point on it and one 10 mm off it at the
  // same station: the offset turns with the section's rotation (the frame angle plus the modes'
  // slope there)
  const FlexibleBody b(modes(BeamSupport::clamped_free, 1e9), {0.0, -kL / 2}, {0.0, kL / 2},
                       {{0.0, 0.05}, {-0.01, 0.05}}, 0.0);
  State s = spinning(b.mode_count());
  s.q.tail(b.mode_count()) *= 10.0;  // ~1 mm: a visible rotation, second order still ~1e-6
  const PointKinematics axis = b.point(0, s.q, s.v), off = b.point(1, s.q, s.v);
  const Eigen::Vector2d expected =
      axis.position - 0.01 * Eigen::Vector2d(std::cos(axis.angle), std::sin(axis.angle));
  INFO("section rotation " << axis.angle - s.q(2) << " rad");
  CHECK(std::abs(axis.angle - s.q(2)) > 1e-3);
  // linear kinematics: the offset is 0.01 (1, theta) rather than 0.01 (sin, cos): error 0.01
  // theta^2
  const double theta = axis.angle - s.q(2);
  CHECK((off.position - expected).norm() < 0.01 * theta * theta);
}

TEST_CASE("flexible body: free-free modes pinned at both ends converge to the pinned-pinned beam",
          "[flexible_body]") {
  // The body's two end points held by pins (4 constraints through the point Jacobians at rest):
  // the Ritz frequencies of the constrained body bound the pinned-pinned beam's first
  // frequency, (pi / L)^2 sqrt(E I / (rho A)), from above and fall towards it as modes are added.
  // This is the flap parts' situation: free-free modes (the part's) inside a linkage of pins.
  const double exact = std::pow(std::numbers::pi / kL, 2) * std::sqrt(1e9 * kI / (kRho * kA));
  double previous = 1e300;
  for (int n : {1, 3, 5, 9}) {
    const FlexibleBody b(modes(BeamSupport::free_free, 1e9, n, 0), {0.0, 0.0}, {kL, 0.0},
                         {{0.0, 0.0}, {kL, 0.0}}, 0.0);
    const int c = b.coordinate_count();
    const Eigen::VectorXd q = Eigen::VectorXd::Zero(c);
    Eigen::MatrixXd g(4, c);
    g.topRows<2>() = b.point(0, q, q).jacobian;
    g.bottomRows<2>() = b.point(1, q, q).jacobian;
    const Eigen::MatrixXd free = Eigen::FullPivLU<Eigen::MatrixXd>(g).kernel();
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(c, c);
    for (int i = 0; i < n; ++i) k(3 + i, 3 + i) = b.modal_stiffness(i);
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(
        free.transpose() * k * free, free.transpose() * b.mass_matrix(q) * free);
    const double w = std::sqrt(es.eigenvalues()(0));
    INFO(n << " free-free modes: " << w << " rad/s, pinned-pinned " << exact);
    CHECK(w >= exact * (1 - 1e-9));
    CHECK(w < previous);
    previous = w;
  }
  CHECK(previous < exact * 1.001);  // 9 modes: 2.2e-4 high (1 mode: 1.4e-2, 3: 2.7e-3)
}

TEST_CASE("flexible body: the energy lost is the modal damping's dissipated power",
          "[flexible_body]") {
  // E(t) + int_0^t P_d dt stays at E(0): the audit's balance (trapezoidal rule on the steps)
  const FlexibleBody b = body(BeamSupport::free_free, 1e9, 0.05);
  State s = spinning(b.mode_count());
  const Eigen::Vector2d g(0.0, -9.81);
  const double e0 = b.kinetic_energy(s.q, s.v) + b.potential_energy(s.q, g);
  double lost = 0.0, p = b.dissipated_power(s.q, s.v);
  const double h = 5e-6;
  for (int k = 0; k < 4000; ++k) {
    s = rk4(b, s, h, g);
    const double pn = b.dissipated_power(s.q, s.v);
    lost += 0.5 * h * (p + pn);
    p = pn;
  }
  const double e = b.kinetic_energy(s.q, s.v) + b.potential_energy(s.q, g);
  INFO("energy " << e0 << " -> " << e << ", dissipated " << lost);
  CHECK(lost > 1e-4 * e0);  // the modes carry ~1e-3 of the energy; half of theirs is lost
  // trapezoidal rule on kHz oscillations at 5 us: ~(omega h)^2 / 12 ~ 1e-4 of the dissipated
  CHECK(e + lost == Approx(e0).epsilon(1e-3 * lost / e0));
}
