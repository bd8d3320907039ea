// Scene free-body: one 6-DOF body under a prescribed force and moment, each a vector amplitude
// times an input of unit amplitude: constant, a ramp or a waveform (core/scenes/load_kinds.def;
// thesis §3.3, the 6DOF-block validation). No contact, no gravity.
//
// State: body (13) | input work [J] (1).
#include <array>

#include "core/scene.hpp"
#include "core/scenes/drivers.hpp"
#include "core/scenes/parts.hpp"

namespace rodend {
namespace {

constexpr int kBody = 0;
constexpr int kWork = BodyStateLayout::size;
constexpr int kStates = kWork + 1;

constexpr auto kSignals =
    concat(SignalId::time, SignalId::body_position, SignalId::body_velocity,
           SignalId::body_euler_321, SignalId::body_angular_velocity,
           SignalId::body_angular_momentum, kEnergySignals, SignalId::quaternion_norm_error);
static_assert(distinct(kSignals));
constexpr std::array kQuaternions{kBody + BodyStateLayout::q};
constexpr std::array kAudit{kWork};

class FreeBodyScene final : public Scene {
 public:
  explicit FreeBodyScene(const ParameterSet& p)
      : body_(read_body(p, "body")),
        force_(read_load(p, "force")),
        moment_(read_load(p, "moment")),
        p0_(p.vec3("body.initial_position")),
        v0_(p.vec3("body.initial_velocity")),
        w0_(p.vec3("body.initial_angular_velocity")),
        q0_(quat_from_rotation_vector(p.vec3("body.initial_rotation_vector"))) {}

  std::string_view name() const override { return "free-body"; }
  Features features() const override { return Features{Feature::energy_audit}; }
  int state_size() const override { return kStates; }
  void initial_state(double* x) const override {
    body_initial_state(x + kBody, p0_, v0_, q0_, w0_);
    x[kWork] = 0.0;
  }
  void state_scale(double* s) const override {
    // metres, metres per second, unit quaternion, radians per second: all order one here
    for (int i = 0; i < kStates; ++i) s[i] = 1.0;
  }
  std::span<const int> quaternion_offsets() const override { return kQuaternions; }
  std::span<const int> audit_offsets() const override { return kAudit; }

  void loads(double t, const BodyKinematics& k, Vec3& F_W, Vec3& M_W) const {
    F_W = force_.at(t);
    if (force_.body_frame) F_W = k.R_WB * F_W;
    M_W = moment_.at(t);
    if (moment_.body_frame) M_W = k.R_WB * M_W;
  }

  void derivatives(double t, const double* x, const DiscreteState&, double* dxdt) const override {
    const BodyKinematics k = BodyKinematics::from_state(x + kBody);
    Vec3 F, M;
    loads(t, k, F, M);
    body_derivatives(body_, k, F, M, x + kBody, dxdt + kBody);
    dxdt[kWork] = F.dot(k.v_W) + M.dot(k.w_W);  // input power
  }

  std::span<const SignalId> signals() const override { return kSignals; }
  EnergyTerms energy(double, const double* x, const DiscreteState&) const override {
    const BodyKinematics k = BodyKinematics::from_state(x + kBody);
    return {kinetic_energy(body_, k), x[kWork], 0.0};
  }
  void outputs(double t, const double* x, const DiscreteState& d, SignalFrame& f) const override {
    const BodyKinematics k = BodyKinematics::from_state(x + kBody);
    f.set(SignalId::body_position, k.p_W);
    f.set(SignalId::body_velocity, k.v_W);
    f.set(SignalId::body_euler_321, euler321(k.R_WB));
    f.set(SignalId::body_angular_velocity, k.w_B);
    f.set(SignalId::body_angular_momentum, angular_momentum_W(body_, k));
    write_energy_signals(f, energy(t, x, d), initial_energy());
    f.set(SignalId::quaternion_norm_error, quaternion_norm_error(x, kBody + BodyStateLayout::q));
  }

 private:
  double initial_energy() const {
    return 0.5 * body_.mass * v0_.squaredNorm() + 0.5 * w0_.dot(body_.inertia.cwiseProduct(w0_));
  }
  RigidBodyParams body_;
  Load force_, moment_;
  Vec3 p0_, v0_, w0_;
  Quat q0_;
};

}  // namespace

std::unique_ptr<Scene> make_free_body_scene(const ParameterSet& p) {
  return std::make_unique<FreeBodyScene>(p);
}

}  // namespace rodend
