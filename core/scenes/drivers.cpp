#include "core/scenes/drivers.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "core/scenes/parts.hpp"

namespace rodend {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
// the waveforms sit at the same place in both menus that include them
constexpr auto kWaveformCount = choice_count(WaveformKind{});
static_assert(static_cast<int>(MotionShape::profile) - static_cast<int>(MotionShape::sine) ==
              static_cast<int>(kWaveformCount));
static_assert(static_cast<int>(HingeMomentKind::profile) -
                  static_cast<int>(HingeMomentKind::sine) ==
              static_cast<int>(kWaveformCount));

/// Normalised stroke S(u), u in [0, 1], and its first two derivatives.
void stroke_shape(ActuatorMotion::Shape s, double u, double& S, double& dS, double& ddS) {
  if (s == ActuatorMotion::Shape::step) {
    S = u > 0.0 ? 1.0 : 0.0;
    dS = ddS = 0.0;
  } else if (s == ActuatorMotion::Shape::raised_cosine) {
    S = u - std::sin(kTwoPi * u) / kTwoPi;
    dS = 1.0 - std::cos(kTwoPi * u);
    ddS = kTwoPi * std::sin(kTwoPi * u);
  } else {
    const double u2 = u * u, u3 = u2 * u;
    S = u3 * (10.0 - 15.0 * u + 6.0 * u2);
    dS = 30.0 * u2 * (1.0 - 2.0 * u + u2);
    ddS = 60.0 * u * (1.0 - 3.0 * u + 2.0 * u2);
  }
}

/// tri(phase): 0 -> 1 -> -1 -> 0 in straight lines over one period, and its slope.
void triangle(double phase, double& w, double& dw) {
  const double u = phase - std::floor(phase);
  if (u < 0.25) {
    w = 4.0 * u, dw = 4.0;
  } else if (u < 0.75) {
    w = 2.0 - 4.0 * u, dw = -4.0;
  } else {
    w = 4.0 * u - 4.0, dw = 4.0;
  }
}

/// A whole number of cycles >= 1 at `key`.
int read_cycles(const ParameterSet& p, const std::string& key) {
  const double c = p.number(key);
  if (!(c >= 1.0 && c == std::floor(c) && c <= 1e6))
    throw InputError(key, "expected a whole number of cycles >= 1");
  return static_cast<int>(c);
}

}  // namespace

std::optional<PeriodicInput> periodic_input(const Waveform& w) {
  if (!w.single_frequency()) return std::nullopt;
  return PeriodicInput{w.frequency, w.start_time, w.cycles, w.amplitude};
}

bool Waveform::single_frequency() const {
  static constexpr bool kSingle[] = {
#define RODEND_CHOICE(identifier, name, description, single_frequency) single_frequency,
#include "core/scenes/waveforms.def"
#undef RODEND_CHOICE
  };
  return kSingle[static_cast<std::size_t>(kind)];
}

double Waveform::end_time() const {
  return start_time + (single_frequency() ? cycles / frequency : chirp_duration);
}

Waveform::Sample Waveform::at(double t) const {
  const double tau = t - start_time;
  if (tau < 0.0) return {offset, 0.0, 0.0};
  // after the window: the end value (offset after whole periods; a chirp holds where it ended)
  if (t > end_time()) return {single_frequency() ? offset : at(end_time()).value, 0.0, 0.0};
  // phase [cycles], instantaneous frequency f = dphase/dt [Hz] and its rate df/dt [Hz/s]
  double phase = frequency * tau, f = frequency, df = 0.0;
  if (kind == Kind::triangle) {
    double w, dw;
    triangle(phase, w, dw);
    return {offset + amplitude * w, amplitude * dw * frequency, 0.0};
  }
  if (kind == Kind::linear_chirp) {
    df = (end_frequency - start_frequency) / chirp_duration;
    f = start_frequency + df * tau;
    phase = start_frequency * tau + 0.5 * df * tau * tau;
  } else if (kind == Kind::log_chirp) {
    const bool known = log_ratio_of[0] == start_frequency && log_ratio_of[1] == end_frequency;
    const double lk = known ? log_ratio : std::log(end_frequency / start_frequency);
    const double g = std::exp(lk * tau / chirp_duration);  // k^(tau/D)
    f = start_frequency * g;
    df = f * lk / chirp_duration;
    phase = lk > 0.0 ? start_frequency * chirp_duration * (g - 1.0) / lk : start_frequency * tau;
  }
  const double s = std::sin(kTwoPi * phase), c = std::cos(kTwoPi * phase);
  return {offset + amplitude * s, amplitude * kTwoPi * f * c,
          amplitude * (kTwoPi * df * c - kTwoPi * kTwoPi * f * f * s)};
}

Waveform read_waveform(const ParameterSet& p, const std::string& pre, Waveform::Kind kind) {
  Waveform w;
  w.kind = kind;
  w.amplitude = read_positive(p, pre + ".amplitude", true);
  w.offset = p.number(pre + ".offset");
  if (!std::isfinite(w.offset)) throw InputError(pre + ".offset", "expected a finite value");
  w.start_time = read_positive(p, pre + ".start_time", true);
  if (w.single_frequency()) {
    w.frequency = read_positive(p, pre + ".frequency");
    w.cycles = read_cycles(p, pre + ".cycles");
    return w;
  }
  w.start_frequency = read_positive(p, pre + ".start_frequency");
  w.end_frequency = read_positive(p, pre + ".end_frequency");
  w.chirp_duration = read_positive(p, pre + ".chirp_duration");
  if (w.end_frequency < w.start_frequency)
    throw InputError(pre + ".end_frequency",
                     "the chirp's end frequency " + format_number(w.end_frequency) +
                         " Hz precedes its start frequency " + format_number(w.start_frequency) +
                         " Hz: a chirp sweeps upwards (start_frequency <= end_frequency)");
  w.log_ratio = std::log(w.end_frequency / w.start_frequency);
  w.log_ratio_of[0] = w.start_frequency;
  w.log_ratio_of[1] = w.end_frequency;
  return w;
}

double ActuatorMotion::duration() const {
  if (shape == Shape::profile) return profile.end_time();
  if (is_waveform()) return wave.end_time();
  return start_time + cycles * stroke_period();
}

std::pair<double, double> ActuatorMotion::range() const {
  if (shape == Shape::profile) {
    const auto [lo, hi] = profile.range();
    return {std::min(0.0, lo), std::max(0.0, hi)};
  }
  if (is_waveform())
    return {std::min(0.0, wave.offset - wave.amplitude),
            std::max(0.0, wave.offset + wave.amplitude)};
  return {std::min(0.0, -retraction), std::max(0.0, extension)};
}

ActuatorMotion::Sample ActuatorMotion::at(double t) const {
  if (shape == Shape::profile) {
    const ProfileInput::Sample s = profile.at(t);
    return {s.value, s.rate, s.acceleration};
  }
  if (is_waveform()) {
    const Waveform::Sample w = wave.at(t);
    return {w.value, w.rate, w.acceleration};
  }
  const double period = stroke_period();
  if (t <= start_time) return {0.0, 0.0, 0.0};
  // duration() of a stroke, from the period at hand (the right-hand side calls this each stage)
  if (t >= start_time + cycles * period) return {-retraction, 0.0, 0.0};
  const double tc = t - start_time;
  const int cycle = static_cast<int>(tc / period);
  double tau = tc - cycle * period;
  const double from = cycle == 0 ? 0.0 : -retraction;
  double S, dS, ddS;
  // extension from `from` to +extension
  if (tau < extension_time) {
    stroke_shape(shape, tau / extension_time, S, dS, ddS);
    const double a = extension - from;
    return {from + a * S, a * dS / extension_time, a * ddS / (extension_time * extension_time)};
  }
  tau -= extension_time;
  if (tau < hold_time) return {extension, 0.0, 0.0};
  tau -= hold_time;
  // retraction from +extension to -retraction
  if (tau < retraction_time) {
    stroke_shape(shape, tau / retraction_time, S, dS, ddS);
    const double a = -(extension + retraction);
    return {extension + a * S, a * dS / retraction_time,
            a * ddS / (retraction_time * retraction_time)};
  }
  return {-retraction, 0.0, 0.0};
}

ActuatorMotion read_motion(const ParameterSet& p, const std::string& prefix) {
  ActuatorMotion m;
  m.shape = read_choice<MotionShape>(p, prefix + ".shape");
  m.extension = read_positive(p, prefix + ".extension", true);
  m.retraction = read_positive(p, prefix + ".retraction", true);
  m.extension_time = read_positive(p, prefix + ".extension_time");
  m.retraction_time = read_positive(p, prefix + ".retraction_time");
  m.hold_time = read_positive(p, prefix + ".hold_time", true);
  m.start_time = read_positive(p, prefix + ".start_time", true);
  m.cycles = read_cycles(p, prefix + ".cycles");
  if (m.is_waveform())
    m.wave =
        read_waveform(p, prefix,
                      static_cast<Waveform::Kind>(static_cast<int>(m.shape) -
                                                  static_cast<int>(ActuatorMotion::Shape::sine)));
  if (m.shape == ActuatorMotion::Shape::profile)
    m.profile = read_profile_input(p, prefix + ".profile");
  return m;
}

double HingeMoment::at(double t, double theta) const {
  // no sine term, no sin call (the right-hand side calls this each stage)
  double m = sine_amplitude != 0.0 ? sine_amplitude * std::sin(kTwoPi * sine_frequency * t) : 0.0;
  switch (kind) {
    case Kind::none:
      break;
    case Kind::constant:
      m += t >= step_time ? constant_moment : 0.0;
      break;
    case Kind::proportional:
      m -= stiffness * theta;
      break;
    case Kind::profile:
      m += profile.at(t).value;
      break;
    default:  // a waveform
      m += wave.at(t).value;
      break;
  }
  return m;
}

HingeMoment read_hinge(const ParameterSet& p, const std::string& prefix) {
  HingeMoment h;
  h.kind = read_choice<HingeMomentKind>(p, prefix + ".kind");
  h.constant_moment = p.number(prefix + ".constant_moment");
  h.step_time = read_positive(p, prefix + ".step_time", true);
  h.stiffness = read_positive(p, prefix + ".stiffness", true);
  h.sine_amplitude = p.number(prefix + ".sine_amplitude");
  h.sine_frequency = read_positive(p, prefix + ".sine_frequency", true);
  if (h.is_waveform())
    h.wave = read_waveform(p, prefix,
                           static_cast<Waveform::Kind>(static_cast<int>(h.kind) -
                                                       static_cast<int>(HingeMoment::Kind::sine)));
  if (h.kind == HingeMoment::Kind::profile) h.profile = read_profile_input(p, prefix + ".profile");
  return h;
}

}  // namespace rodend
