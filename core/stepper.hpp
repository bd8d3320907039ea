// Internal to core: the stepper interface the integration driver uses, the scaled right-hand
// side, and the factory of the integrator menu. Each method is a Stepper: one accepted step at
// a time, with an interpolant over the last step.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "core/integrator_settings.hpp"
#include "core/scene.hpp"

namespace rodend::detail {

using state_t = std::vector<double>;

inline bool all_finite(const state_t& z) {
  return std::all_of(z.begin(), z.end(), [](double v) { return std::isfinite(v); });
}

/// Thrown inside the step loop; the driver turns it into a RunResult.
struct RunFailure {
  RunStatus status;
  std::string message;
};

/// Watches the right-hand side's evaluations for contacts the driver has not latched: the
/// earliest time at which a stage of the method evaluated one of them penetrating, an onset the
/// method's stages felt whatever its step ends show (the driver clears it before each step).
struct StageWatch {
  bool armed = false;                                         ///< some contact is not latched: look
  double earliest = std::numeric_limits<double>::infinity();  ///< [s]
  void see(const Scene& scene, const DiscreteState& discrete, double t, const double* x) {
    for (int c = 0; c < scene.contact_count(); ++c)
      if (!discrete.contacts[static_cast<std::size_t>(c)].in_contact && t < earliest &&
          scene.contact_gap(c, x).penetration > 0.0)
        earliest = t;
  }
};

/// The right-hand side in scaled variables z = x / scale. Holds references to the model and
/// the discrete state, plus scratch of its own; counts calls against a budget.
struct ScaledSystem {
  const Scene& scene;
  const DiscreteState& discrete;
  const state_t& scale;
  state_t x, dx;
  long long calls = 0;
  long long max_calls = 0;
  StageWatch* watch = nullptr;  ///< when set and armed, sees every evaluated state

  ScaledSystem(const Scene& s, const DiscreteState& d, const state_t& sc, long long budget)
      : scene(s), discrete(d), scale(sc), x(sc.size()), dx(sc.size()), max_calls(budget) {}
  void operator()(const state_t& z, state_t& dz, double t);
  /// The Jacobian in scaled variables, Jz[i * n + j] = d(dz_i/dt)/dz_j (row-major), from the
  /// scene's jacobian(); its finite differences count as right-hand-side calls
  /// (Scene::jacobian_cost() each).
  void jacobian(const state_t& z, double t, state_t& Jz);
  /// d(dz/dt)/dt at (t, z) by a forward difference in time (one call); dz is f(t, z).
  void time_derivative(const state_t& z, const state_t& dz, double t, state_t& dfdt);
  long long jacobians = 0;  ///< Jacobian evaluations
  state_t jx_;              ///< scratch: the unscaled Jacobian
  state_t dz2_;             ///< scratch
};

class Stepper {
 public:
  virtual ~Stepper() = default;
  /// (Re)starts at (t, z) with a first trial step dt.
  virtual void reset(const state_t& z, double t, double dt) = 0;
  /// Advances one accepted step, not past t_limit.
  virtual void step(double t_limit) = 0;
  /// State at t in [t_prev, t_now] on the method's interpolant.
  virtual void interpolate(double t, state_t& out) = 0;
  /// Whether the interpolant is as accurate as the method everywhere in the step (dense
  /// output): then steps need not land on sample times.
  virtual bool dense() const = 0;
  virtual double suggested_dt() const = 0;
  /// Whether the method locates contact onsets itself (CVODE's root finding): then `root_found`
  /// says that the last step ended at an onset.
  virtual bool finds_roots() const { return false; }
  /// Contacts whose onset the last step ended at (finds_roots() only).
  std::vector<int> roots;

  double t_prev = 0.0, t_now = 0.0;
  state_t z_prev, z_now;
  long long accepted = 0, rejected = 0;
};

/// Builds the stepper of `settings.method` (the integrator menu).
std::unique_ptr<Stepper> make_stepper(ScaledSystem& sys, const Scene& scene,
                                      const IntegratorSettings& settings);

/// One factory per family, each in its own file.
std::unique_ptr<Stepper> make_odeint_stepper(ScaledSystem& sys, const IntegratorSettings& s);
std::unique_ptr<Stepper> make_cvode_stepper(ScaledSystem& sys, const Scene& scene,
                                            const IntegratorSettings& s);

}  // namespace rodend::detail
