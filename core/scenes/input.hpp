// The inputs of the scenes: one interface for every time-varying load and command (the position
// command of the actuator scenes and the linkage, the hinge moment, the free body's force and
// moment), one class per kind behind it (core/scenes/input_kinds.hpp), in the manner of
// Chrono's ChFunction. A menu of kinds is a catalogue (.def) whose lines name each kind's class;
// read_input makes the input a parameter prefix names.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "core/params.hpp"
#include "core/scene.hpp"

namespace rodend {

/// A scalar input u(t) [the unit of what it drives: m, N m, or 1 for a load's shape], and for
/// the state-dependent kinds u(t, s) of one state s (the hinge's proportional moment, -k theta).
/// Immutable once made: cases and threads share it.
class Input {
 public:
  /// Value and its first two time derivatives.
  struct Sample {
    double value, rate, acceleration;
  };
  virtual ~Input() = default;

  /// The value and its time derivatives at t (a state-dependent kind: at state 0).
  virtual Sample at(double t) const = 0;
  /// The value at (t, state): at(t).value unless the kind reads the state.
  virtual double value(double t, double /*state*/) const { return at(t).value; }
  /// d value / d state (the exact Jacobians): 0 unless the kind reads the state.
  virtual double slope() const { return 0.0; }
  /// Whether value() is 0 at every (t, state) (no call needed).
  virtual bool is_zero() const { return false; }
  /// The integral of the value from 0 to t: a closed form where the kind has one, else the
  /// composite Simpson rule on 4096 intervals.
  virtual double integral(double t) const;
  /// The time after which the input no longer changes [s] (+infinity when it never stops).
  virtual double end_time() const = 0;
  /// The smallest and largest value the input reaches.
  virtual std::pair<double, double> range() const = 0;
  /// The keys, relative to the input's prefix, that set the smallest and the largest value:
  /// what a check of the range names.
  virtual std::pair<std::string_view, std::string_view> range_keys() const = 0;
  /// The input as the frequency-response and free-play metrics read it (Scene::periodic_inputs)
  /// when it has a single frequency over whole periods.
  virtual std::optional<PeriodicInput> periodic() const { return std::nullopt; }
  /// Where a scan for the value's extremes ends [s] and how many samples it takes: the whole
  /// input (end_time) in 200000 by default; an input whose later cycles repeat earlier ones ends
  /// it sooner.
  struct Scan {
    double end;
    int samples;
  };
  virtual Scan scan() const { return {end_time(), 200000}; }
};

using InputPtr = std::shared_ptr<const Input>;

/// What a kind reads its keys from: `<prefix>.<leaf>` of the parameters. With `unit`, the
/// input is the shape of a vector load whose amplitude the load reads itself (the free body's
/// force and moment): a kind's own amplitude is then 1 and its offset 0, neither read.
struct InputKeys {
  const ParameterSet& p;
  std::string prefix;
  bool unit = false;

  std::string key(std::string_view leaf) const { return prefix + "." + std::string(leaf); }
  double number(std::string_view leaf) const { return p.number(key(leaf)); }
  /// A value > 0 (>= 0 with allow_zero), else InputError naming the key.
  double positive(std::string_view leaf, bool allow_zero = false) const;
  /// A whole number of cycles >= 1 (at most 1e6), else InputError naming the key.
  int cycles(std::string_view leaf) const;
};

}  // namespace rodend
