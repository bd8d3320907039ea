// A scene: the immutable model of one simulated system, composed of parts (bodies, the
// contact, springs, drivers, loads). Its state vector holds only the parts present.
//
// Model apart from data (as MuJoCo's mjModel / mjData): a Scene is constant after it is built
// and may be shared between threads. Everything that changes lives in the state vector `x`
// (continuous) or in DiscreteState (latched between accepted steps by the integration driver).
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/contact.hpp"
#include "core/features.hpp"
#include "core/params.hpp"
#include "core/signals.hpp"
#include "core/wear.hpp"

namespace rodend {

/// State that changes only between accepted steps.
struct DiscreteState {
  std::vector<ContactLatch> contacts;  ///< one per contact of the scene
};

/// Free play of a worn joint in one configuration (wear evolution).
struct JointPlay {
  double axial_clearance = 0.0;   ///< half the free play of the ball along the rod axis [m]
  double max_clearance = 0.0;     ///< largest local clearance in the mechanism plane [m]
  double surface_backlash = 0.0;  ///< free play of the surface angle, the axial play over
                                  ///< d(rod length)/d(surface angle) [rad]
};

/// Energy-audit terms at one instant [J]. `input_work` and `dissipated` are time integrals the
/// scene carries as states of its own.
struct EnergyTerms {
  double mechanical = 0.0;  ///< kinetic + potential (gravity, springs, contact)
  double input_work = 0.0;  ///< work of prescribed motions and applied loads since t = 0
  double dissipated = 0.0;  ///< energy dissipated since t = 0
};

/// A contact at one instant: what the driver reads on a step's interpolant to locate the
/// contact's force and penetration maxima (Scene::contact_snapshot).
struct ContactSnapshot {
  double penetration = 0.0;       ///< delta [m]
  double penetration_rate = 0.0;  ///< delta' [m/s]
  double eccentricity = 0.0;      ///< |e| [m]
  double normal_force = 0.0;      ///< F_n [N]
};

/// What the frame of an accepted step carries (Scene::step_outputs): the signals that the
/// per-step metrics (sweep/metrics.cpp) and the driver's checks read, of those a scene provides.
/// Full frames, every signal, are computed only at sample times.
inline constexpr SignalId kStepSignals[] = {SignalId::time,
                                            SignalId::eccentricity,
                                            SignalId::penetration,
                                            SignalId::penetration_rate,
                                            SignalId::impact_speed,
                                            SignalId::contact_force,
                                            SignalId::wear_indicator,
                                            SignalId::surface_angle,
                                            SignalId::surface_angle_command,
                                            SignalId::actuator_command,
                                            SignalId::actuator_position,
                                            SignalId::hinge_moment,
                                            SignalId::chamber_pressures,
                                            SignalId::lvdt_position,
                                            SignalId::surface_acceleration,
                                            SignalId::kinetic_energy,
                                            SignalId::input_work,
                                            SignalId::dissipated_energy,
                                            SignalId::energy_residual};

/// A single-frequency periodic input of a scene (a sine or triangle command or hinge moment):
/// where its whole periods lie, for the frequency-response and free-play metrics.
struct PeriodicInput {
  double frequency = 0.0;   ///< [Hz]
  double start_time = 0.0;  ///< start of the first period [s]
  int cycles = 0;           ///< whole periods from start_time
  double amplitude = 0.0;   ///< [the input's unit]
};
struct PeriodicInputs {
  std::optional<PeriodicInput> command;  ///< the position command (actuator_command signal)
  std::optional<PeriodicInput> load;     ///< the hinge moment (hinge_moment signal)
};

class Scene {
 public:
  virtual ~Scene() = default;
  virtual std::string_view name() const = 0;
  /// What this scene has (core/features.def), for these parameters (e.g. wear only with
  /// wear.model archard): whoever needs to know asks this, never the signal list.
  virtual Features features() const = 0;

  // --- state --------------------------------------------------------------------------------
  /// Number of continuous states.
  virtual int state_size() const = 0;
  /// Initial continuous state.
  virtual void initial_state(double* x) const = 0;
  /// Characteristic magnitude of each state, in its own unit. The driver integrates x / scale,
  /// so one scalar tolerance means the same thing for micrometres, metres and pascals.
  virtual void state_scale(double* scale) const = 0;
  /// Offsets of the unit quaternions in the state (renormalised by the driver between steps).
  virtual std::span<const int> quaternion_offsets() const { return {}; }
  /// Offsets of states that are only bookkeeping (energy integrals): excluded from error control.
  virtual std::span<const int> audit_offsets() const { return {}; }

  // --- dynamics -----------------------------------------------------------------------------
  /// dx/dt at (t, x) with the discrete state `d`. Reads only the model, t, x and d.
  virtual void derivatives(double t, const double* x, const DiscreteState& d,
                           double* dxdt) const = 0;

  /// The Jacobian of derivatives(): J[i * n + j] = d(dx_i/dt)/dx_j at (t, x) with the discrete
  /// state `d` (row-major, n = state_size()), for the implicit methods (rosenbrock4). By default
  /// forward differences of derivatives() (jacobian_cost() calls), the increment of state j
  /// sqrt(eps) times its state_scale(); a scene with an analytic Jacobian overrides it and says
  /// so in exact_jacobian(). Reads only the model, t, x and d.
  virtual void jacobian(double t, const double* x, const DiscreteState& d, double* J) const;
  /// Calls of derivatives() that the default jacobian() makes (n + 1, less the audit states).
  int jacobian_cost() const;
  /// Whether jacobian() is exact (analytic), not the default's finite differences.
  virtual bool exact_jacobian() const { return false; }

  // --- contacts (the driver latches their onsets) -------------------------------------------
  virtual int contact_count() const { return 0; }
  virtual ContactGap contact_gap(int /*contact*/, const double* /*x*/) const { return {-1.0, 0.0}; }
  /// friction.mode switch (ContactGap::stick): the friction force that would hold the contact
  /// stuck at time t and state x, over its static limit (ContactEval::stick_demand); a scene
  /// that accepts the mode overrides it. Reads only the model, t, x and d.
  virtual double stick_demand(int /*contact*/, double /*t*/, const double* /*x*/,
                              const DiscreteState& /*d*/) const {
    return 0.0;
  }
  /// Clearance of a contact [m] (for penetration health checks).
  virtual double contact_clearance(int /*contact*/) const { return 0.0; }
  /// The smaller radius of a contact's two surfaces (the ball's, the journal's) [m]: the length
  /// that bounds the elastic contact laws' validity (health.max_penetration_strain).
  virtual double contact_radius(int /*contact*/) const { return 0.0; }

  // --- wear (core/wear.hpp; scenes whose clearance contact wears) -------------------------
  /// The wear model of contact 0, or null when the scene does not model wear (wear.model
  /// "none"): the driver then deposits nothing and the state holds no wear integral.
  virtual const WearModel* wear_model() const { return nullptr; }
  /// Sliding power F_N v_slip and where it acts at (t, x) (scenes with a wear model).
  virtual WearSource wear_source(double /*t*/, const double* /*x*/,
                                 const DiscreteState& /*d*/) const {
    return {};
  }
  /// The same scene on worn surfaces (null when the scene does not model wear).
  virtual std::unique_ptr<Scene> with_worn_surfaces(std::shared_ptr<const WornSurfaces>) const {
    return nullptr;
  }
  /// Free play of the joint, worn surfaces included, in the configuration (t, x).
  virtual std::optional<JointPlay> joint_play(double /*t*/, const double* /*x*/) const {
    return std::nullopt;
  }

  /// The scene's single-frequency periodic inputs, if any (none by default).
  virtual PeriodicInputs periodic_inputs() const { return {}; }

  // --- outputs ------------------------------------------------------------------------------
  /// The catalogue signals this scene provides (time is always provided).
  virtual std::span<const SignalId> signals() const = 0;
  /// Fills the frame with this scene's signals at (t, x, d), energy terms included.
  virtual void outputs(double t, const double* x, const DiscreteState& d,
                       SignalFrame& frame) const = 0;
  /// The frame of an accepted step: at least the signals of kStepSignals this scene provides
  /// (the others may hold stale values). A scene whose full outputs cost much more overrides it;
  /// by default the full outputs().
  virtual void step_outputs(double t, const double* x, const DiscreteState& d,
                            SignalFrame& frame) const {
    outputs(t, x, d, frame);
  }
  /// Contact `c` at (t, x, d) (scenes with contacts). By default read from the full outputs'
  /// contact signals; a scene overrides it with its contact evaluation alone.
  virtual ContactSnapshot contact_snapshot(int c, double t, const double* x,
                                           const DiscreteState& d) const;
  /// Energy terms at (t, x).
  virtual EnergyTerms energy(double t, const double* x, const DiscreteState& d) const = 0;
};

/// Builds a scene from its resolved parameters; throws InputError (key path into the
/// parameters) for non-physical values.
using SceneFactory = std::unique_ptr<Scene> (*)(const ParameterSet&);

struct SceneEntry {
  std::string_view name;
  SceneFactory make;
  std::string_view summary;
};

/// The catalogue of scenes (core/scenes/scenes.def).
std::span<const SceneEntry> scene_catalogue();
const SceneEntry* find_scene(std::string_view name);
/// The embedded default parameter file of a scene (throws InputError for an unknown scene).
std::string_view scene_default_parameters_json(std::string_view scene);

/// Builds a scene by name from parameters (defaults plus overrides).
std::unique_ptr<Scene> make_scene(std::string_view name, const ParameterSet& params);

/// For tests: while it lives, make_scene builds scene `name` with `make` instead of the
/// catalogue's factory (the name, the defaults and the study's checks stay the catalogue's), e.g.
/// to wrap a scene in one that fails. One at a time; create and destroy it while no study loads
/// or runs (worker threads read it through an atomic pointer, never while it changes).
class SceneFactoryOverride {
 public:
  SceneFactoryOverride(std::string_view name, SceneFactory make);
  ~SceneFactoryOverride();
  SceneFactoryOverride(const SceneFactoryOverride&) = delete;
  SceneFactoryOverride& operator=(const SceneFactoryOverride&) = delete;
};

}  // namespace rodend
