// Drivers and loads of the mechanism scenes: the actuator motion profile (prescribed in
// rod-end-kinematic, the position command in rod-end-actuator) and the hinge moment.
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "core/params.hpp"

namespace rodend {

/// Smooth extension-retraction profile of the actuator (thesis fig. 5.1): the velocity is a
/// smooth pulse with no jumps, and the position is its integral. Per cycle: extension from the
/// retracted position to +extension over extension_time, hold, retraction to -retraction over
/// retraction_time, hold. The first extension starts from 0 at start_time.
///   shape raised-cosine: S(u) = u - sin(2 pi u)/(2 pi)  (velocity 1 - cos 2 pi u)
///   shape minimum-jerk:  S(u) = 10u^3 - 15u^4 + 6u^5
struct ActuatorMotion {
  /// step: the position jumps at the start of each stroke (a command only: the actuator scenes
  /// accept it, the kinematic scene, which needs a velocity, rejects it)
  enum class Shape { raised_cosine, minimum_jerk, step } shape = Shape::raised_cosine;
  double extension = 0.05;       ///< extended position [m]
  double retraction = 0.0;       ///< retracted position is -retraction [m]
  double extension_time = 1.0;   ///< [s]
  double retraction_time = 1.0;  ///< [s]
  double hold_time = 0.2;        ///< hold after each stroke [s]
  double start_time = 0.0;       ///< [s]
  int cycles = 1;

  /// Position [m], velocity [m/s] and acceleration [m/s^2] at time t.
  struct Sample {
    double position, velocity, acceleration;
  };
  Sample at(double t) const;
  /// Time at which the profile ends (after the last hold) [s].
  double duration() const;
};

/// The catalogue of profile shapes: the allowed values of `<prefix>.shape`, in the order of
/// ActuatorMotion::Shape.
std::span<const std::string_view> motion_shape_names();

/// Reads `<prefix>.*` (shape, extension, retraction, extension_time, retraction_time,
/// hold_time, start_time, cycles). Throws InputError.
ActuatorMotion read_motion(const ParameterSet& p, const std::string& prefix);

/// Hinge moment on the surface [N m], counter-clockwise positive (thesis §6.3.2):
///   none;  constant: M0 from step_time on (a negative M0 opposes extension);
///   proportional: -k theta, always opposing deflection;
///   plus an optional sinusoidal term A sin(2 pi f t).
struct HingeMoment {
  enum class Kind { none, constant, proportional } kind = Kind::none;
  double constant_moment = 0.0;  ///< M0 [N m]
  double step_time = 0.0;        ///< [s]
  double stiffness = 0.0;        ///< k [N m/rad]
  double sine_amplitude = 0.0;   ///< A [N m]
  double sine_frequency = 0.0;   ///< f [Hz]

  double at(double t, double theta) const;
};

/// The catalogue of hinge-moment kinds: the allowed values of hinge.kind, in the order of
/// HingeMoment::Kind.
std::span<const std::string_view> hinge_moment_names();

HingeMoment read_hinge(const ParameterSet& p, const std::string& prefix);

}  // namespace rodend
