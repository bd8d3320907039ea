// Scene impact-pair: one impact of the ball (inner body) on the outer body (socket or bearing),
// to measure what a contact law does: achieved restitution, peak force, maximum penetration,
// contact duration, energy lost (model-notes §3: "a head-on impact of two bodies measures it").
//
// The outer body sits at the origin, at rest; it is either fixed (ground) or free with its own
// mass and inertia. The ball starts on the +x side of the clearance, a tiny gap short of contact
// (see kInitialGapFraction), moving along +x toward the wall at impact.approach_speed, plus an
// optional impact.tangential_speed along +y (only friction makes use of it). No gravity and no
// friction by default. The impact goes through the project's contact pipeline unchanged
// (evaluate_contact; delta'^- latched by the driver at the located onset).
//
// After the contact ends the bodies fly freely (no gravity by default), so the penetration rate
// at any later step end is the exit speed delta'^+: the summary metric first_impact_restitution
// (-delta'^+/delta'^-) is exact for a fixed or a free outer body. The ball reaches the opposite
// wall 2c/(c_r v) later: runs should end before that (one impact).
//
// State: ball (13) | outer body (13, only when free) | dissipated energy [J] (1).
#include <array>
#include <cmath>

#include "core/scene.hpp"
#include "core/scenes/impact_pair.hpp"
#include "core/scenes/parts.hpp"

namespace rodend {
namespace {

constexpr int kBall = 0;

/// The ball starts 1e-9 clearance short of contact rather than exactly at it: the driver
/// latches delta'^- at t = 0 only for a penetration > 0, so a start at penetration 0 would run
/// its first step unlatched (the current approach speed standing in for delta'^-) before the
/// located onset. With the gap, the onset is located on the first step like any other impact
/// and latched at the approach speed exactly (free flight before it). The gap is crossed in
/// 1e-9 c / v (5e-11 s at 1 cm/s): nothing else changes.
constexpr double kInitialGapFraction = 1e-9;

constexpr auto kSignals = concat(SignalId::time, kBallMotion, kSocketMotion, kContactPlacement,
                                 SignalId::relative_velocity, kContactResponse, kBodyAudit);
static_assert(distinct(kSignals));
constexpr std::array kQuaternionsFixed{kBall + BodyStateLayout::q};
constexpr std::array kQuaternionsFree{kBall + BodyStateLayout::q,
                                      BodyStateLayout::size + BodyStateLayout::q};

class ImpactPairScene final : public OneContactScene<ImpactPairScene> {
 public:
  explicit ImpactPairScene(const ParameterSet& p)
      : ball_(read_body(p, "ball")),
        outer_(read_body(p, "outer")),
        contact_(read_clearance_contact(p, "contact", "friction")),
        approach_speed_(read_positive(p, "impact.approach_speed")),
        tangential_speed_(p.number("impact.tangential_speed")),
        gravity_(p.vec3("gravity")) {
    free_ = read_choice<OuterBody>(p, "impact.outer_body") == OuterBody::free;
    if (!std::isfinite(tangential_speed_))
      throw InputError("impact.tangential_speed", "expected a finite number [m/s]");
    dissipated_ = free_ ? 2 * BodyStateLayout::size : BodyStateLayout::size;
    audit_[0] = dissipated_;
  }

  std::string_view name() const override { return "impact-pair"; }
  Features features() const override { return Features{Feature::contact, Feature::energy_audit}; }
  int state_size() const override { return dissipated_ + 1; }
  void initial_state(double* x) const override {
    const double gap = kInitialGapFraction * contact_.clearance;
    body_initial_state(x + kBall, Vec3(contact_.clearance - gap, 0.0, 0.0),
                       Vec3(approach_speed_, tangential_speed_, 0.0));
    if (free_) body_initial_state(x + kOuter, Vec3::Zero());
    x[dissipated_] = 0.0;
  }
  void state_scale(double* s) const override {
    // lengths on the Hertz penetration scale d = (m v^2 / K)^(1/(n+1)) of this impact (reduced
    // mass; a cylinder's K taken at delta << c), speeds on the impact speed
    const double K = contact_.geometry == ContactGeometry::cylinder
                         ? contact_.stiffness / std::sqrt(2.0 * contact_.clearance)
                         : contact_.stiffness;
    const double L = std::pow(reduced_mass() * approach_speed_ * approach_speed_ / K,
                              1.0 / (contact_.exponent + 1.0));
    const double V = std::hypot(approach_speed_, tangential_speed_);
    const int bodies = free_ ? 2 : 1;
    for (int b = 0; b < bodies; ++b)
      body_state_scale(s + b * BodyStateLayout::size, L, V, V / contact_.ball_radius);
    s[dissipated_] = 1.0;
  }
  std::span<const int> quaternion_offsets() const override {
    if (free_) return kQuaternionsFree;
    return kQuaternionsFixed;
  }
  std::span<const int> audit_offsets() const override { return audit_; }
  const ClearanceContactModel& contact() const { return contact_; }
  ContactGap contact_gap(int, const double* x) const override {
    return rodend::contact_gap(contact_, BodyKinematics::from_state(x + kBall), outer(x));
  }

  void derivatives(double, const double* x, const DiscreteState& d, double* dxdt) const override {
    const BodyKinematics ball = BodyKinematics::from_state(x + kBall);
    const BodyKinematics out = outer(x);
    const ContactEval c = evaluate_contact(contact_, ball, out, d.contacts[0]);
    body_derivatives(ball_, ball, ball_.mass * gravity_ + c.force_on_ball(), c.moment_on_ball,
                     x + kBall, dxdt + kBall);
    if (free_)
      body_derivatives(outer_, out, outer_.mass * gravity_ - c.force_on_ball(), c.moment_on_socket,
                       x + kOuter, dxdt + kOuter);
    dxdt[dissipated_] = c.damping_power + c.friction_power;
  }

  std::span<const SignalId> signals() const override { return kSignals; }
  EnergyTerms energy(double, const double* x, const DiscreteState& d) const override {
    const BodyKinematics ball = BodyKinematics::from_state(x + kBall);
    const BodyKinematics out = outer(x);
    const ContactEval c = evaluate_contact(contact_, ball, out, d.contacts[0]);
    return {kinetic(ball, out) - ball_.mass * gravity_.dot(ball.p_W) -
                (free_ ? outer_.mass * gravity_.dot(out.p_W) : 0.0) + c.potential,
            0.0, x[dissipated_]};
  }
  ContactSnapshot contact_snapshot(int, double, const double* x,
                                   const DiscreteState& d) const override {
    const ContactEval c =
        evaluate_contact(contact_, BodyKinematics::from_state(x + kBall), outer(x), d.contacts[0]);
    return {c.penetration, c.penetration_rate, c.eccentricity, c.normal_force};
  }
  void outputs(double t, const double* x, const DiscreteState& d, SignalFrame& f) const override {
    const BodyKinematics ball = BodyKinematics::from_state(x + kBall);
    const BodyKinematics out = outer(x);
    const ContactEval c = evaluate_contact(contact_, ball, out, d.contacts[0]);
    f.set(SignalId::ball_position, ball.p_W);
    f.set(SignalId::ball_velocity, ball.v_W);
    f.set(SignalId::ball_angular_velocity, ball.w_B);
    f.set(SignalId::socket_position, out.p_W);
    f.set(SignalId::socket_velocity, out.v_W);
    f.set(SignalId::socket_angular_velocity, out.w_B);
    write_contact_signals(f, c, ball, out, d.contacts[0]);
    f.set(SignalId::relative_velocity, Vec3(ball.v_W - out.v_W));
    f.set(SignalId::kinetic_energy, kinetic(ball, out));
    write_energy_signals(f, energy(t, x, d), initial_mechanical_energy());
    f.set(SignalId::quaternion_norm_error,
          free_ ? std::max(quaternion_norm_error(x, kBall + BodyStateLayout::q),
                           quaternion_norm_error(x, kOuter + BodyStateLayout::q))
                : quaternion_norm_error(x, kBall + BodyStateLayout::q));
  }

  /// m_ball m_outer / (m_ball + m_outer) for a free outer body, m_ball for a fixed one [kg].
  double reduced_mass() const {
    return free_ ? ball_.mass * outer_.mass / (ball_.mass + outer_.mass) : ball_.mass;
  }

 private:
  static constexpr int kOuter = BodyStateLayout::size;

  BodyKinematics outer(const double* x) const {
    return free_ ? BodyKinematics::from_state(x + kOuter) : BodyKinematics::fixed(Vec3::Zero());
  }
  double kinetic(const BodyKinematics& ball, const BodyKinematics& out) const {
    return kinetic_energy(ball_, ball) + (free_ ? kinetic_energy(outer_, out) : 0.0);
  }
  double initial_mechanical_energy() const {
    const double gap = kInitialGapFraction * contact_.clearance;
    return 0.5 * ball_.mass *
               (approach_speed_ * approach_speed_ + tangential_speed_ * tangential_speed_) -
           ball_.mass * gravity_.dot(Vec3(contact_.clearance - gap, 0.0, 0.0));
  }

  RigidBodyParams ball_, outer_;
  ClearanceContactModel contact_;
  double approach_speed_, tangential_speed_;
  Vec3 gravity_;
  bool free_ = false;
  int dissipated_ = 0;
  std::array<int, 1> audit_{};
};

}  // namespace

std::unique_ptr<Scene> make_impact_pair_scene(const ParameterSet& p) {
  return std::make_unique<ImpactPairScene>(p);
}

}  // namespace rodend
