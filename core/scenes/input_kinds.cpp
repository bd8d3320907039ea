#include "core/scenes/input_kinds.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

#include "core/scenes/parts.hpp"

namespace rodend {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

double InputKeys::positive(std::string_view leaf, bool allow_zero) const {
  return read_positive(p, key(leaf), allow_zero);
}

int InputKeys::cycles(std::string_view leaf) const {
  const double c = number(leaf);
  if (!(c >= 1.0 && c == std::floor(c) && c <= 1e6))
    throw InputError(key(leaf), "expected a whole number of cycles >= 1");
  return static_cast<int>(c);
}

double Input::integral(double t) const {
  constexpr int n = 4096;  // even
  const double h = t / n;
  double sum = at(0.0).value + at(t).value;
  for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * at(i * h).value;
  return sum * h / 3.0;
}

InputPtr NoInput::read(const InputKeys&) {
  return std::make_shared<NoInput>();
}
std::pair<std::string_view, std::string_view> NoInput::range_keys() const {
  return {"kind", "kind"};
}

InputPtr ConstantInput::read(const InputKeys& in) {
  return std::make_shared<ConstantInput>(in.unit ? 1.0 : in.number("amplitude"));
}
std::pair<std::string_view, std::string_view> ConstantInput::range_keys() const {
  return {"amplitude", "amplitude"};
}

InputPtr StepInput::read(const InputKeys& in) {
  const double level = in.number("constant_moment");
  return std::make_shared<StepInput>(level, in.positive("step_time", true));
}
std::pair<double, double> StepInput::range() const {
  return {std::min(0.0, level_), std::max(0.0, level_)};
}
std::pair<std::string_view, std::string_view> StepInput::range_keys() const {
  return {"constant_moment", "constant_moment"};
}

InputPtr ProportionalInput::read(const InputKeys& in) {
  return std::make_shared<ProportionalInput>(in.positive("stiffness", true));
}
std::pair<double, double> ProportionalInput::range() const {
  return k_ > 0.0 ? std::pair{-kInf, kInf} : std::pair{0.0, 0.0};
}
std::pair<std::string_view, std::string_view> ProportionalInput::range_keys() const {
  return {"stiffness", "stiffness"};
}

InputPtr RampInput::read(const InputKeys& in) {
  const double level = in.unit ? 1.0 : in.number("amplitude");
  return std::make_shared<RampInput>(level, in.positive("ramp_time"));
}
std::pair<double, double> RampInput::range() const {
  return level_ > 0.0 ? std::pair{0.0, kInf} : std::pair{-kInf, 0.0};
}
std::pair<std::string_view, std::string_view> RampInput::range_keys() const {
  return {"amplitude", "amplitude"};
}

Input::Sample SinusoidInput::at(double t) const {
  const double w = kTwoPi * f_;
  return {a_ * std::sin(kTwoPi * f_ * t), a_ * w * std::cos(w * t), -a_ * w * w * std::sin(w * t)};
}
double SinusoidInput::value(double t, double) const {
  return a_ * std::sin(kTwoPi * f_ * t);
}
double SinusoidInput::integral(double t) const {
  const double w = kTwoPi * f_;
  return w > 0.0 ? a_ * (1.0 - std::cos(w * t)) / w : 0.0;
}
std::pair<double, double> SinusoidInput::range() const {
  return {-std::abs(a_), std::abs(a_)};
}
std::pair<std::string_view, std::string_view> SinusoidInput::range_keys() const {
  return {"sine_amplitude", "sine_amplitude"};
}

Input::Sample SumInput::at(double t) const {
  const Sample a = a_->at(t), b = b_->at(t);
  return {a.value + b.value, a.rate + b.rate, a.acceleration + b.acceleration};
}
double SumInput::end_time() const {
  return std::max(a_->end_time(), b_->end_time());
}
std::pair<double, double> SumInput::range() const {
  const auto [alo, ahi] = a_->range();
  const auto [blo, bhi] = b_->range();
  return {alo + blo, ahi + bhi};  // bounds: the two need not reach their extremes together
}
std::pair<std::string_view, std::string_view> SumInput::range_keys() const {
  return b_->range_keys();
}

InputPtr ProfileFromFile::read(const InputKeys& in) {
  return std::make_shared<ProfileFromFile>(read_profile_input(in.p, in.key("profile")));
}
Input::Sample ProfileFromFile::at(double t) const {
  const ProfileInput::Sample s = profile_.at(t);
  return {s.value, s.rate, s.acceleration};
}
std::pair<std::string_view, std::string_view> ProfileFromFile::range_keys() const {
  return {"profile.file", "profile.file"};
}

}  // namespace rodend
