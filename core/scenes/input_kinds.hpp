// The kinds of input (core/scenes/input.hpp), one class each. A kind is a line of the menus that
// offer it (core/scenes/motion_shapes.def, hinge_moments.def, load_kinds.def, and waveforms.def
// inside all three) naming its class; the class reads its keys (`static InputPtr read`, under
// the prefix of InputKeys) and computes the value. Adding a kind is its line and its class.
#pragma once

#include <limits>

#include "core/scenes/input.hpp"
#include "core/scenes/profile.hpp"

namespace rodend {

/// none: 0 at every time.
class NoInput final : public Input {
 public:
  static InputPtr read(const InputKeys&);
  Sample at(double) const override { return {0.0, 0.0, 0.0}; }
  bool is_zero() const override { return true; }
  double integral(double) const override { return 0.0; }
  double end_time() const override { return 0.0; }
  std::pair<double, double> range() const override { return {0.0, 0.0}; }
  std::pair<std::string_view, std::string_view> range_keys() const override;
};

/// constant (a load): A at every time (1 for a load's shape; else `amplitude`).
class ConstantInput final : public Input {
 public:
  explicit ConstantInput(double level) : level_(level) {}
  static InputPtr read(const InputKeys& in);
  Sample at(double) const override { return {level_, 0.0, 0.0}; }
  double integral(double t) const override { return level_ * t; }
  double end_time() const override { return 0.0; }
  std::pair<double, double> range() const override { return {level_, level_}; }
  std::pair<std::string_view, std::string_view> range_keys() const override;

 private:
  double level_;
};

/// constant (the hinge): M0 (`constant_moment`) from `step_time` on, 0 before.
class StepInput final : public Input {
 public:
  StepInput(double level, double time) : level_(level), time_(time) {}
  static InputPtr read(const InputKeys& in);
  Sample at(double t) const override { return {t >= time_ ? level_ : 0.0, 0.0, 0.0}; }
  double integral(double t) const override { return t > time_ ? level_ * (t - time_) : 0.0; }
  double end_time() const override { return time_; }
  std::pair<double, double> range() const override;
  std::pair<std::string_view, std::string_view> range_keys() const override;

 private:
  double level_, time_;
};

/// proportional: -k s (`stiffness` k >= 0), always opposing the state s (the surface angle).
class ProportionalInput final : public Input {
 public:
  explicit ProportionalInput(double k) : k_(k) {}
  static InputPtr read(const InputKeys& in);
  Sample at(double) const override { return {0.0, 0.0, 0.0}; }
  double value(double, double state) const override { return 0.0 - k_ * state; }
  double slope() const override { return -k_; }
  double end_time() const override { return 0.0; }
  std::pair<double, double> range() const override;
  std::pair<std::string_view, std::string_view> range_keys() const override;

 private:
  double k_;
};

/// ramp (a load): A t / T (`ramp_time` T > 0), without end.
class RampInput final : public Input {
 public:
  RampInput(double level, double ramp_time) : level_(level), ramp_time_(ramp_time) {}
  static InputPtr read(const InputKeys& in);
  Sample at(double t) const override {
    return {level_ * (t / ramp_time_), level_ / ramp_time_, 0.0};
  }
  double integral(double t) const override { return level_ * (0.5 * t * t / ramp_time_); }
  double end_time() const override { return std::numeric_limits<double>::infinity(); }
  std::pair<double, double> range() const override;
  std::pair<std::string_view, std::string_view> range_keys() const override;

 private:
  double level_, ramp_time_;
};

/// A sinusoid A sin(2 pi f t) from t = 0 without end: the hinge moment's optional sine term
/// (`sine_amplitude`, `sine_frequency`), added to its kind by SumInput.
class SinusoidInput final : public Input {
 public:
  SinusoidInput(double amplitude, double frequency) : a_(amplitude), f_(frequency) {}
  Sample at(double t) const override;
  double value(double t, double) const override;
  double integral(double t) const override;
  double end_time() const override { return std::numeric_limits<double>::infinity(); }
  std::pair<double, double> range() const override;
  std::pair<std::string_view, std::string_view> range_keys() const override;

 private:
  double a_, f_;
};

/// first + second (the hinge's sine term and its kind). periodic() is the second's (the kind's),
/// as the metrics read the kind.
class SumInput final : public Input {
 public:
  SumInput(InputPtr first, InputPtr second) : a_(std::move(first)), b_(std::move(second)) {}
  Sample at(double t) const override;
  double value(double t, double s) const override { return a_->value(t, s) + b_->value(t, s); }
  double slope() const override { return a_->slope() + b_->slope(); }
  bool is_zero() const override { return a_->is_zero() && b_->is_zero(); }
  double integral(double t) const override { return a_->integral(t) + b_->integral(t); }
  double end_time() const override;
  std::pair<double, double> range() const override;
  std::pair<std::string_view, std::string_view> range_keys() const override;
  std::optional<PeriodicInput> periodic() const override { return b_->periodic(); }

 private:
  InputPtr a_, b_;
};

/// profile: a time series from a file (`<prefix>.profile.*`, core/scenes/profile.hpp).
class ProfileFromFile final : public Input {
 public:
  explicit ProfileFromFile(ProfileInput profile) : profile_(std::move(profile)) {}
  static InputPtr read(const InputKeys& in);
  Sample at(double t) const override;
  double end_time() const override { return profile_.end_time(); }
  std::pair<double, double> range() const override { return profile_.range(); }
  std::pair<std::string_view, std::string_view> range_keys() const override;
  const ProfileInput& profile() const { return profile_; }

 private:
  ProfileInput profile_;
};

}  // namespace rodend

#include "core/scenes/input_strokes.hpp"
#include "core/scenes/input_waveforms.hpp"
