#include "core/scenes/drivers.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "core/scenes/parts.hpp"

namespace rodend {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr std::array<std::string_view, 3> kShapeNames{"raised-cosine", "minimum-jerk", "step"};
constexpr std::array<std::string_view, 3> kHingeNames{"none", "constant", "proportional"};

/// The position of the text at `path` in `names`; InputError naming them if it is not there.
std::size_t catalogue_index(const ParameterSet& p, const std::string& path,
                            std::span<const std::string_view> names) {
  const std::string s = p.text(path);
  const auto it = std::find(names.begin(), names.end(), s);
  if (it != names.end()) return static_cast<std::size_t>(it - names.begin());
  std::string expected;
  for (std::size_t i = 0; i < names.size(); ++i)
    expected += (i == 0                  ? ""
                 : i + 1 == names.size() ? " or "
                                         : ", ") +
                ("\"" + std::string(names[i]) + "\"");
  throw InputError(path, "expected " + expected);
}

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

}  // namespace

double ActuatorMotion::duration() const {
  return start_time + cycles * (extension_time + retraction_time + 2.0 * hold_time);
}

ActuatorMotion::Sample ActuatorMotion::at(double t) const {
  const double period = extension_time + retraction_time + 2.0 * hold_time;
  if (t <= start_time) return {0.0, 0.0, 0.0};
  if (t >= duration()) return {-retraction, 0.0, 0.0};
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

std::span<const std::string_view> motion_shape_names() {
  return kShapeNames;
}

ActuatorMotion read_motion(const ParameterSet& p, const std::string& prefix) {
  ActuatorMotion m;
  m.shape = static_cast<ActuatorMotion::Shape>(catalogue_index(p, prefix + ".shape", kShapeNames));
  m.extension = read_positive(p, prefix + ".extension", true);
  m.retraction = read_positive(p, prefix + ".retraction", true);
  m.extension_time = read_positive(p, prefix + ".extension_time");
  m.retraction_time = read_positive(p, prefix + ".retraction_time");
  m.hold_time = read_positive(p, prefix + ".hold_time", true);
  m.start_time = read_positive(p, prefix + ".start_time", true);
  const double c = p.number(prefix + ".cycles");
  if (!(c >= 1.0 && c == std::floor(c) && c <= 1e6))
    throw InputError(prefix + ".cycles", "expected a whole number of cycles >= 1");
  m.cycles = static_cast<int>(c);
  return m;
}

double HingeMoment::at(double t, double theta) const {
  double m = sine_amplitude * std::sin(kTwoPi * sine_frequency * t);
  switch (kind) {
    case Kind::none:
      break;
    case Kind::constant:
      m += t >= step_time ? constant_moment : 0.0;
      break;
    case Kind::proportional:
      m -= stiffness * theta;
      break;
  }
  return m;
}

std::span<const std::string_view> hinge_moment_names() {
  return kHingeNames;
}

HingeMoment read_hinge(const ParameterSet& p, const std::string& prefix) {
  HingeMoment h;
  h.kind = static_cast<HingeMoment::Kind>(catalogue_index(p, prefix + ".kind", kHingeNames));
  h.constant_moment = p.number(prefix + ".constant_moment");
  h.step_time = read_positive(p, prefix + ".step_time", true);
  h.stiffness = read_positive(p, prefix + ".stiffness", true);
  h.sine_amplitude = p.number(prefix + ".sine_amplitude");
  h.sine_frequency = read_positive(p, prefix + ".sine_frequency", true);
  return h;
}

}  // namespace rodend
