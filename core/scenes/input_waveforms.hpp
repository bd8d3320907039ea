// The waveforms (kinds of core/scenes/input.hpp; catalogue core/scenes/waveforms.def, inside the
// menus of the command, the hinge moment and the free body's loads): a periodic or swept w(t) on
// the window [start_time, end_time()], `offset` before it and its end value after it (offset
// after whole periods of sine and triangle; a chirp holds the value it ended at), tau =
// t - start_time. A new waveform is its line in waveforms.def and its class here (its formula
// in `inside`, in core/scenes/input_waveforms.cpp).
#pragma once

#include "core/scenes/input.hpp"

namespace rodend {

/// What every waveform reads: amplitude A >= 0, offset, start_time >= 0 (with InputKeys::unit,
/// A = 1 and offset 0, unread).
struct WaveformLevel {
  double amplitude = 1.0;
  double offset = 0.0;
  double start_time = 0.0;
};
WaveformLevel read_waveform_level(const InputKeys& in);

/// The frequency f > 0 and whole periods of a single-frequency waveform.
struct WavePeriods {
  double frequency = 1.0;
  int cycles = 1;
};
WavePeriods read_wave_periods(const InputKeys& in);

/// The sweep of a chirp: f0 > 0 to f1 >= f0 over chirp_duration D > 0.
struct ChirpSweep {
  double start_frequency = 1.0, end_frequency = 1.0, duration = 1.0;
};
ChirpSweep read_chirp_sweep(const InputKeys& in);

class Waveform : public Input {
 public:
  explicit Waveform(const WaveformLevel& l) : l_(l) {}
  Sample at(double t) const override;
  /// [offset - A, offset + A].
  std::pair<double, double> range() const override;
  std::pair<std::string_view, std::string_view> range_keys() const override {
    return {"amplitude", "amplitude"};
  }
  const WaveformLevel& level() const { return l_; }

 protected:
  /// The value and its derivatives at tau in the window.
  virtual Sample inside(double tau) const = 0;
  /// Whether the waveform returns to its offset after the window (whole periods).
  virtual bool ends_at_offset() const = 0;
  /// offset + A sin(2 pi phase) with instantaneous frequency f [Hz] and its rate df [Hz/s].
  Sample sinusoid(double phase, double f, double df) const;

 private:
  WaveformLevel l_;
};

/// A waveform of one frequency over `cycles` whole periods: a periodic input of the metrics.
class PeriodicWaveform : public Waveform {
 public:
  PeriodicWaveform(const WaveformLevel& l, const WavePeriods& w) : Waveform(l), w_(w) {}
  double end_time() const override { return level().start_time + w_.cycles / w_.frequency; }
  std::optional<PeriodicInput> periodic() const override {
    return PeriodicInput{w_.frequency, level().start_time, w_.cycles, level().amplitude};
  }

 protected:
  bool ends_at_offset() const override { return true; }
  const WavePeriods& periods() const { return w_; }

 private:
  WavePeriods w_;
};

/// A waveform swept from f0 to f1 over D.
class Chirp : public Waveform {
 public:
  Chirp(const WaveformLevel& l, const ChirpSweep& c) : Waveform(l), c_(c) {}
  double end_time() const override { return level().start_time + c_.duration; }

 protected:
  bool ends_at_offset() const override { return false; }
  const ChirpSweep& sweep() const { return c_; }

 private:
  ChirpSweep c_;
};

/// sine: offset + A sin(2 pi f tau).
class SineWave final : public PeriodicWaveform {
 public:
  using PeriodicWaveform::PeriodicWaveform;
  static InputPtr read(const InputKeys& in);
  double integral(double t) const override;

 protected:
  Sample inside(double tau) const override;
};

/// triangle: offset + A tri(f tau), tri rising 0 -> 1 -> -1 -> 0 in straight lines over a
/// period (the phase of the sine).
class TriangleWave final : public PeriodicWaveform {
 public:
  using PeriodicWaveform::PeriodicWaveform;
  static InputPtr read(const InputKeys& in);

 protected:
  Sample inside(double tau) const override;
};

/// linear-chirp: offset + A sin(2 pi (f0 tau + (f1 - f0) tau^2 / (2 D))).
class LinearChirp final : public Chirp {
 public:
  using Chirp::Chirp;
  static InputPtr read(const InputKeys& in);

 protected:
  Sample inside(double tau) const override;
};

/// log-chirp: offset + A sin(2 pi f0 D (k^(tau/D) - 1) / ln k), k = f1/f0 (k = 1: the sine at
/// f0); ln k is computed once, when it is made.
class LogChirp final : public Chirp {
 public:
  LogChirp(const WaveformLevel& l, const ChirpSweep& c);
  static InputPtr read(const InputKeys& in);

 protected:
  Sample inside(double tau) const override;

 private:
  double log_ratio_;
};

}  // namespace rodend
