// Unit tests of the pieces the contact is built from: rotation vectors, the Hertz stiffness,
// the no-pull clamp, the hysteresis factors chi(c_r) of the normal laws and the friction laws.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "core/contact.hpp"
#include "core/math.hpp"
#include "core/scene.hpp"
#include "fixture.hpp"
#include "sweep/study.hpp"

using namespace rodend;
using namespace rodend::test;

namespace {

constexpr double kPi = std::numbers::pi;
/// A few ulps of an O(1) quantity: rotation-vector formulas involve one atan2, one sqrt and a
/// division, each correctly rounded, so a handful of ulps is all they may lose.
constexpr double kUlps = 8 * std::numeric_limits<double>::epsilon();

InputError thrown_input_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e;
  }
  FAIL("expected an InputError");
  return InputError("", "");
}

ClearanceContactModel steel_model(double chi) {
  ClearanceContactModel m;
  m.ball_radius = 0.01;
  m.clearance = 0.5e-3;
  m.stiffness = 6.9e10;
  m.exponent = 1.5;
  m.hysteresis = chi;
  m.min_impact_speed = 1e-3;
  return m;
}

/// The ball displaced by `pen` beyond the clearance along +x, moving at `rate` along +x
/// (positive: approaching the socket wall), socket fixed at the origin.
BodyKinematics ball_at(const ClearanceContactModel& m, double pen, double rate,
                       const Vec3& tangential_velocity = Vec3::Zero()) {
  BodyKinematics b = BodyKinematics::fixed(Vec3(m.clearance + pen, 0.0, 0.0));
  b.v_W = Vec3(rate, 0.0, 0.0) + tangential_velocity;
  return b;
}

}  // namespace

TEST_CASE("rotation vector: exact at zero, exact for a quarter turn", "[math]") {
  // zero rotation: exactly zero, no 0/0
  CHECK(rotation_vector(Quat::Identity()) == Vec3::Zero());
  // q and -q are the same rotation
  Quat minus_identity(-1.0, 0.0, 0.0, 0.0);
  CHECK(rotation_vector(minus_identity) == Vec3::Zero());

  const Vec3 axis = GENERATE(Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(1, 2, -2) / 3.0);
  const Quat q(Eigen::AngleAxisd(kPi / 2, axis));
  const Vec3 rv = rotation_vector(q);
  CHECK((rv - (kPi / 2) * axis).norm() <= kUlps * kPi);
  Quat flipped = q;
  flipped.coeffs() = -q.coeffs();
  CHECK((rotation_vector(flipped) - (kPi / 2) * axis).norm() <= kUlps * kPi);

  // tiny angles keep their full relative accuracy (the series branch below 1e-7)
  for (double angle : {1e-12, 1e-9, 1e-7, 2e-7, 1e-4}) {
    const Vec3 small = rotation_vector(Quat(Eigen::AngleAxisd(angle, axis)));
    CHECK((small - angle * axis).norm() <= kUlps * angle);
  }
  // a half turn minus a little: the shortest rotation, angle in [0, pi]
  const Vec3 near_pi = rotation_vector(Quat(Eigen::AngleAxisd(kPi - 1e-6, axis)));
  CHECK((near_pi - (kPi - 1e-6) * axis).norm() <= 1e-12);
}

TEST_CASE("rotation vector: quat_from_rotation_vector round trip", "[math]") {
  CHECK(quat_from_rotation_vector(Vec3::Zero()).coeffs() == Quat::Identity().coeffs());
  const Vec3 rv = GENERATE(Vec3(0.3, -0.2, 0.1), Vec3(1.0, 2.0, 0.5), Vec3(-2.9, 0.1, 0.2),
                           Vec3(1e-9, -2e-9, 3e-9), Vec3(1e-8, 0, 0), Vec3(0, 0, kPi / 2));
  const Quat q = quat_from_rotation_vector(rv);
  CHECK(std::abs(q.norm() - 1.0) <= kUlps);
  // the same rotation as Eigen's angle-axis
  const double angle = rv.norm();
  const Quat eigen_q(Eigen::AngleAxisd(angle, rv / angle));
  CHECK(q.angularDistance(eigen_q) <= 1e-7 * std::max(angle, 1e-9));
  // and back
  const Vec3 back = rotation_vector(q);
  CHECK((back - rv).norm() <= kUlps * std::max(rv.norm(), 1e-300) * 4);
}

TEST_CASE("Hertz stiffness of a ball in a socket", "[contact]") {
  // hand value for the defaults: steel/steel E = 206 GPa, nu = 0.3, R_b = 10 mm, c = 0.5 mm:
  // E* = 206e9 / (2 * 0.91) = 1.13187e11 Pa, R* = 0.01 * 0.0105 / 0.0005 = 0.21 m,
  // K = 4/3 * 1.13187e11 * sqrt(0.21) = 6.91583e10 N/m^1.5
  const double K = sphere_in_sphere_stiffness(0.01, 0.0105, 206e9, 0.3, 206e9, 0.3);
  CHECK(K == Approx(6.91583e10).epsilon(1e-5));  // 6 digits given by hand

  // dissimilar materials (steel ball, bronze race) against the sigma form of thesis eq. 3.5:
  // K = 4 / (3 pi (sigma_b + sigma_s)) sqrt(R*), sigma = (1 - nu^2) / (pi E)
  const double Rb = 0.0125, Rs = 0.0128, Eb = 206e9, nub = 0.3, Es = 110e9, nus = 0.34;
  const double sb = (1 - nub * nub) / (kPi * Eb), ss = (1 - nus * nus) / (kPi * Es);
  const double K_sigma = 4.0 / (3.0 * kPi * (sb + ss)) * std::sqrt(Rb * Rs / (Rs - Rb));
  // the two forms are the same expression rearranged: equal to round-off
  CHECK(sphere_in_sphere_stiffness(Rb, Rs, Eb, nub, Es, nus) == Approx(K_sigma).epsilon(1e-14));
  // symmetric in the two materials, and a tighter fit (smaller clearance) is stiffer
  CHECK(sphere_in_sphere_stiffness(Rb, Rs, Es, nus, Eb, nub) == Approx(K_sigma).epsilon(1e-14));
  CHECK(sphere_in_sphere_stiffness(Rb, Rb + 1e-4, Eb, nub, Es, nus) > K_sigma);
}

TEST_CASE("normal force is never negative, however fast the contact separates", "[contact]") {
  // chi up to 14.4 (Flores at c_r = 0.1); separation speeds up to 1e4 times the latched
  // approach speed: raw F_el (1 + chi delta'/delta'^-) is hugely negative, the force is not
  const double chi = GENERATE(0.0, 0.75, 1.5, 14.4);
  const double rate = GENERATE(-1e-4, -0.01, -1.0, -10.0);
  const bool latched = GENERATE(true, false);
  const ClearanceContactModel m = steel_model(chi);
  const BodyKinematics socket = BodyKinematics::fixed(Vec3::Zero());
  const ContactLatch latch{latched, 1e-3};
  const ContactEval e = evaluate_contact(m, ball_at(m, 1e-6, rate), socket, latch);
  CAPTURE(chi, rate, latched, e.normal_force);
  REQUIRE(e.penetration == Approx(1e-6).epsilon(1e-9));
  REQUIRE(e.penetration_rate == Approx(rate).epsilon(1e-12));
  CHECK(e.elastic_force == Approx(m.stiffness * std::pow(1e-6, 1.5)).epsilon(1e-12));
  CHECK(e.normal_force >= 0.0);
  CHECK(e.force_on_ball().x() <= 0.0);  // pushes the ball back toward the centre, or nothing
  CHECK(e.damping_power >= 0.0);        // damping only ever dissipates
  if (chi * std::abs(rate) / std::max(latched ? 1e-3 : std::abs(rate), m.min_impact_speed) > 1.0)
    CHECK(e.normal_force == 0.0);  // fully clamped
  // approaching at the same speed, the damping adds to the elastic force
  const ContactEval a = evaluate_contact(m, ball_at(m, 1e-6, -rate), socket, latch);
  CHECK(a.normal_force >= a.elastic_force);
}

TEST_CASE("no force across a gap", "[contact]") {
  const ClearanceContactModel m = steel_model(0.75);
  const BodyKinematics socket = BodyKinematics::fixed(Vec3::Zero());
  for (double pen : {-1e-4, -1e-12, 0.0}) {
    const ContactEval e =
        evaluate_contact(m, ball_at(m, pen, 1.0, Vec3(0, 0.5, 0)), socket, ContactLatch{true, 1.0});
    CHECK(e.normal_force == 0.0);
    CHECK(e.force_on_ball() == Vec3::Zero());
    CHECK(e.potential == 0.0);
  }
  // concentric spheres: no direction, no force, no NaN
  const ContactEval e0 = evaluate_contact(m, BodyKinematics::fixed(Vec3::Zero()), socket, {});
  CHECK(e0.normal_force == 0.0);
  CHECK(e0.penetration == -m.clearance);
}

TEST_CASE("hysteresis factors chi(c_r) of the normal laws (model-notes §3)", "[contact]") {
  const double cr = GENERATE(0.1, 0.3, 0.5, 0.8, 0.95, 1.0);
  CAPTURE(cr);
  const NormalLaw* ln = find_normal_law("lankarani-nikravesh");
  REQUIRE(ln);
  CHECK(ln->hysteresis_factor(cr) ==
        Approx(3.0 * (1 - cr * cr) / 4.0).epsilon(1e-15).margin(1e-300));
  CHECK(find_normal_law("hertz")->hysteresis_factor(cr) == 0.0);
  CHECK(find_normal_law("hunt-crossley")->hysteresis_factor(cr) ==
        Approx(3.0 * (1 - cr) / 2.0).epsilon(1e-15).margin(1e-300));
  CHECK(find_normal_law("flores")->hysteresis_factor(cr) ==
        Approx(8.0 * (1 - cr) / (5.0 * cr)).epsilon(1e-15).margin(1e-300));
  CHECK(find_normal_law("gonthier")->hysteresis_factor(cr) ==
        Approx((1 - cr * cr) / cr).epsilon(1e-15).margin(1e-300));
  // the flap-actuation study's modified law: Gonthier's chi, meant for the cylinder geometry
  CHECK(find_normal_law("flap-modified")->hysteresis_factor(cr) ==
        Approx((1 - cr * cr) / cr).epsilon(1e-15).margin(1e-300));
  // restitution-matched: chi solved numerically (tests/test_impact_pair.cpp); decreasing in c_r
  const NormalLaw* rm = find_normal_law("restitution-matched");
  REQUIRE(rm);
  if (cr < 1.0) CHECK(rm->hysteresis_factor(cr) > rm->hysteresis_factor(std::min(cr + 0.05, 1.0)));
  // perfectly elastic: every law is undamped at c_r = 1
  if (cr == 1.0)
    for (const NormalLaw* law : normal_laws()) CHECK(law->hysteresis_factor(1.0) == 0.0);
  CHECK(ln->hysteresis_factor(0.0) == 0.75);
  CHECK(find_normal_law("no-such-law") == nullptr);
}

TEST_CASE("laws that divide by c_r reject c_r = 0 when a scene is built", "[contact]") {
  const std::string scene = GENERATE(as<std::string>{}, "gravity-drop", "spring-contact");
  const std::string law =
      GENERATE(as<std::string>{}, "flores", "gonthier", "flap-modified", "restitution-matched");
  ParameterSet p = ParameterSet::defaults_for(scene);
  p.set("contact.law", law);
  p.set("contact.restitution", 0.0);
  const InputError e = thrown_input_error([&] { make_scene(scene, p); });
  CHECK(e.key_path() == "contact.restitution");
  // a small positive c_r is fine
  p.set("contact.restitution", 0.05);
  CHECK_NOTHROW(make_scene(scene, p));
  // and the laws that stay finite accept c_r = 0
  for (const char* ok : {"hertz", "hunt-crossley", "lankarani-nikravesh"}) {
    p.set("contact.law", ok);
    p.set("contact.restitution", 0.0);
    CHECK_NOTHROW(make_scene(scene, p));
  }
}

TEST_CASE("thesis friction law: 0 at rest, mu_st at v_st, mu_dyn at v_dyn, continuous",
          "[friction]") {
  const double mu_v = GENERATE(0.0, 0.5);  // without and with the viscous term [s/m]
  FrictionParams f;
  f.law = FrictionLawKind::thesis;
  f.static_coefficient = 0.12;
  f.dynamic_coefficient = 0.1;
  f.static_speed = 1e-3;
  f.dynamic_speed = 5e-3;
  f.viscous_coefficient = mu_v;
  const auto law = make_friction_law(f);
  REQUIRE(law);
  CAPTURE(mu_v);
  // endpoints of the blends (thesis 3.9-3.10): to round-off
  CHECK(law->coefficient(0.0) == 0.0);
  CHECK(law->coefficient(f.static_speed) == Approx(f.static_coefficient).epsilon(1e-14));
  CHECK(law->coefficient(f.dynamic_speed) == Approx(f.dynamic_coefficient).epsilon(1e-14));
  // beyond v_dyn: mu_dyn plus the viscous term
  CHECK(law->coefficient(0.1) ==
        Approx(f.dynamic_coefficient + mu_v * (0.1 - f.dynamic_speed)).epsilon(1e-14));
  // continuous (Lipschitz): no step anywhere, including at v_st and v_dyn. The largest slope
  // of the cubic step is 1.5 x (rise / width) at mid-blend; the viscous slope adds mu_v.
  const double slope = 1.5 * std::max(2 * f.static_coefficient / (2 * f.static_speed),
                                      (f.static_coefficient - f.dynamic_coefficient) /
                                          (f.dynamic_speed - f.static_speed)) +
                       mu_v;
  const double h = 1e-7;
  double worst = 0.0;
  for (double v = 0.0; v < 2 * f.dynamic_speed; v += h) {
    const double jump = std::abs(law->coefficient(v + h) - law->coefficient(v));
    worst = std::max(worst, jump / (slope * h));
    REQUIRE(law->coefficient(v) >= 0.0);
  }
  measured("thesis friction: max |d mu| / (max slope * dv)", worst, 1.0);
  CHECK(worst <= 1.0 + 1e-6);  // the slope bound, plus round-off of mu over dv = 1e-7
  // rising to the static peak, then falling to the dynamic value
  CHECK(law->coefficient(0.5 * f.static_speed) > 0.0);
  CHECK(law->coefficient(0.5 * f.static_speed) < f.static_coefficient);
  CHECK(law->coefficient(3e-3) < f.static_coefficient);
  CHECK(law->coefficient(3e-3) > f.dynamic_coefficient);
}

TEST_CASE("thesis friction law: slope continuous at v_st and v_dyn, falling between them",
          "[friction]") {
  // issue 34: the pieces of eq. 3.9-3.10 join with the same value and the same slope (each
  // cubic step is flat at both its ends), so neither join is a kink; what makes loaded cases
  // slow is the falling blend between the joins (docs/performance.md, "The thesis friction
  // law under a sustained hinge moment")
  const double mu_v = GENERATE(0.0, 0.5);  // without and with the viscous term [s/m]
  FrictionParams f;
  f.law = FrictionLawKind::thesis;
  f.static_coefficient = 0.12;
  f.dynamic_coefficient = 0.1;
  f.static_speed = 1e-3;
  f.dynamic_speed = 5e-3;
  f.viscous_coefficient = mu_v;
  const auto law = make_friction_law(f);
  REQUIRE(law);
  CAPTURE(mu_v);
  // one-sided difference quotients over h: each differs from the one-sided derivative by at
  // most |mu''| h / 2, |mu''| <= 6 (rise / width^2) = 3.6e5 s^2/m^2 on the static step, so
  // 1.8e-4 s/m at h = 1e-9 m/s, plus round-off 2 eps mu / h ~ 6e-8 s/m. A kink would show as
  // the one-sided slopes differing by the blends' own slopes, 180 or 7.5 s/m.
  const double h = 1e-9;
  const double bound =
      0.5 * 6.0 * 2 * f.static_coefficient / std::pow(2 * f.static_speed, 2) * h + 1e-6;
  for (const double join : {f.static_speed, f.dynamic_speed}) {
    CAPTURE(join);
    const double left = (law->coefficient(join) - law->coefficient(join - h)) / h;
    const double right = (law->coefficient(join + h) - law->coefficient(join)) / h;
    CHECK(std::abs(left - mu_v) <= bound);  // flat ends of both cubic steps, plus mu_v
    CHECK(std::abs(right - mu_v) <= bound);
  }
  // between the joins mu falls from mu_st to mu_dyn (the Stribeck drop of eq. 3.9): the cubic
  // step carries the base values mu_st - mu_v v_st to mu_dyn - mu_v v_dyn, so its slope at
  // mid-blend is mu_v - 1.5 (their difference) / (v_dyn - v_st), -7.5 s/m without the viscous
  // term: the negative damping that makes a loaded contact break away (a Jacobian eigenvalue
  // of +1.8e5 1/s at 3 mm/s and 933 N in rod-end-actuator, rodend-eigen --breakaway)
  const double mid = 0.5 * (f.static_speed + f.dynamic_speed), dv = 1e-8;
  const double falling = (law->coefficient(mid + dv) - law->coefficient(mid - dv)) / (2 * dv);
  const double drop = 1.5 *
                      ((f.static_coefficient - mu_v * f.static_speed) -
                       (f.dynamic_coefficient - mu_v * f.dynamic_speed)) /
                      (f.dynamic_speed - f.static_speed);
  CHECK(falling == Approx(mu_v - drop).epsilon(1e-6));
}

TEST_CASE("thesis friction law: the sliding force above v_dyn", "[friction]") {
  // what the law gives in sliding, pinned in closed form: F_t = -(mu_dyn + mu_v (v - v_dyn))
  // F_n v_t/|v_t| at every slip speed above v_dyn (eq. 3.9; any change to the blends below
  // v_dyn must leave this as it is)
  const double mu_v = GENERATE(0.0, 0.5);
  const double v = GENERATE(5.0001e-3, 6e-3, 1e-2, 0.1, 1.0);
  FrictionParams fp;
  fp.law = FrictionLawKind::thesis;
  fp.static_coefficient = 0.12;
  fp.dynamic_coefficient = 0.1;
  fp.static_speed = 1e-3;
  fp.dynamic_speed = 5e-3;
  fp.viscous_coefficient = mu_v;
  ClearanceContactModel m = steel_model(0.0);
  m.friction = make_friction_law(fp);
  CAPTURE(mu_v, v);
  // ball pressed 1 um into the wall along +x, sliding along y and z
  const Vec3 vt = v * Vec3(0.0, 0.6, 0.8);
  const ContactEval e = evaluate_contact(m, ball_at(m, 1e-6, 0.0, vt),
                                         BodyKinematics::fixed(Vec3::Zero()), {true, 1e-3});
  REQUIRE(e.normal_force > 0.0);
  const double mu = fp.dynamic_coefficient + mu_v * (v - fp.dynamic_speed);
  const Vec3 expected = -mu * e.normal_force * Vec3(0.0, 0.6, 0.8);
  CHECK((e.friction_on_ball - expected).norm() <= 1e-13 * expected.norm());
  CHECK(e.friction_power == Approx(mu * e.normal_force * v).epsilon(1e-13));
}

TEST_CASE("friction opposes the slip with mu F_n", "[friction]") {
  FrictionParams fp;
  fp.law = FrictionLawKind::thesis;
  fp.static_coefficient = 0.12;
  fp.dynamic_coefficient = 0.1;
  fp.static_speed = 1e-3;
  fp.dynamic_speed = 5e-3;
  ClearanceContactModel m = steel_model(0.0);
  m.friction = make_friction_law(fp);
  const BodyKinematics socket = BodyKinematics::fixed(Vec3::Zero());
  // ball pressed 1 um into the wall along +x, sliding along +y at 0.1 m/s (> v_dyn)
  const ContactEval e =
      evaluate_contact(m, ball_at(m, 1e-6, 0.0, Vec3(0.0, 0.1, 0.0)), socket, {true, 1e-3});
  REQUIRE(e.normal_force > 0.0);
  CHECK(e.slip_speed == Approx(0.1).epsilon(1e-12));
  CHECK(e.friction_on_ball.y() == Approx(-0.1 * e.normal_force).epsilon(1e-12));
  CHECK(e.friction_on_ball.x() == 0.0);
  CHECK(e.friction_power == Approx(0.1 * e.normal_force * 0.1).epsilon(1e-12));
  // moment r x F_t with each sphere's own radius (model-notes §1): about -z... r = R n = +x,
  // F_t along -y, so r x F_t is along -z with magnitude R |F_t|
  CHECK(e.moment_on_ball.z() == Approx(-m.ball_radius * 0.1 * e.normal_force).epsilon(1e-12));
  CHECK(e.moment_on_socket.z() == Approx(m.socket_radius() * 0.1 * e.normal_force).epsilon(1e-12));
  // a spin that cancels the slip at the contact point: no friction (thesis 3.12-3.13)
  BodyKinematics rolling = ball_at(m, 1e-6, 0.0, Vec3(0.0, 0.1, 0.0));
  rolling.w_W = Vec3(0.0, 0.0, -0.1 / m.ball_radius);  // w x (R n) = -0.1 y
  const ContactEval r = evaluate_contact(m, rolling, socket, {true, 1e-3});
  CHECK(r.slip_speed == Approx(0.0).margin(1e-15));
  CHECK(r.friction_on_ball.norm() == Approx(0.0).margin(1e-15));
}

TEST_CASE("the other friction laws", "[friction]") {
  FrictionParams f;
  f.static_coefficient = 0.12;
  f.dynamic_coefficient = 0.1;
  f.static_speed = 1e-3;
  f.dynamic_speed = 5e-3;
  f.law = FrictionLawKind::ambrosio;  // c_f c_d, c_d linear from 0 at v0 to 1 at v1
  const auto amb = make_friction_law(f);
  CHECK(amb->coefficient(0.0) == 0.0);
  CHECK(amb->coefficient(f.static_speed) == 0.0);
  CHECK(amb->coefficient(3e-3) == Approx(0.1 * 0.5).epsilon(1e-14));
  CHECK(amb->coefficient(f.dynamic_speed) == Approx(0.1).epsilon(1e-14));
  CHECK(amb->coefficient(1.0) == Approx(0.1).epsilon(1e-14));
  f.law = FrictionLawKind::coulomb;
  const auto coul = make_friction_law(f);
  CHECK(coul->coefficient(0.0) == 0.0);
  CHECK(coul->coefficient(1.0) == Approx(0.1).epsilon(1e-14));
  f.law = FrictionLawKind::none;
  CHECK(make_friction_law(f) == nullptr);
  CHECK_FALSE(choice_from_name<FrictionLawKind>("bogus"));  // no such law: read as an error
}

TEST_CASE("every friction law: mu(0) = 0, continuous, its limits", "[friction]") {
  // the laws share FrictionParams; each uses the coefficients it needs (contact.hpp)
  FrictionParams f;
  f.static_coefficient = 0.12;
  f.dynamic_coefficient = 0.1;
  f.static_speed = 1e-3;
  f.dynamic_speed = 5e-3;
  f.viscous_coefficient = 0.0;
  const std::string name = GENERATE(as<std::string>{}, "thesis", "ambrosio", "coulomb", "none");
  CAPTURE(name);
  f.law = *choice_from_name<FrictionLawKind>(name);
  const auto law = make_friction_law(f);
  if (name == "none") {
    // no law object: the contact then applies no friction at all
    REQUIRE(law == nullptr);
    ClearanceContactModel m = steel_model(0.0);
    m.friction = nullptr;
    const ContactEval e = evaluate_contact(m, ball_at(m, 1e-6, 0.0, Vec3(0.0, 0.1, 0.0)),
                                           BodyKinematics::fixed(Vec3::Zero()), {true, 1e-3});
    REQUIRE(e.normal_force > 0.0);
    CHECK(e.friction_on_ball == Vec3::Zero());
    CHECK(e.friction_power == 0.0);
    return;
  }
  REQUIRE(law);
  CHECK(law->name() == name);
  // mu(0) = 0 exactly: the friction force -mu F_n v_t/|v_t| then goes to 0 with the slip,
  // continuous through zero slip whatever its direction
  CHECK(law->coefficient(0.0) == 0.0);
  // Lipschitz: no jump anywhere on [0, 4 v_dyn]; slope bounds by hand: thesis 1.5 x the
  // steepest blend (rise / width), Ambrosio c_f / (v1 - v0), Coulomb mu / v_eps (tanh' <= 1)
  const double slope =
      name == "thesis"     ? 1.5 * std::max(2 * f.static_coefficient / (2 * f.static_speed),
                                            (f.static_coefficient - f.dynamic_coefficient) /
                                                (f.dynamic_speed - f.static_speed))
      : name == "ambrosio" ? f.dynamic_coefficient / (f.dynamic_speed - f.static_speed)
                           : f.dynamic_coefficient / f.static_speed;
  const double h = 1e-7;
  double worst = 0.0;
  for (double v = 0.0; v < 4 * f.dynamic_speed; v += h) {
    worst = std::max(worst, std::abs(law->coefficient(v + h) - law->coefficient(v)) / (slope * h));
    REQUIRE(law->coefficient(v) >= 0.0);
  }
  measured(name + " friction: max |d mu| / (slope bound * dv)", worst, 1.0);
  CHECK(worst <= 1.0 + 1e-6);  // the slope bound, plus round-off of mu over dv = 1e-7
  // limits at large slip: the dynamic coefficient (no viscous term here); tanh(1000) = 1
  CHECK(law->coefficient(1.0) == Approx(f.dynamic_coefficient).epsilon(1e-14));
  CHECK(law->coefficient(100.0) == Approx(f.dynamic_coefficient).epsilon(1e-14));
  // near zero slip: thesis and Coulomb rise at once (slope 1.5 mu_st/v_st for the cubic step
  // centred on 0, mu/v_eps for tanh); Ambrosio is 0 up to v0
  const double small = 1e-9;
  if (name == "thesis")
    CHECK(law->coefficient(small) / small ==
          Approx(1.5 * f.static_coefficient / f.static_speed).epsilon(1e-5));
  if (name == "coulomb")
    CHECK(law->coefficient(small) / small ==
          Approx(f.dynamic_coefficient / f.static_speed).epsilon(1e-5));
  if (name == "ambrosio") CHECK(law->coefficient(0.999 * f.static_speed) == 0.0);
}

TEST_CASE("the contact and friction laws are selectable per study", "[friction][contact]") {
  // every scene with a contact lists exactly the catalogues' laws as choices of contact.law
  // and friction.law, and a study can pick each of them (parameters.friction.law)
  std::vector<std::string> normal, friction;
  for (const NormalLaw* l : normal_laws()) normal.emplace_back(l->name());
  for (std::string_view n : choice_names(FrictionLawKind{})) friction.emplace_back(n);
  for (const SceneEntry& s : scene_catalogue()) {
    const ParameterSet p = ParameterSet::defaults_for(s.name);
    if (!p.has("contact.law")) continue;
    CAPTURE(s.name);
    const Json leaves = p.leaves();
    CHECK(leaves.at("contact.law").at("choices").get<std::vector<std::string>>() == normal);
    CHECK(leaves.at("friction.law").at("choices").get<std::vector<std::string>>() == friction);
    CHECK(leaves.at("contact.geometry").at("choices").get<std::vector<std::string>>() ==
          std::vector<std::string>{"sphere", "cylinder"});
    for (const std::string& law : friction) {
      ParameterSet q = p;
      q.set("friction.law", law);
      CHECK_NOTHROW(make_scene(s.name, q));
    }
  }
  // through a study file, as a grid axis
  const Json doc = {{"scene", "impact-pair"},
                    {"time", {{"end", 1e-4}, {"sample_interval", 1e-5}}},
                    {"grid", {{{"key", "parameters.friction.law"}, {"values", friction}}}}};
  const Study study = parse_study(doc, "friction-laws.json");
  REQUIRE(study.cases.size() == friction.size());
  for (std::size_t i = 0; i < friction.size(); ++i)
    CHECK(study.cases[i].parameters.text("friction.law") == friction[i]);
}
