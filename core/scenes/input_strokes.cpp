#include "core/scenes/input_strokes.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

namespace rodend {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

}  // namespace

StrokeParams read_stroke_params(const InputKeys& in) {
  StrokeParams s;
  s.extension = in.positive("extension", true);
  s.retraction = in.positive("retraction", true);
  s.extension_time = in.positive("extension_time");
  s.retraction_time = in.positive("retraction_time");
  s.hold_time = in.positive("hold_time", true);
  s.start_time = in.positive("start_time", true);
  s.cycles = in.cycles("cycles");
  return s;
}

Input::Scan Stroke::scan() const {
  const int cycles = std::min(s_.cycles, 2);
  return {s_.start_time + cycles * s_.period(), 20000 * cycles};
}

Input::Sample Stroke::at(double t) const {
  const double period = s_.period();
  if (t <= s_.start_time) return {0.0, 0.0, 0.0};
  // end_time(), from the period at hand (the right-hand side calls this each stage)
  if (t >= s_.start_time + s_.cycles * period) return {-s_.retraction, 0.0, 0.0};
  const double tc = t - s_.start_time;
  const int cycle = static_cast<int>(tc / period);
  double tau = tc - cycle * period;
  const double from = cycle == 0 ? 0.0 : -s_.retraction;
  double S, dS, ddS;
  // extension from `from` to +extension
  const double te = s_.extension_time, tr = s_.retraction_time;
  if (tau < te) {
    shape(tau / te, S, dS, ddS);
    const double a = s_.extension - from;
    return {from + a * S, a * dS / te, a * ddS / (te * te)};
  }
  tau -= te;
  if (tau < s_.hold_time) return {s_.extension, 0.0, 0.0};
  tau -= s_.hold_time;
  // retraction from +extension to -retraction
  if (tau < tr) {
    shape(tau / tr, S, dS, ddS);
    const double a = -(s_.extension + s_.retraction);
    return {s_.extension + a * S, a * dS / tr, a * ddS / (tr * tr)};
  }
  return {-s_.retraction, 0.0, 0.0};
}

InputPtr RaisedCosineStroke::read(const InputKeys& in) {
  return std::make_shared<RaisedCosineStroke>(read_stroke_params(in));
}

void RaisedCosineStroke::shape(double u, double& S, double& dS, double& ddS) const {
  S = u - std::sin(kTwoPi * u) / kTwoPi;
  dS = 1.0 - std::cos(kTwoPi * u);
  ddS = kTwoPi * std::sin(kTwoPi * u);
}

InputPtr MinimumJerkStroke::read(const InputKeys& in) {
  return std::make_shared<MinimumJerkStroke>(read_stroke_params(in));
}

void MinimumJerkStroke::shape(double u, double& S, double& dS, double& ddS) const {
  const double u2 = u * u, u3 = u2 * u;
  S = u3 * (10.0 - 15.0 * u + 6.0 * u2);
  dS = 30.0 * u2 * (1.0 - 2.0 * u + u2);
  ddS = 60.0 * u * (1.0 - 3.0 * u + 2.0 * u2);
}

InputPtr StepStroke::read(const InputKeys& in) {
  return std::make_shared<StepStroke>(read_stroke_params(in));
}

void StepStroke::shape(double u, double& S, double& dS, double& ddS) const {
  S = u > 0.0 ? 1.0 : 0.0;
  dS = ddS = 0.0;
}

}  // namespace rodend
