#include "core/scenes/rod_end_mechanism.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "core/contact_eval.hpp"
#include "core/contact_stick.hpp"
#include "core/scenes/contact_length_scale.hpp"
#include "core/scenes/parts.hpp"

namespace rodend {
namespace {

SliderCrank read_geometry(const ParameterSet& p) {
  const double s = read_positive(p, "geometry.crank");
  const double t = read_positive(p, "geometry.frame");
  const double l0 = read_positive(p, "geometry.rod");
  try {
    return SliderCrank(s, t, l0);
  } catch (const std::invalid_argument& e) {
    throw InputError("geometry.rod",
                     std::string(e.what()) + ": need |frame - crank| < rod < frame + crank");
  }
}

std::optional<WearModel> read_wear(const ParameterSet& p) {
  switch (read_choice<WearModelKind>(p, "wear.model")) {
    case WearModelKind::none:
      return std::nullopt;
    case WearModelKind::archard:
      break;
  }
  WearModel w;
  w.ball = {read_positive(p, "wear.ball_coefficient", true),
            read_positive(p, "wear.ball_hardness")};
  w.socket = {read_positive(p, "wear.socket_coefficient", true),
              read_positive(p, "wear.socket_hardness")};
  auto cells = [&](const char* key, int lo) {
    const double v = p.number(key);
    if (!(v >= lo && v <= 4096 && v == std::floor(v)))
      throw InputError(key, "expected a whole number of cells from " + std::to_string(lo) +
                                " to 4096, got " + format_number(v));
    return static_cast<int>(v);
  };
  w.n_longitude = cells("wear.map_longitude_cells", 4);
  w.n_latitude = cells("wear.map_latitude_cells", 2);
  return w;
}

/// The rotation about z by the angle whose cosine and sine are c, s: the unit quaternion of
/// the half angle, from the half-angle identities (the branch that does not cancel).
template <class S>
QuatT<S> about_z(const S& c, const S& s) {
  using std::sqrt;
  if (c >= 0.0) {
    const S ch = sqrt(0.5 * (1.0 + c));  // cos(angle/2) >= 1/sqrt(2)
    return QuatT<S>(ch, S(0.0), S(0.0), 0.5 * s / ch);
  }
  const S root = sqrt(0.5 * (1.0 - c));
  // copysign(root, s) (root > 0); |sin(angle/2)| >= 1/sqrt(2)
  const S sh = std::signbit(value_of(s)) ? S(-root) : root;
  return QuatT<S>(0.5 * s / sh, S(0.0), S(0.0), sh);
}

}  // namespace

RodEndMechanism::RodEndMechanism(const ParameterSet& p)
    : geometry_(read_geometry(p)),
      ball_(read_body(p, "ball")),
      socket_(read_body(p, "socket")),
      contact_(read_clearance_contact(p, "contact", "friction", {}, true)),
      slider_spring_(read_spring(p, "slider_spring")),
      crank_spring_(read_spring(p, "crank_spring")),
      hinge_(read_hinge(p, "hinge")),
      gravity_(p.vec3("gravity")),
      misalignment_z_(p.number("socket.misalignment_z")),
      wear_(read_wear(p)) {
  const double m = read_positive(p, "surface.mass", true);
  const double I = read_positive(p, "surface.inertia", true);
  const double s = geometry_.crank();
  surface_inertia_ = m * (s / 3.0) * (s / 3.0) + I;  // eq. 4.16 with the typo of 4.15 fixed
  if (!(surface_inertia_ > 0.0))
    throw InputError("surface.inertia", "the surface needs a mass or an inertia > 0");
  surface_damping_ = read_positive(p, "surface.damping", true);
  if (wear_) {
    wear_->ball_radius = contact_.ball_radius;
    wear_->socket_radius = contact_.socket_radius();
  }
}

void RodEndMechanism::check_closure(const Input& motion, const std::string& key,
                                    const std::string& short_key) const {
  // scan the whole profile finely: the extremes are at the ends of the strokes, but a scan
  // also reports the first offending time
  // cycles after the second repeat it (each starts from -retraction), so two cycles cover the
  // whole profile and the scan stays bounded for any cycle count (up to the 1e6 allowed)
  // the rod extension is monotonic within each stroke and constant in the holds (drivers.cpp:
  // both stroke shapes rise monotonically), so it spans [-retraction, extension] over the whole
  // profile (a waveform spans offset -+ amplitude: Input::range): when both ends close,
  // every instant does, and the scan below (which finds the first offending time) is needed only
  // when one does not. This keeps the check cheap when a large grid is validated.
  {
    const double margin = 1e-6 * geometry_.max_rod();
    const auto [lo, hi] = motion.range();
    // the range with the start, 0
    const double shortest = geometry_.rod_zero() + std::min(0.0, lo);
    const double longest = geometry_.rod_zero() + std::max(0.0, hi);
    if (shortest > geometry_.min_rod() + margin && longest < geometry_.max_rod() - margin) return;
  }
  // a stroke's cycles after the second repeat it; a waveform is scanned over its whole window
  const auto [T, n] = motion.scan();
  for (int i = 0; i <= n; ++i) {
    const double t = T * i / n;
    const double l = geometry_.rod_zero() + motion.at(t).value;
    // a margin keeps d(rod angle)/dl (which divides by sin alpha) finite
    const double margin = 1e-6 * geometry_.max_rod();
    if (l <= geometry_.min_rod() + margin || l >= geometry_.max_rod() - margin) {
      std::ostringstream m;
      m << "the mechanism cannot close: rod length " << l << " m at t = " << t << " s is outside ("
        << geometry_.min_rod() << ", " << geometry_.max_rod()
        << ") m = (|frame - crank|, frame + crank)";
      const bool too_short = l <= geometry_.min_rod() + margin;
      throw InputError(too_short && !short_key.empty() ? short_key : key, m.str());
    }
  }
}

void RodEndMechanism::initial_state(double* x) const {
  // both spheres at the rod end of the mechanism at rest (thesis §5); the socket offset along
  // z by the misalignment (thesis "initial condition"). A misalignment beyond the clearance is
  // a forced assembly: the socket starts against the ball (zero penetration, never inside it)
  // and the slider spring, whose anchor keeps the full offset, carries the excess as a preload
  // (README "Modelling decisions": an initial penetration would release the stiff Hertz
  // contact's energy at once, 24 kN and 0.5 J at 1.1 x the default clearance)
  const double c = contact_.clearance;
  body_initial_state(x + kBall, Vec3::Zero());
  body_initial_state(x + kSocket, Vec3(0.0, 0.0, std::clamp(misalignment_z_, -c, c)));
  x[kTheta] = 0.0;
  x[kThetaDot] = 0.0;
}

void RodEndMechanism::state_scale(double* s) const {
  // lengths on a fixed 10 um, whatever the clearance (contact_length_scale.hpp), speeds on
  // 0.1 m/s (the actuator's rate), angles on 1 mrad
  const double L = contact_length_scale(), V = 0.1;
  for (int b : {kBall, kSocket}) body_state_scale(s + b, L, V, V / contact_.ball_radius);
  s[kTheta] = 1e-3;
  s[kThetaDot] = V / geometry_.crank();
}

std::vector<SignalId> RodEndMechanism::scene_signals(std::span<const SignalId> own) const {
  // time and the bodies, the contact, the rod and crank
  static constexpr auto kMechanism =
      concat(SignalId::time, kBallAndSocket, kContactSignals, SignalId::actuator_position,
             SignalId::actuator_velocity, SignalId::rod_inclination, SignalId::slider_end_position,
             SignalId::crank_end_position, SignalId::surface_angle, SignalId::surface_angle_command,
             SignalId::surface_rate, SignalId::surface_acceleration, SignalId::hinge_moment,
             SignalId::slider_spring_force, SignalId::slider_spring_axial_force,
             SignalId::slider_spring_moment, SignalId::crank_spring_force,
             SignalId::crank_spring_axial_force, SignalId::crank_spring_moment);
  std::vector<SignalId> v(kMechanism.begin(), kMechanism.end());
  v.insert(v.end(), own.begin(), own.end());
  v.insert(v.end(), kBodyAudit.begin(), kBodyAudit.end());
  if (wear_) v.insert(v.end(), {SignalId::sliding_work, SignalId::worn_volume});
  return v;
}

void RodEndMechanism::write_wear_signals(double sliding_work, SignalFrame& f) const {
  if (!wear_) return;
  f.set(SignalId::sliding_work, sliding_work);
  f.set(SignalId::worn_volume, worn_volume_per_work() * sliding_work);
}

double RodEndMechanism::worn_volume_per_work() const {
  return wear_ ? wear_->ball.rate() + wear_->socket.rate() : 0.0;
}

WearSource RodEndMechanism::wear_source(const Eval& e) const {
  WearSource w;
  const ContactEval& c = e.contact;
  if (!(c.normal_force > 0.0)) return w;
  w.sliding_power = sliding_power(e);
  // the contact point lies along n from both centres: the same world direction, read in each
  // body's frame
  w.direction_ball_B = e.ball.R_WB.transpose() * c.normal;
  w.direction_socket_B = e.socket.R_WB.transpose() * c.normal;
  // Hertz contact radius a = sqrt(R* delta), R* = R_b R_s / (R_s - R_b) of the nominal
  // surfaces (model-notes §1): wear deepens the race by micrometres, it does not change its
  // curvature at the scale of the patch. For a cylinder the same relation is used for the
  // half-width (the patch then spreads the wear over the same angular width).
  const double Rb = contact_.ball_radius, Rs = contact_.socket_radius();
  w.patch_radius = std::sqrt(Rb * Rs / (Rs - Rb) * std::max(c.penetration, 0.0));
  return w;
}

void RodEndMechanism::set_worn_surfaces(std::shared_ptr<const WornSurfaces> worn) {
  contact_.worn = std::move(worn);
}

JointPlay RodEndMechanism::joint_play(const Eval& e) const {
  // The play as the contact model sees it: the ball centre, moved from the socket centre along
  // a unit direction d, touches when its distance reaches the local clearance c(d) (contact.hpp:
  // the contact direction is the direction of the eccentricity). A groove in that direction
  // counts in full, however narrow (the local-clearance model; README "Wear").
  auto local = [&](const Vec3& d) {
    return contact_.clearance +
           (contact_.worn ? contact_.worn->extra_clearance(d, e.ball.R_WB, e.socket.R_WB) : 0.0);
  };
  JointPlay j;
  // the ball can move along the rod from contact on one side to contact on the other
  const double play = local(e.rod_direction) + local(-e.rod_direction);
  j.axial_clearance = 0.5 * play;
  // the surface turns by the play over d(rod length)/d(theta) of the ideal mechanism
  const double l = e.rod_length, h = 1e-6 * geometry_.max_rod();
  const double dtheta_dl =
      (geometry_.ideal_crank_angle(l + h) - geometry_.ideal_crank_angle(l - h)) / (2.0 * h);
  j.surface_backlash = play * std::abs(dtheta_dl);
  // the largest local clearance over directions in the mechanism plane, every 0.5 degree
  j.max_clearance = contact_.clearance;
  if (contact_.worn)
    for (int k = 0; k < 720; ++k) {
      const double phi = k * (0.5 * std::numbers::pi / 180.0);
      j.max_clearance = std::max(j.max_clearance, local(Vec3(std::cos(phi), std::sin(phi), 0.0)));
    }
  return j;
}

ContactGap RodEndMechanism::gap(const double* x) const {
  return contact_gap(contact_, BodyKinematics::from_state(x + kBall),
                     BodyKinematics::from_state(x + kSocket));
}

ContactSnapshot RodEndMechanism::contact_snapshot(const double* x, const ContactLatch& l) const {
  const ContactEval c = evaluate_normal_contact(contact_, BodyKinematics::from_state(x + kBall),
                                                BodyKinematics::from_state(x + kSocket), l);
  return {c.penetration, c.penetration_rate, c.eccentricity, c.normal_force};
}

namespace {

/// The hinge moment at (t, theta), and for a dual its derivative through Input::slope
/// (without a call when there is none).
double hinge_at(const Input& h, double t, double theta) {
  return h.is_zero() ? 0.0 : h.value(t, theta);
}
template <int N>
Dual<N> hinge_at(const Input& h, double t, const Dual<N>& theta) {
  return Dual<N>::chain(theta, h.is_zero() ? 0.0 : h.value(t, theta.v), h.slope());
}

}  // namespace

template <class S>
void RodEndMechanism::kinematics(const S& u, const S& u_dot, const S* x, EvalT<S>& e) const {
  e.ball = BodyKinematicsT<S>::from_state(x + kBall);
  e.socket = BodyKinematicsT<S>::from_state(x + kSocket);
  e.theta = x[kTheta];
  e.theta_dot = x[kThetaDot];

  // rod end from the rod length (eq. 4.1-4.3, differentiated for the velocity): one law of
  // cosines gives the rod's direction; its rotation about z is the half-angle quaternion
  e.rod_length = geometry_.rod_zero() + u;
  const RodKinematicsT<S> rod = geometry_.rod_kinematics(e.rod_length, u_dot);
  e.rod_angle_rate = rod.angle_rate;
  e.rod_direction = rod.direction();
  e.slider_anchor.p_W = rod.end + Vec3(0.0, 0.0, misalignment_z_);
  e.slider_anchor.v_W = rod.end_velocity;
  e.slider_anchor.q_ref = about_z(rod.cos_angle, rod.sin_angle);  // rod angle 0 at actuator zero
  e.slider_anchor.w_ref_W = Vec3T<S>(S(0.0), S(0.0), e.rod_angle_rate);

  // crank end from the crank angle (eq. 4.17-4.21)
  const CrankKinematicsT<S> crank = geometry_.crank_kinematics(e.theta, e.theta_dot);
  e.crank_anchor.p_W = crank.end;
  e.crank_anchor.v_W = crank.end_velocity;
  e.crank_anchor.q_ref = QuatT<S>(crank.cos_half, S(0.0), S(0.0), crank.sin_half);
  e.crank_anchor.w_ref_W = Vec3T<S>(S(0.0), S(0.0), e.theta_dot);
}

template <class S>
RodEndMechanism::EvalT<S> RodEndMechanism::evaluate(double t, const S& u, const S& u_dot,
                                                    const S* x, const ContactLatch& latch) const {
  EvalT<S> e;
  kinematics(u, u_dot, x, e);
  e.contact = evaluate_contact(contact_, e.ball, e.socket, latch);
  e.slider_spring = evaluate_spring(slider_spring_, e.slider_anchor, e.socket);
  e.crank_spring = evaluate_spring(crank_spring_, e.crank_anchor, e.ball);

  // the crank takes the reaction of the ball spring at its end; only the in-plane components
  // do work (the hinge bearing takes the rest) (thesis eq. 4.12-4.14 in vector form)
  const Vec3T<S> arm = e.crank_anchor.p_W - geometry_.crank_pivot();
  e.crank_torque = arm.cross(-e.crank_spring.force_on_body).z() - e.crank_spring.moment_on_body.z();
  e.hinge_moment = hinge_at(*hinge_, t, e.theta);
  if (contact_.stick && latch.in_contact && !latch.slipping && e.contact.normal_force > 0.0)
    hold_stuck_contact(e);
  return e;
}

template <class S>
void RodEndMechanism::hold_stuck_contact(EvalT<S>& e) const {
  // the other forces and moments on each sphere, as derivatives() sums them (the contact's
  // holds its normal force and, on worn surfaces, that force's moments)
  StickBody<S> ball{
      &e.ball,
      1.0 / ball_.mass,
      ball_.inertia,
      true,
      ball_.mass * gravity_ + e.contact.normal_force_on_ball + e.crank_spring.force_on_body,
      e.contact.moment_on_ball + e.crank_spring.moment_on_body,
      contact_.ball_radius};
  StickBody<S> socket{
      &e.socket,
      1.0 / socket_.mass,
      socket_.inertia,
      true,
      socket_.mass * gravity_ - e.contact.normal_force_on_ball + e.slider_spring.force_on_body,
      e.contact.moment_on_socket + e.slider_spring.moment_on_body,
      contact_.socket_radius()};
  apply_stick(contact_, e.contact, ball, socket, stick_force(e.contact, ball, socket));
}

RodEndMechanism::Eval RodEndMechanism::evaluate_state(double t, double u, double u_dot,
                                                      const double* x,
                                                      const ContactLatch& latch) const {
  Eval e;
  kinematics(u, u_dot, x, e);
  e.contact = evaluate_contact(contact_, e.ball, e.socket, latch);
  e.hinge_moment = hinge_at(*hinge_, t, e.theta);
  return e;
}

template <class S>
void RodEndMechanism::derivatives(const EvalT<S>& e, const S* x, S* dxdt) const {
  const Vec3T<S> F_ball =
      ball_.mass * gravity_ + e.contact.force_on_ball() + e.crank_spring.force_on_body;
  const Vec3T<S> M_ball = e.contact.moment_on_ball + e.crank_spring.moment_on_body;
  const Vec3T<S> F_socket =
      socket_.mass * gravity_ - e.contact.force_on_ball() + e.slider_spring.force_on_body;
  const Vec3T<S> M_socket = e.contact.moment_on_socket + e.slider_spring.moment_on_body;
  body_derivatives(ball_, e.ball, F_ball, M_ball, x + kBall, dxdt + kBall);
  body_derivatives(socket_, e.socket, F_socket, M_socket, x + kSocket, dxdt + kSocket);
  // crank and surface: (m (s/3)^2 + I) theta'' = F s - c theta' + M_hinge (eq. 4.16, fixed)
  dxdt[kTheta] = e.theta_dot;
  dxdt[kThetaDot] =
      (e.crank_torque - surface_damping_ * e.theta_dot + e.hinge_moment) / surface_inertia_;
}

template <class S>
S RodEndMechanism::input_power(const EvalT<S>& e) const {
  return e.slider_spring.anchor_power + e.hinge_moment * e.theta_dot;
}

template <class S>
S RodEndMechanism::dissipated_power(const EvalT<S>& e) const {
  return e.contact.damping_power + e.contact.friction_power + e.slider_spring.damping_power +
         e.crank_spring.damping_power + surface_damping_ * e.theta_dot * e.theta_dot;
}

#define RODEND_MECHANISM_SCALAR(S)                                                          \
  template RodEndMechanism::EvalT<S> RodEndMechanism::evaluate(                             \
      double, const S&, const S&, const S*, const ContactLatch&) const;                     \
  template void RodEndMechanism::kinematics(const S&, const S&, const S*, EvalT<S>&) const; \
  template void RodEndMechanism::derivatives(const EvalT<S>&, const S*, S*) const;          \
  template S RodEndMechanism::input_power(const EvalT<S>&) const;                           \
  template S RodEndMechanism::dissipated_power(const EvalT<S>&) const;
RODEND_MECHANISM_SCALAR(double)
RODEND_MECHANISM_SCALAR(RodEndMechanism::KinematicDual)
RODEND_MECHANISM_SCALAR(RodEndMechanism::ActuatorDual)
#undef RODEND_MECHANISM_SCALAR

double RodEndMechanism::kinetic_energy(const Eval& e) const {
  return rodend::kinetic_energy(ball_, e.ball) + rodend::kinetic_energy(socket_, e.socket) +
         0.5 * surface_inertia_ * e.theta_dot * e.theta_dot;
}

double RodEndMechanism::mechanical_energy(const Eval& e) const {
  return mechanical_energy(e, kinetic_energy(e));
}

double RodEndMechanism::mechanical_energy(const Eval& e, double kinetic) const {
  return kinetic - ball_.mass * gravity_.dot(e.ball.p_W) -
         socket_.mass * gravity_.dot(e.socket.p_W) + e.contact.potential +
         spring_potential(slider_spring_, e.slider_anchor, e.socket) +
         spring_potential(crank_spring_, e.crank_anchor, e.ball);
}

double RodEndMechanism::surface_acceleration(const Eval& e) const {
  // the crank spring's torque on the crank, as evaluate() has it: a step frame may come from
  // evaluate_state(), which leaves the springs out
  const auto spring = evaluate_spring(crank_spring_, e.crank_anchor, e.ball);
  const Vec3 arm = e.crank_anchor.p_W - geometry_.crank_pivot();
  const double torque = arm.cross(-spring.force_on_body).z() - spring.moment_on_body.z();
  // the surface's equation of motion (derivatives(), eq. 4.16)
  return (torque - surface_damping_ * e.theta_dot + e.hinge_moment) / surface_inertia_;
}

void RodEndMechanism::step_outputs(const Eval& e, double command, double kinetic,
                                   SignalFrame& f) const {
  f.set(SignalId::surface_angle, e.theta);
  f.set(SignalId::hinge_moment, e.hinge_moment);
  f.set(SignalId::surface_angle_command,
        geometry_.ideal_crank_angle(geometry_.rod_zero() + command));  // thesis eq. 4.1
  f.set(SignalId::surface_acceleration, surface_acceleration(e));
  f.set(SignalId::kinetic_energy, kinetic);
}

void RodEndMechanism::outputs(const Eval& e, const double* x, double command,
                              SignalFrame& f) const {
  f.set(SignalId::ball_position, e.ball.p_W);
  f.set(SignalId::ball_velocity, e.ball.v_W);
  f.set(SignalId::ball_angular_velocity, e.ball.w_B);
  f.set(SignalId::ball_euler_321, euler321(e.ball.R_WB));
  f.set(SignalId::socket_position, e.socket.p_W);
  f.set(SignalId::socket_velocity, e.socket.v_W);
  f.set(SignalId::socket_angular_velocity, e.socket.w_B);
  f.set(SignalId::socket_euler_321, euler321(e.socket.R_WB));
  // contact signals need the latch only for impact_speed, which the scene sets
  f.set(SignalId::rod_inclination, e.rod_angle());
  f.set(SignalId::slider_end_position, e.slider_anchor.p_W);
  f.set(SignalId::crank_end_position, e.crank_anchor.p_W);
  f.set(SignalId::surface_angle, e.theta);
  // what a rigid mechanism without clearance would reach (thesis eq. 4.1)
  f.set(SignalId::surface_angle_command,
        geometry_.ideal_crank_angle(geometry_.rod_zero() + command));
  f.set(SignalId::surface_rate, e.theta_dot);
  double dxdt[size];
  derivatives(e, x, dxdt);
  f.set(SignalId::surface_acceleration, dxdt[kThetaDot]);
  f.set(SignalId::hinge_moment, e.hinge_moment);
  f.set(SignalId::kinetic_energy, kinetic_energy(e));
  f.set(SignalId::slider_spring_force, e.slider_spring.force_on_body);
  // thesis §4 sign conventions: slider spring compression positive, crank spring tension
  // positive, both along the rod
  f.set(SignalId::slider_spring_axial_force, e.slider_spring.force_on_body.dot(e.rod_direction));
  f.set(SignalId::slider_spring_moment, e.slider_spring.moment_on_body);
  f.set(SignalId::crank_spring_force, e.crank_spring.force_on_body);
  f.set(SignalId::crank_spring_axial_force, e.crank_spring.force_on_body.dot(e.rod_direction));
  f.set(SignalId::crank_spring_moment, e.crank_spring.moment_on_body);
  f.set(SignalId::quaternion_norm_error,
        std::max(quaternion_norm_error(x, kBall + BodyStateLayout::q),
                 quaternion_norm_error(x, kSocket + BodyStateLayout::q)));
}

}  // namespace rodend
