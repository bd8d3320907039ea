// One sensor while a case runs (sweep/sensors.hpp): its low-pass integrated exactly between
// accepted steps, its samples at its own rate, their noise, bias and quantisation.
#pragma once

#include <cstdint>
#include <vector>

#include "core/signals.hpp"
#include "sweep/sensors.hpp"

namespace rodend {

/// A seeded normal generator: xoshiro256** (Blackman & Vigna 2018) seeded by splitmix64,
/// Box-Muller pairs. Spelled out (not std::normal_distribution, whose algorithm each standard
/// library chooses) so that a seed gives the same record on every platform.
class NormalStream {
 public:
  explicit NormalStream(std::uint64_t seed);
  double next();

 private:
  std::uint64_t bits();
  std::uint64_t s_[4];
  double spare_ = 0.0;
  bool has_spare_ = false;
};

/// The low-pass of a sensor: 1 / (1 + s/w) (first order) or w^2 / (s^2 + sqrt(2) w s + w^2)
/// (second-order Butterworth), w = 2 pi cut-off; order 0 passes its input. Advanced exactly for
/// an input linear in time: u(t0 + tau) = u0 + slope tau.
class LowPass {
 public:
  LowPass(int order, double cutoff_hz);
  /// At rest at the input u (the output u, its rate 0).
  void reset(double u);
  /// Advances by tau with the input u0 + slope t over it (u0 the input at the start).
  void advance(double tau, double u0, double slope);
  double output() const { return y_; }

 private:
  int order_;
  double w_;
  double y_ = 0.0, dy_ = 0.0;
};

/// One sensor's record: samples at k / rate, k = 0, 1, ..., of the low-passed component of
/// its signal, plus bias and noise, quantised.
class SensorChannel {
 public:
  SensorChannel(const SensorSpec& spec, double noise_scale, long long seed,
                long design_sample = -1);
  /// The first frame (t = 0): the filter at rest at its value, the sample at 0.
  void start(const SignalFrame& f);
  /// The frame of the next accepted step: the input linear from the last frame's value.
  void advance(const SignalFrame& f);
  const SensorSpec& spec() const { return spec_; }
  SignalId signal() const { return signal_; }
  const std::vector<double>& times() const { return times_; }
  const std::vector<double>& values() const { return values_; }

 private:
  void sample(double t);
  SensorSpec spec_;
  SignalId signal_;
  double noise_;
  LowPass filter_;
  NormalStream noise_stream_;
  double t_ = 0.0, u_ = 0.0;  // the last frame's time and value
  long long next_ = 0;        // index of the next sample
  bool started_ = false;
  std::vector<double> times_, values_;
};

}  // namespace rodend
