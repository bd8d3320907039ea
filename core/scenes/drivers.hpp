// Drivers and loads of the mechanism scenes: the actuator motion profile (prescribed in
// rod-end-kinematic, the position command in rod-end-actuator) and the hinge moment.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <utility>

#include "core/choice.hpp"
#include "core/params.hpp"
#include "core/scene.hpp"
#include "core/scenes/profile.hpp"

namespace rodend {

/// The menus of this file (core/choice.hpp): the waveforms (core/scenes/waveforms.def), offered
/// both as position commands (motion.shape, core/scenes/motion_shapes.def) and as hinge moments
/// (hinge.kind, core/scenes/hinge_moments.def), which include the waveforms' lines: one line
/// adds a waveform to both (its formula goes in Waveform::at, drivers.cpp).
#define RODEND_CHOICE_ENUM WaveformKind
#define RODEND_CHOICE_FILE "core/scenes/waveforms.def"
#include "core/choice.hpp"
#define RODEND_CHOICE_ENUM MotionShape
#define RODEND_CHOICE_FILE "core/scenes/motion_shapes.def"
#include "core/choice.hpp"
#define RODEND_CHOICE_ENUM HingeMomentKind
#define RODEND_CHOICE_FILE "core/scenes/hinge_moments.def"
#include "core/choice.hpp"

/// A periodic or swept waveform w(t) on the window [start_time, end_time()], `offset` before
/// it and its end value after it (offset after whole periods of sine and triangle; a chirp
/// holds the value it ended at) (tau = t - start_time):
///   sine:         offset + A sin(2 pi f tau), `cycles` whole periods
///   triangle:     offset + A tri(f tau), tri rising 0 -> 1 -> -1 -> 0 in straight lines over a
///                 period (the phase of the sine), `cycles` whole periods
///   linear-chirp: offset + A sin(2 pi (f0 tau + (f1 - f0) tau^2 / (2 D))), over D
///   log-chirp:    offset + A sin(2 pi f0 D (k^(tau/D) - 1) / ln k), k = f1/f0, over D
/// (the chirps' instantaneous frequency runs from f0 to f1 linearly or geometrically in time).
struct Waveform {
  using Kind = WaveformKind;
  Kind kind = Kind::sine;
  double amplitude = 0.0;        ///< A [unit of the signal]
  double frequency = 1.0;        ///< f of sine and triangle [Hz]
  double offset = 0.0;           ///< [unit of the signal]
  double start_time = 0.0;       ///< [s]
  int cycles = 1;                ///< whole periods of sine and triangle
  double start_frequency = 1.0;  ///< f0 of the chirps [Hz]
  double end_frequency = 1.0;    ///< f1 of the chirps [Hz]
  double chirp_duration = 1.0;   ///< D [s]
  /// ln k = ln(f1/f0) of the log chirp, for the frequencies in `log_ratio_of` (f0, f1): computed
  /// once by read_waveform instead of at every call of at(), which recomputes it only for other
  /// frequencies (a waveform built or changed by hand)
  double log_ratio = 0.0;
  double log_ratio_of[2] = {0.0, 0.0};

  /// Value and its first two time derivatives.
  struct Sample {
    double value, rate, acceleration;
  };
  Sample at(double t) const;
  double end_time() const;
  /// Whether the waveform has one frequency (sine, triangle): what the frequency-response and
  /// free-play metrics read (Scene::periodic_inputs).
  bool single_frequency() const;
};

/// The waveform as a PeriodicInput (Scene::periodic_inputs) when it has one frequency.
std::optional<PeriodicInput> periodic_input(const Waveform& w);

/// Reads the waveform keys under `prefix` (amplitude, frequency, offset, start_time, cycles,
/// start_frequency, end_frequency, chirp_duration), checking only those `kind` uses: a frequency
/// or a duration <= 0, a chirp whose end frequency precedes (is below) its start frequency, a
/// cycle count that is not a whole number >= 1. Throws InputError naming the key.
Waveform read_waveform(const ParameterSet& p, const std::string& prefix, Waveform::Kind kind);

/// Smooth extension-retraction profile of the actuator (thesis fig. 5.1): the velocity is a
/// smooth pulse with no jumps, and the position is its integral. Per cycle: extension from the
/// retracted position to +extension over extension_time, hold, retraction to -retraction over
/// retraction_time, hold. The first extension starts from 0 at start_time.
///   shape raised-cosine: S(u) = u - sin(2 pi u)/(2 pi)  (velocity 1 - cos 2 pi u)
///   shape minimum-jerk:  S(u) = 10u^3 - 15u^4 + 6u^5
struct ActuatorMotion {
  /// step: the position jumps at the start of each stroke (a command only: the actuator scenes
  /// accept it, the kinematic scene, which needs a velocity, rejects it)
  /// then the waveforms (core/scenes/waveforms.def), which replace the stroke by `wave`
  /// then profile: a time series from a file (`<prefix>.profile.*`, core/scenes/profile.hpp)
  using Shape = MotionShape;
  Shape shape = Shape::raised_cosine;
  double extension = 0.05;       ///< extended position [m]
  double retraction = 0.0;       ///< retracted position is -retraction [m]
  double extension_time = 1.0;   ///< [s]
  double retraction_time = 1.0;  ///< [s]
  double hold_time = 0.2;        ///< hold after each stroke [s]
  double start_time = 0.0;       ///< [s]
  int cycles = 1;
  Waveform wave;  ///< the waveform of a waveform shape (its start_time and cycles are the above)
  ProfileInput profile;  ///< the time series of shape profile [m]

  /// Whether the shape is a waveform (sine, chirp, triangle).
  bool is_waveform() const { return shape > Shape::step && shape < Shape::profile; }
  /// Whether the shape is a stroke out and back (raised-cosine, minimum-jerk, step).
  bool is_stroke() const { return shape <= Shape::step; }
  /// The smallest and largest position the profile reaches [m] (0 included: the start).
  std::pair<double, double> range() const;

  /// Position [m], velocity [m/s] and acceleration [m/s^2] at time t.
  struct Sample {
    double position, velocity, acceleration;
  };
  Sample at(double t) const;
  /// Time at which the profile ends (after the last hold; a profile's last sample) [s].
  double duration() const;
  /// One stroke cycle: extension, hold, retraction, hold [s].
  double stroke_period() const { return extension_time + retraction_time + 2.0 * hold_time; }
};

/// Reads `<prefix>.*` (shape, extension, retraction, extension_time, retraction_time,
/// hold_time, start_time, cycles; the waveform's keys; `<prefix>.profile.*` for a profile).
/// Throws InputError.
ActuatorMotion read_motion(const ParameterSet& p, const std::string& prefix);

/// Hinge moment on the surface [N m], counter-clockwise positive (thesis §6.3.2):
///   none;  constant: M0 from step_time on (a negative M0 opposes extension);
///   proportional: -k theta, always opposing deflection;
///   plus an optional sinusoidal term A sin(2 pi f t).
struct HingeMoment {
  /// then the waveforms (core/scenes/waveforms.def): M = the waveform `wave`
  /// then profile: M = the time series `profile` from a file (`<prefix>.profile.*`)
  using Kind = HingeMomentKind;
  Kind kind = Kind::none;
  double constant_moment = 0.0;  ///< M0 [N m]
  double step_time = 0.0;        ///< [s]
  double stiffness = 0.0;        ///< k [N m/rad]
  double sine_amplitude = 0.0;   ///< A [N m]
  double sine_frequency = 0.0;   ///< f [Hz]
  Waveform wave;                 ///< the moment of a waveform kind [N m]
  ProfileInput profile;          ///< the moment of kind profile [N m]

  bool is_waveform() const { return kind > Kind::proportional && kind < Kind::profile; }

  double at(double t, double theta) const;
  /// Whether at() is 0 at every (t, theta): kind none without a sine term.
  bool is_zero() const { return kind == Kind::none && sine_amplitude == 0.0; }
  /// d at / d theta [N m/rad] (the exact Jacobians).
  double slope() const { return kind == Kind::proportional ? -stiffness : 0.0; }
};

HingeMoment read_hinge(const ParameterSet& p, const std::string& prefix);

}  // namespace rodend
