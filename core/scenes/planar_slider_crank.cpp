// Scene planar-slider-crank: the test rig of Wang, Liu, Ma and Tong, "Study on dynamic responses
// of planar multibody systems with dry revolute clearance joint: numerical and experimental
// approaches", J. Sound Vib. 438 (2019) 116-138 (issue 21; docs/planar-slider-crank.md).
//
// An in-line slider-crank in the xy-plane: the crank turns about the ground pivot A (the
// origin) at a prescribed constant speed, the connecting rod joins the crank pin B to the
// slider pin C, the slider moves on a frictionless guide along the x-axis (y = 0, no rotation).
// Each of the three revolute joints A (ground-crank), B (crank-rod), C (rod-slider) is either
// ideal or has radial clearance (journal in bearing, the cylindrical contact of core/contact.hpp).
//
// Formulation: minimal coordinates, ideal joints eliminated exactly, clearance joints as force
// elements. Every clearance joint adds two coordinates, deviations from the ideal mechanism
// (so they are of the order of the clearance and the integrator's scale fits them):
//   A with clearance: the crank pivot (x_A, y_A) itself (the bearing centre is the origin);
//   B with clearance: the rod's B-bore centre relative to the crank pin, (u_Bx, u_By);
//   C with clearance: the rod angle and the slider position relative to their values in the
//     closed loop through the rod's B bore, (phi - phi_c, x_C - x_c), with
//       sin phi_c = -y_Brod / L,  x_c = x_Brod + L cos phi_c     (loop closure at C, y = 0).
// The crank angle theta = theta_0 + omega t is prescribed (the motor holds it). With every joint
// ideal there is no coordinate: the positions are the closed-form slider-crank kinematics.
// The model forms of issue 36 (planar_slider_crank_options.hpp), each off by default, add:
//   guide.model clearance: the slider's y across its guide (the loop closes at C through it:
//     sin phi_c = (y_s - y_Brod) / L), a coordinate after the joints';
//   rod_flexibility.model first_mode: the rod's mode amplitude eta, the last coordinate; the
//     mode's points are bodies of the pose (mode_pose()), so its inertia couples through the
//     same Jacobians;
//   drive.model motor: theta is solved for with q (its row carries the flywheel and the motor
//     torque), and theta' is a state.
//
// Dynamics (Lagrange's equations in minimal coordinates q, n = 2 x clearance joints):
//   M(q) q'' = Q(q, q', t) - sum_b [m_b J_b^T c_b + I_b j_b^T c_phi,b]
//   M = sum_b m_b J_b^T J_b + I_b j_b^T j_b
// with J_b = d r_b / dq (mass centre), j_b = d phi_b / dq, and c_b the velocity-product part of
// the mass-centre acceleration. Positions r(q, theta) are written once (pose() below) on
// second-order truncated Taylor numbers (Jet), so J, c and the velocities are exact derivatives
// of that one function (forward-mode differentiation, no finite differences). Q collects
// gravity and the contact forces, each projected through the Jacobian of the material point it
// acts on (journal centre, bearing centre) and of the body angle (friction moments).
// The driving torque is the generalised force conjugate to theta that keeps theta'' = 0
// (inverse dynamics): tau = sum_b (m_b a_b - F_b) . dr_b/dtheta + I_b phi_b'' dphi_b/dtheta
// - Q_theta(contacts); its power tau omega is the audit's input work.
//
// State: crank angle theta [rad] | q (n) | q' (n) | [theta' with the motor] | input work [J] |
// dissipated energy [J].
// theta is a state (theta' = omega, integrated exactly by every Runge-Kutta method) so that the
// contact gaps, which the driver asks for from the state alone, see the crank's position.
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/scene.hpp"
#include "core/scenes/parts.hpp"
#include "core/scenes/planar_slider_crank_options.hpp"

namespace rodend {
namespace {

/// f(s) along one direction to second order: value, f'(0) and f''(0) (forward-mode
/// differentiation of the mechanism's positions).
struct Jet {
  double v = 0.0, d = 0.0, dd = 0.0;
};
Jet operator+(Jet a, Jet b) {
  return {a.v + b.v, a.d + b.d, a.dd + b.dd};
}
Jet operator*(double k, Jet a) {
  return {k * a.v, k * a.d, k * a.dd};
}
Jet operator*(Jet a, Jet b) {
  return {a.v * b.v, a.d * b.v + a.v * b.d, a.dd * b.v + 2.0 * a.d * b.d + a.v * b.dd};
}
/// g(a) from g, g', g'' at a.v (chain rule to second order).
Jet chain(Jet a, double g, double g1, double g2) {
  return {g, g1 * a.d, g2 * a.d * a.d + g1 * a.dd};
}
Jet sin(Jet a) {
  const double s = std::sin(a.v), c = std::cos(a.v);
  return chain(a, s, c, -s);
}
Jet cos(Jet a) {
  const double s = std::sin(a.v), c = std::cos(a.v);
  return chain(a, c, -s, -c);
}
Jet asin(Jet a) {
  const double r = 1.0 / std::sqrt(1.0 - a.v * a.v);
  return chain(a, std::asin(a.v), r, a.v * r * r * r);
}

/// The positions of the mechanism: every body's mass centre and angle, the joint points.
enum Pose : int {
  crank_pivot_x,
  crank_pivot_y,  // A on the crank (journal of joint A)
  crank_pin_x,
  crank_pin_y,  // B on the crank (journal of joint B)
  rod_b_x,
  rod_b_y,  // the rod's B bore (bearing of joint B)
  rod_c_x,
  rod_c_y,  // the rod's C bore (bearing of joint C)
  slider_x,
  slider_y,  // C on the slider (journal of joint C); mass centre of the slider
  crank_com_x,
  crank_com_y,
  rod_com_x,
  rod_com_y,
  crank_phi,
  rod_phi,
  rod_mode,    // the rod's bending-mode amplitude eta [m] (0 for a rigid rod)
  rod_points,  // the mode's points: x, y of each deflected point, then of each undeflected one
  pose_size = rod_points + 4 * RodMode::kPoints
};
using PoseJets = std::array<Jet, pose_size>;

enum Joint : int { ground_crank = 0, crank_rod = 1, rod_slider = 2 };
constexpr std::array<const char*, 3> kJointKeys{"joints.ground_crank", "joints.crank_rod",
                                                "joints.rod_slider"};

/// A body: its mass-centre and angle entries in the pose (angle -1: does not turn).
struct BodyPose {
  int x, y, phi;
};
constexpr std::array<BodyPose, 3> kBodies{{{crank_com_x, crank_com_y, crank_phi},
                                           {rod_com_x, rod_com_y, rod_phi},
                                           {slider_x, slider_y, -1}}};
/// Journal and bearing of each joint (pose entries; bearing -1: ground at the origin), and the
/// body (index into kBodies, -1 ground) that carries each.
struct JointPose {
  int journal_x, bearing_x;
  int journal_body, bearing_body;
};
constexpr std::array<JointPose, 3> kJoints{
    {{crank_pivot_x, -1, 0, -1}, {crank_pin_x, rod_b_x, 0, 1}, {slider_x, rod_c_x, 2, 1}}};

/// Signals of every case; the contact signals follow when a joint has clearance.
constexpr auto kMechanismSignals =
    concat(SignalId::time, SignalId::crank_angle, SignalId::slider_position, SignalId::surface_rate,
           SignalId::slider_velocity, SignalId::slider_acceleration, SignalId::driving_torque,
           SignalId::joint_normal_forces, SignalId::joint_eccentricities, kEnergyAudit);

/// A body of the dynamics: mass-centre and angle entries of the pose (angle -1: no rotary
/// inertia), mass and moment of inertia. The flexible rod's mode points are bodies too (point
/// masses, the undeflected ones with negative mass: see RodMode).
struct Body {
  int x, y, phi;
  double mass, inertia;
};

struct Link {
  double length = 0.0;   ///< [m]
  double com = 0.0;      ///< distance of the mass centre from the link's first joint [m]
  double mass = 0.0;     ///< [kg]
  double inertia = 0.0;  ///< about the mass centre, normal to the plane [kg m^2]
};

class PlanarSliderCrankScene final : public Scene {
 public:
  explicit PlanarSliderCrankScene(const ParameterSet& p) {
    crank_ = read_link(p, "crank");
    rod_ = read_link(p, "rod");
    slider_mass_ = read_positive(p, "slider.mass");
    read_positive(p, "slider.inertia");  // checked; the slider does not turn on its guide
    if (!(rod_.length > crank_.length))
      throw InputError("rod.length",
                       "expected a rod longer than the crank (" + format_number(crank_.length) +
                           " m) so the crank turns fully, got " + format_number(rod_.length));
    omega_ = p.number("drive.crank_speed");
    if (!(std::abs(omega_) > 0.0) || !std::isfinite(omega_))
      throw InputError("drive.crank_speed", "expected a finite non-zero crank speed [rad/s]");
    theta0_ = p.number("drive.initial_crank_angle");
    if (!std::isfinite(theta0_))
      throw InputError("drive.initial_crank_angle", "expected a finite angle [rad]");
    const Vec3 g = p.vec3("gravity");
    if (g.z() != 0.0)
      throw InputError("gravity", "expected a vector in the plane of motion (z component 0)");
    gravity_ = g;
    read_joints(p);
    read_options(p);
    signals_.assign(kMechanismSignals.begin(), kMechanismSignals.end());
    if (!joints_.empty()) {
      signals_.insert(signals_.end(), kContactSignals.begin(), kContactSignals.end());
      signals_.push_back(SignalId::relative_velocity);
    }
    std::sort(signals_.begin(), signals_.end());  // catalogue order
    audit_ = {work(), work() + 1};
    std::vector<double> x0(static_cast<std::size_t>(state_size()));
    initial_state(x0.data());
    initial_mechanical_ = energy(0.0, x0.data(), DiscreteState{}).mechanical;
  }

  std::string_view name() const override { return "planar-slider-crank"; }
  int state_size() const override { return 2 * n_ + 3 + (drive_.on() ? 1 : 0); }
  void initial_state(double* x) const override {
    // every joint concentric, the ideal mechanism's velocities (deviation rates 0), the rod
    // straight, the slider on the guide's centre line, the crank at its (no-load) speed
    for (int i = 0; i < state_size(); ++i) x[i] = 0.0;
    x[kTheta] = theta0_;
    if (drive_.on()) x[theta_rate_index()] = omega_;
  }
  void state_scale(double* s) const override;
  std::span<const int> audit_offsets() const override { return audit_; }

  Features features() const override {
    Features f{Feature::planar, Feature::energy_audit};
    if (!joints_.empty()) f.set(Feature::contact);  // a clearance joint: a latched contact
    return f;
  }
  int contact_count() const override { return static_cast<int>(joints_.size()); }
  double contact_clearance(int c) const override {
    return models_[static_cast<std::size_t>(c)].clearance;
  }
  double contact_radius(int c) const override {
    return models_[static_cast<std::size_t>(c)].ball_radius;
  }
  ContactGap contact_gap(int c, const double* x) const override {
    const auto [journal, bearing] = joint_kinematics(c, velocity_pose(x));
    return rodend::contact_gap(models_[static_cast<std::size_t>(c)], journal, bearing);
  }
  // contact c itself (the default reads the contact signals, which follow only the last joint)
  ContactSnapshot contact_snapshot(int c, double, const double* x,
                                   const DiscreteState& d) const override {
    const ContactEval e = contact(c, velocity_pose(x), d);
    return {e.penetration, e.penetration_rate, e.eccentricity, e.normal_force};
  }

  void derivatives(double, const double* x, const DiscreteState& d, double* dxdt) const override {
    const Solution s = solve(x, d);
    dxdt[kTheta] = theta_rate(x);
    for (int i = 0; i < n_; ++i) {
      dxdt[kQ + i] = x[kQ + n_ + i];
      dxdt[kQ + n_ + i] = s.qdd[i];
    }
    if (drive_.on()) dxdt[theta_rate_index()] = s.theta_acceleration;
    dxdt[work()] = s.torque * theta_rate(x);
    dxdt[work() + 1] = s.dissipation;
  }

  std::span<const SignalId> signals() const override { return signals_; }
  EnergyTerms energy(double, const double* x, const DiscreteState& d) const override {
    const PoseJets v = velocity_pose(x);
    double e = kinetic(v, x);
    for (const Body& b : bodies_) e -= b.mass * (gravity_.x() * v[b.x].v + gravity_.y() * v[b.y].v);
    for (std::size_t i = 0; i < joints_.size(); ++i)
      e += contact(static_cast<int>(i), v, d).potential;
    const double eta = v[rod_mode].v;
    e += 0.5 * mode_.stiffness * eta * eta + guide_force(v).potential;
    return {e, x[work()], x[work() + 1]};
  }
  void outputs(double t, const double* x, const DiscreteState& d, SignalFrame& f) const override {
    const Solution s = solve(x, d);
    const PoseJets& v = s.velocity;
    f.set(SignalId::crank_angle, x[kTheta]);
    f.set(SignalId::surface_rate, theta_rate(x));  // the crank's rate
    f.set(SignalId::slider_position, v[slider_x].v);
    f.set(SignalId::slider_velocity, v[slider_x].d);
    f.set(SignalId::slider_acceleration, s.slider_acceleration);
    f.set(SignalId::driving_torque, s.torque);
    Vec3 forces = Vec3::Zero(), ecc = Vec3::Zero();
    for (std::size_t i = 0; i < joints_.size(); ++i) {
      forces[joints_[i]] = s.contacts[i].normal_force;
      ecc[joints_[i]] = s.contacts[i].eccentricity;
    }
    f.set(SignalId::joint_normal_forces, forces);
    f.set(SignalId::joint_eccentricities, ecc);
    if (!joints_.empty()) {  // the contact signals: the last clearance joint (rod-slider first)
      const int i = static_cast<int>(joints_.size()) - 1;
      const auto [journal, bearing] = joint_kinematics(i, v);
      write_contact_signals(f, s.contacts[static_cast<std::size_t>(i)], journal, bearing,
                            d.contacts[static_cast<std::size_t>(i)]);
      f.set(SignalId::relative_velocity, Vec3(journal.v_W - bearing.v_W));
    }
    f.set(SignalId::kinetic_energy, kinetic(v, x));
    write_energy_signals(f, energy(t, x, d), initial_mechanical_);
  }

 private:
  static constexpr int kTheta = 0, kQ = 1;
  static constexpr int kMaxQ = 8;  ///< 2 per clearance joint, the guide's y, the rod's mode
  /// the crank's rate, a state with the motor (after the coordinates' rates)
  int theta_rate_index() const { return kQ + 2 * n_; }
  double theta_rate(const double* x) const { return drive_.on() ? x[theta_rate_index()] : omega_; }
  /// input work; dissipated energy follows
  int work() const { return kQ + 2 * n_ + (drive_.on() ? 1 : 0); }
  struct Solution {
    PoseJets velocity;  ///< value, velocity and velocity-product acceleration of each entry
    Eigen::VectorXd qdd;
    double theta_acceleration = 0.0;      ///< theta'' [rad/s^2] (0 at prescribed speed)
    Guide::Force guide;                   ///< the guide's force on the slider
    std::array<ContactEval, 3> contacts;  ///< per clearance joint, in joints_ order
    double torque = 0.0;                  ///< driving (or motor) torque [N m]
    double dissipation = 0.0;             ///< [W]
    double slider_acceleration = 0.0;     ///< [m/s^2]
  };

  /// The clearance joints: the coordinates they add and their contact models.
  void read_joints(const ParameterSet& p) {
    for (int j = 0; j < 3; ++j) {
      const std::string key = kJointKeys[static_cast<std::size_t>(j)];
      if (read_choice<JointModel>(p, key + ".model") == JointModel::clearance) {
        const double c = p.number(key + ".clearance");
        if (!(c > 0.0) || !std::isfinite(c))
          throw InputError(key + ".clearance",
                           "expected a clearance > 0 [m] for a joint with model \"clearance\" "
                           "(model \"ideal\" for none), got " +
                               format_number(c));
        ClearanceContactModel m =
            read_clearance_contact(p, "contact", "friction", key + ".clearance");
        if (m.clearance >= m.ball_radius)
          throw InputError(key + ".clearance",
                           "expected a clearance smaller than the journal "
                           "radius contact.ball_radius");
        offset_[j] = n_;
        n_ += 2;
        joints_.push_back(j);
        models_.push_back(std::move(m));
      }
    }
  }

  /// The model forms of issue 36 item 4 (each off by default: today's model) and the bodies.
  void read_options(const ParameterSet& p) {
    mode_ = RodMode::read(p, rod_.length, rod_.mass, rod_.inertia, rod_.com);
    guide_ = Guide::read(p, slider_mass_);
    drive_ = Drive::read(p);
    if (guide_.on()) guide_offset_ = n_++;
    if (mode_.on()) mode_offset_ = n_++;
    bodies_ = {{crank_com_x, crank_com_y, crank_phi, crank_.mass, crank_.inertia},
               {rod_com_x, rod_com_y, rod_phi, rod_.mass, rod_.inertia},
               {slider_x, slider_y, -1, slider_mass_, 0.0}};
    for (int k = 0; mode_.on() && k < RodMode::kPoints; ++k) {
      const double m = mode_.mass[static_cast<std::size_t>(k)];
      bodies_.push_back({mode_point(k, true), mode_point(k, true) + 1, -1, m, 0.0});
      bodies_.push_back({mode_point(k, false), mode_point(k, false) + 1, -1, -m, 0.0});
    }
  }
  /// pose entry (x; y follows) of mode point k, deflected or not
  static int mode_point(int k, bool deflected) {
    return rod_points + 2 * k + (deflected ? 0 : 2 * RodMode::kPoints);
  }

  static Link read_link(const ParameterSet& p, const std::string& key) {
    Link l;
    l.length = read_positive(p, key + ".length");
    l.mass = read_positive(p, key + ".mass");
    l.inertia = read_positive(p, key + ".inertia");
    l.com = p.number(key + ".center_of_mass");
    if (!(l.com >= 0.0 && l.com <= l.length))
      throw InputError(key + ".center_of_mass",
                       "expected a distance from the link's first joint in [0, " +
                           format_number(l.length) + "] m (the link length), got " +
                           format_number(l.com));
    return l;
  }

  /// The guide's force on the slider at the pose (zero for an ideal guide).
  Guide::Force guide_force(const PoseJets& v) const {
    return guide_.force(v[slider_y].v, v[slider_y].d, v[slider_x].d);
  }

  /// The positions at (q, theta), differentiated along (dq, dtheta): the one description of
  /// the mechanism's geometry (see the header for the coordinates).
  /// Along (dq, dtheta); dq null: zero.
  PoseJets pose(const double* x, const double* dq, double dtheta) const {
    std::array<Jet, kMaxQ> qj{};
    for (int i = 0; i < n_; ++i)
      qj[static_cast<std::size_t>(i)] = {x[kQ + i], dq ? dq[i] : 0.0, 0.0};
    return pose(qj, Jet{x[kTheta], dtheta, 0.0});
  }
  /// Along the motion (q', omega): values, velocities and velocity-product accelerations.
  PoseJets velocity_pose(const double* x) const { return pose(x, x + kQ + n_, theta_rate(x)); }
  PoseJets pose(const std::array<Jet, kMaxQ>& q, Jet theta) const {
    PoseJets p{};
    auto coord = [&](Joint j, int i) { return q[static_cast<std::size_t>(offset_[j] + i)]; };
    if (offset_[ground_crank] >= 0) {
      p[crank_pivot_x] = coord(ground_crank, 0);
      p[crank_pivot_y] = coord(ground_crank, 1);
    }
    const Jet c1 = cos(theta), s1 = sin(theta);
    p[crank_phi] = theta;
    p[crank_pin_x] = p[crank_pivot_x] + crank_.length * c1;
    p[crank_pin_y] = p[crank_pivot_y] + crank_.length * s1;
    p[crank_com_x] = p[crank_pivot_x] + crank_.com * c1;
    p[crank_com_y] = p[crank_pivot_y] + crank_.com * s1;
    p[rod_b_x] = p[crank_pin_x];
    p[rod_b_y] = p[crank_pin_y];
    if (offset_[crank_rod] >= 0) {
      p[rod_b_x] = p[rod_b_x] + coord(crank_rod, 0);
      p[rod_b_y] = p[rod_b_y] + coord(crank_rod, 1);
    }
    // loop closure at C on the guide, slider pin at y = y_s (0 for an ideal guide):
    // sin phi = (y_s - y_B) / L, slider on the +x side
    const Jet ys = guide_offset_ >= 0 ? q[static_cast<std::size_t>(guide_offset_)] : Jet{};
    Jet phi = guide_offset_ >= 0 ? asin((1.0 / rod_.length) * (ys + (-1.0) * p[rod_b_y]))
                                 : asin((-1.0 / rod_.length) * p[rod_b_y]);
    Jet x = p[rod_b_x] + rod_.length * cos(phi);
    if (offset_[rod_slider] >= 0) {
      phi = phi + coord(rod_slider, 0);
      x = x + coord(rod_slider, 1);
    }
    const Jet c2 = cos(phi), s2 = sin(phi);
    p[rod_phi] = phi;
    p[rod_c_x] = p[rod_b_x] + rod_.length * c2;
    p[rod_c_y] = p[rod_b_y] + rod_.length * s2;
    p[rod_com_x] = p[rod_b_x] + rod_.com * c2;
    p[rod_com_y] = p[rod_b_y] + rod_.com * s2;
    p[slider_x] = x;
    p[slider_y] = ys;
    if (mode_offset_ >= 0) mode_pose(p, q[static_cast<std::size_t>(mode_offset_)], c2, s2);
    return p;
  }
  /// The rod's mode points, deflected by eta psi_k normal to the chord (c2, s2) and not.
  void mode_pose(PoseJets& p, Jet eta, Jet c2, Jet s2) const {
    p[rod_mode] = eta;
    for (int k = 0; k < RodMode::kPoints; ++k) {
      const auto u = static_cast<std::size_t>(k);
      const Jet x = p[rod_b_x] + mode_.s[u] * c2, y = p[rod_b_y] + mode_.s[u] * s2;
      const int d = mode_point(k, true), r = mode_point(k, false);
      p[static_cast<std::size_t>(r)] = x;
      p[static_cast<std::size_t>(r) + 1] = y;
      p[static_cast<std::size_t>(d)] = x + (-mode_.psi[u]) * (eta * s2);
      p[static_cast<std::size_t>(d) + 1] = y + mode_.psi[u] * (eta * c2);
    }
  }

  /// Kinetic energy of the bodies and, with the motor, of the flywheel.
  double kinetic(const PoseJets& v, const double* x) const {
    double e = 0.0;
    for (const Body& b : bodies_) {
      e += 0.5 * b.mass * (v[b.x].d * v[b.x].d + v[b.y].d * v[b.y].d);
      if (b.phi >= 0) e += 0.5 * b.inertia * v[b.phi].d * v[b.phi].d;
    }
    const double w = theta_rate(x);
    return e + (drive_.on() ? 0.5 * drive_.flywheel * w * w : 0.0);
  }

  /// Journal and bearing of clearance joint i as point kinematics (planar: w along z).
  std::pair<BodyKinematics, BodyKinematics> joint_kinematics(int i, const PoseJets& v) const {
    const JointPose& jp = kJoints[static_cast<std::size_t>(joints_[static_cast<std::size_t>(i)])];
    auto point = [&](int px, int body) {
      if (px < 0) return BodyKinematics::fixed(Vec3::Zero());
      BodyKinematics k = BodyKinematics::fixed(Vec3(v[px].v, v[px + 1].v, 0.0));
      k.v_W = Vec3(v[px].d, v[px + 1].d, 0.0);
      const int phi = kBodies[static_cast<std::size_t>(body)].phi;
      k.w_W = k.w_B = Vec3(0.0, 0.0, phi >= 0 ? v[phi].d : 0.0);
      return k;
    };
    return {point(jp.journal_x, jp.journal_body), point(jp.bearing_x, jp.bearing_body)};
  }
  ContactEval contact(int i, const PoseJets& v, const DiscreteState& d) const {
    const auto [journal, bearing] = joint_kinematics(i, v);
    const ContactLatch latch =
        d.contacts.empty() ? ContactLatch{} : d.contacts[static_cast<std::size_t>(i)];
    return evaluate_contact(models_[static_cast<std::size_t>(i)], journal, bearing, latch);
  }

  Solution solve(const double* x, const DiscreteState& d) const;
  /// d(angle)/d(column) of a body (0 for ground and for the slider, which does not turn)
  static double turn(const PoseJets& col, int body) {
    if (body < 0) return 0.0;
    const int phi = kBodies[static_cast<std::size_t>(body)].phi;
    return phi >= 0 ? col[static_cast<std::size_t>(phi)].d : 0.0;
  }
  /// generalised applied force along one column: gravity at the mass centres, each contact
  /// force of `s` at its journal and bearing centres, the friction moments on the bodies' angles,
  /// the guide's force on the slider, the rod mode's elastic and damping force, the motor torque
  double applied(const PoseJets& col, const Solution& s) const {
    double Q = 0.0;
    for (const Body& b : bodies_)
      Q += b.mass * (gravity_.x() * col[b.x].d + gravity_.y() * col[b.y].d);
    Q += s.guide.fx * col[slider_x].d + s.guide.fy * col[slider_y].d;
    const Jet& eta = s.velocity[rod_mode];
    Q -= (mode_.stiffness * eta.v + mode_.damping * eta.d) * col[rod_mode].d;
    if (drive_.on()) Q += s.torque * col[crank_phi].d;
    for (std::size_t i = 0; i < joints_.size(); ++i) {
      const JointPose& jp = kJoints[static_cast<std::size_t>(joints_[i])];
      const ContactEval& c = s.contacts[i];
      const Vec3 F = c.force_on_ball();
      Q += F.x() * col[jp.journal_x].d + F.y() * col[jp.journal_x + 1].d;
      Q += c.moment_on_ball.z() * turn(col, jp.journal_body);
      if (jp.bearing_x >= 0) {
        Q -= F.x() * col[jp.bearing_x].d + F.y() * col[jp.bearing_x + 1].d;
        Q += c.moment_on_socket.z() * turn(col, jp.bearing_body);
      }
    }
    return Q;
  }
  /// inertia products sum_b m_b a.b + I_b a_phi b_phi over two columns (field d or dd of b)
  double inertial(const PoseJets& a, const PoseJets& b, bool second) const {
    double r = 0.0;
    for (const Body& body : bodies_) {
      auto g = [&](int k) { return second ? b[k].dd : b[k].d; };
      r += body.mass * (a[body.x].d * g(body.x) + a[body.y].d * g(body.y));
      if (body.phi >= 0) r += body.inertia * a[body.phi].d * g(body.phi);
    }
    return r;
  }

  Link crank_, rod_;
  double slider_mass_ = 0.0;
  double omega_ = 0.0, theta0_ = 0.0;
  Vec3 gravity_ = Vec3::Zero();
  std::array<int, 3> offset_{-1, -1, -1};  ///< first coordinate of each clearance joint
  std::vector<int> joints_;                ///< the clearance joints, in order A, B, C
  std::vector<ClearanceContactModel> models_;
  RodMode mode_;
  Guide guide_;
  Drive drive_;
  int guide_offset_ = -1, mode_offset_ = -1;  ///< the slider's y, the rod's mode amplitude
  std::vector<Body> bodies_;
  int n_ = 0;
  std::vector<SignalId> signals_;
  std::array<int, 2> audit_{};
  double initial_mechanical_ = 0.0;
};

void PlanarSliderCrankScene::state_scale(double* s) const {
  // deviations on the clearance of their joint, their rates on the crank-pin speed
  const double V = std::abs(omega_) * crank_.length;
  s[kTheta] = 1.0;
  for (std::size_t i = 0; i < joints_.size(); ++i) {
    const int o = kQ + offset_[static_cast<std::size_t>(joints_[i])];
    const double c = models_[i].clearance;
    const double angle = joints_[i] == rod_slider ? 1.0 / rod_.length : 1.0;  // rod angle
    s[o] = c * angle;
    s[o + 1] = c;
    s[n_ + o] = V * angle;
    s[n_ + o + 1] = V;
  }
  if (guide_offset_ >= 0) {  // the slider's y on the guide's clearance
    s[kQ + guide_offset_] = guide_.clearance;
    s[kQ + n_ + guide_offset_] = V;
  }
  if (mode_offset_ >= 0) {  // the mode on the rod's deflection under its inertia load m r w^2/2
    const double eta = 0.5 * rod_.mass * V * std::abs(omega_) / mode_.stiffness;
    s[kQ + mode_offset_] = eta;
    s[kQ + n_ + mode_offset_] = eta * mode_.frequency;
  }
  if (drive_.on()) s[theta_rate_index()] = std::abs(omega_);
  s[work()] = s[work() + 1] = 1.0;
}

PlanarSliderCrankScene::Solution PlanarSliderCrankScene::solve(const double* x,
                                                               const DiscreteState& d) const {
  Solution s;
  s.velocity = velocity_pose(x);
  const PoseJets& v = s.velocity;
  // Jacobian columns: d(pose)/dq_j, and d(pose)/dtheta last
  std::array<PoseJets, kMaxQ + 1> cols;
  std::array<double, kMaxQ> e{};
  for (int j = 0; j < n_; ++j) {
    e.fill(0.0);
    e[static_cast<std::size_t>(j)] = 1.0;
    cols[static_cast<std::size_t>(j)] = pose(x, e.data(), 0.0);
  }
  const PoseJets& col_theta = cols[static_cast<std::size_t>(n_)] = pose(x, nullptr, 1.0);
  for (std::size_t i = 0; i < joints_.size(); ++i) {
    s.contacts[i] = contact(static_cast<int>(i), v, d);
    s.dissipation += s.contacts[i].damping_power + s.contacts[i].friction_power;
  }
  s.guide = guide_force(v);
  s.dissipation += s.guide.dissipation + mode_.damping * v[rod_mode].d * v[rod_mode].d;
  if (drive_.on()) s.torque = drive_.torque(omega_, theta_rate(x));
  // the unknowns: q'' and, with the motor, theta'' (the flywheel adds to its diagonal)
  const int N = n_ + (drive_.on() ? 1 : 0);
  Eigen::VectorXd sol = Eigen::VectorXd::Zero(N);
  if (N > 0) {
    Eigen::MatrixXd M(N, N);
    Eigen::VectorXd rhs(N);
    for (int i = 0; i < N; ++i) {
      const PoseJets& ci = cols[static_cast<std::size_t>(i)];
      for (int j = 0; j <= i; ++j)
        M(i, j) = M(j, i) = inertial(ci, cols[static_cast<std::size_t>(j)], false);
      rhs[i] = applied(ci, s) - inertial(ci, v, true);
    }
    if (drive_.on()) M(n_, n_) += drive_.flywheel;
    sol = M.ldlt().solve(rhs);
  }
  s.qdd = sol.head(n_);
  if (drive_.on()) s.theta_acceleration = sol[n_];
  // accelerations of the pose entries; at prescribed speed the torque that holds theta'' = 0
  PoseJets acc = v;
  for (int k = 0; k < pose_size; ++k) {
    double a = v[static_cast<std::size_t>(k)].dd;
    for (int j = 0; j < N; ++j)
      a += cols[static_cast<std::size_t>(j)][static_cast<std::size_t>(k)].d * sol[j];
    acc[static_cast<std::size_t>(k)].dd = a;
  }
  if (!drive_.on()) s.torque = inertial(col_theta, acc, true) - applied(col_theta, s);
  s.slider_acceleration = acc[slider_x].dd;
  return s;
}

}  // namespace

std::unique_ptr<Scene> make_planar_slider_crank_scene(const ParameterSet& p) {
  return std::make_unique<PlanarSliderCrankScene>(p);
}

}  // namespace rodend
