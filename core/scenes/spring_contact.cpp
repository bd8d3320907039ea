// Scene spring-contact (thesis §3.3, fig. 3.25-3.26): the socket is tethered to ground by a
// 3-D spring; the ball is pulled through a second 3-D spring whose far end follows a ramp.
// Both spheres start concentric at the origin, at rest.
//
// State: ball (13) | socket (13) | input work [J] (1) | dissipated energy [J] (1).
#include <array>

#include "core/scene.hpp"
#include "core/scenes/parts.hpp"

namespace rodend {
namespace {

constexpr int kBall = 0;
constexpr int kSocket = BodyStateLayout::size;
constexpr int kWork = 2 * BodyStateLayout::size;
constexpr int kDissipated = kWork + 1;
constexpr int kStates = kDissipated + 1;

constexpr auto kSignals = concat(SignalId::time, kBallAndSocket, kContactSignals,
                                 SignalId::drive_anchor_position, kBodyAudit);
static_assert(distinct(kSignals));
constexpr std::array kQuaternions{kBall + BodyStateLayout::q, kSocket + BodyStateLayout::q};
constexpr std::array kAudit{kWork, kDissipated};

class SpringContactScene final : public OneContactScene<SpringContactScene> {
 public:
  explicit SpringContactScene(const ParameterSet& p)
      : ball_(read_body(p, "ball")),
        socket_(read_body(p, "socket")),
        contact_(read_clearance_contact(p, "contact", "friction")),
        tether_(read_spring(p, "tether")),
        drive_(read_spring(p, "drive")),
        drive_velocity_(p.vec3("drive.velocity")),
        drive_start_(read_positive(p, "drive.start_time", true)),
        gravity_(p.vec3("gravity")) {}

  std::string_view name() const override { return "spring-contact"; }
  Features features() const override { return Features{Feature::contact, Feature::energy_audit}; }
  int state_size() const override { return kStates; }
  void initial_state(double* x) const override {
    body_initial_state(x + kBall, Vec3::Zero());
    body_initial_state(x + kSocket, Vec3::Zero());
    x[kWork] = 0.0;
    x[kDissipated] = 0.0;
  }
  void state_scale(double* s) const override {
    const double L = contact_.clearance;
    const double V = std::max(drive_velocity_.norm(), 1e-3);
    for (int b : {kBall, kSocket}) body_state_scale(s + b, L, V, V / contact_.ball_radius);
    s[kWork] = s[kDissipated] = 1.0;
  }
  std::span<const int> quaternion_offsets() const override { return kQuaternions; }
  std::span<const int> audit_offsets() const override { return kAudit; }
  const ClearanceContactModel& contact() const { return contact_; }
  ContactGap contact_gap(int, const double* x) const override {
    return rodend::contact_gap(contact_, BodyKinematics::from_state(x + kBall),
                               BodyKinematics::from_state(x + kSocket));
  }

  /// The driven far end of the ball spring: at rest until start_time, then a ramp.
  SpringAnchor drive_anchor(double t) const {
    SpringAnchor a;
    const double tau = std::max(t - drive_start_, 0.0);
    a.p_W = drive_velocity_ * tau;
    a.v_W = t > drive_start_ ? drive_velocity_ : Vec3::Zero();
    return a;
  }

  struct Forces {
    ContactEval contact;
    SpringEval tether, drive;
  };
  Forces forces(double t, const BodyKinematics& ball, const BodyKinematics& socket,
                const DiscreteState& d) const {
    return {evaluate_contact(contact_, ball, socket, d.contacts[0]),
            evaluate_spring(tether_, SpringAnchor{}, socket),
            evaluate_spring(drive_, drive_anchor(t), ball)};
  }

  void derivatives(double t, const double* x, const DiscreteState& d, double* dxdt) const override {
    const BodyKinematics ball = BodyKinematics::from_state(x + kBall);
    const BodyKinematics socket = BodyKinematics::from_state(x + kSocket);
    const Forces f = forces(t, ball, socket, d);
    const Vec3 F_ball = ball_.mass * gravity_ + f.contact.force_on_ball() + f.drive.force_on_body;
    const Vec3 M_ball = f.contact.moment_on_ball + f.drive.moment_on_body;
    const Vec3 F_socket =
        socket_.mass * gravity_ - f.contact.force_on_ball() + f.tether.force_on_body;
    const Vec3 M_socket = f.contact.moment_on_socket + f.tether.moment_on_body;
    body_derivatives(ball_, ball, F_ball, M_ball, x + kBall, dxdt + kBall);
    body_derivatives(socket_, socket, F_socket, M_socket, x + kSocket, dxdt + kSocket);
    dxdt[kWork] = f.drive.anchor_power;
    dxdt[kDissipated] = f.contact.damping_power + f.contact.friction_power +
                        f.tether.damping_power + f.drive.damping_power;
  }

  std::span<const SignalId> signals() const override { return kSignals; }
  EnergyTerms energy(double t, const double* x, const DiscreteState& d) const override {
    const BodyKinematics ball = BodyKinematics::from_state(x + kBall);
    const BodyKinematics socket = BodyKinematics::from_state(x + kSocket);
    const Forces f = forces(t, ball, socket, d);
    const double mech = kinetic_energy(ball_, ball) + kinetic_energy(socket_, socket) -
                        ball_.mass * gravity_.dot(ball.p_W) -
                        socket_.mass * gravity_.dot(socket.p_W) + f.contact.potential +
                        spring_potential(tether_, SpringAnchor{}, socket) +
                        spring_potential(drive_, drive_anchor(t), ball);
    return {mech, x[kWork], x[kDissipated]};
  }
  void outputs(double t, const double* x, const DiscreteState& d, SignalFrame& out) const override {
    const BodyKinematics ball = BodyKinematics::from_state(x + kBall);
    const BodyKinematics socket = BodyKinematics::from_state(x + kSocket);
    const Forces f = forces(t, ball, socket, d);
    out.set(SignalId::ball_position, ball.p_W);
    out.set(SignalId::ball_velocity, ball.v_W);
    out.set(SignalId::ball_angular_velocity, ball.w_B);
    out.set(SignalId::ball_euler_321, euler321(ball.R_WB));
    out.set(SignalId::socket_position, socket.p_W);
    out.set(SignalId::socket_velocity, socket.v_W);
    out.set(SignalId::socket_angular_velocity, socket.w_B);
    out.set(SignalId::socket_euler_321, euler321(socket.R_WB));
    write_contact_signals(out, f.contact, ball, socket, d.contacts[0]);
    out.set(SignalId::drive_anchor_position, drive_anchor(t).p_W);
    out.set(SignalId::kinetic_energy,
            kinetic_energy(ball_, ball) + kinetic_energy(socket_, socket));
    write_energy_signals(out, energy(t, x, d), 0.0);
    out.set(SignalId::quaternion_norm_error,
            std::max(quaternion_norm_error(x, kBall + BodyStateLayout::q),
                     quaternion_norm_error(x, kSocket + BodyStateLayout::q)));
  }

 private:
  RigidBodyParams ball_, socket_;
  ClearanceContactModel contact_;
  Spring3DParams tether_, drive_;
  Vec3 drive_velocity_;
  double drive_start_;
  Vec3 gravity_;
};

}  // namespace

std::unique_ptr<Scene> make_spring_contact_scene(const ParameterSet& p) {
  return std::make_unique<SpringContactScene>(p);
}

}  // namespace rodend
