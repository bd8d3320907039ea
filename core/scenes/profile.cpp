#include "core/scenes/profile.hpp"

#include <algorithm>
#include <cmath>

#include "core/scenes/parts.hpp"

namespace rodend {
namespace {

/// The cubic Hermite interpolant on [t0, t0 + h] through (y0, slope d0) and (y1, slope d1).
ProfileInput::Sample hermite(double s, double h, double y0, double y1, double d0, double d1) {
  const double s2 = s * s, s3 = s2 * s;
  const double value = (2 * s3 - 3 * s2 + 1) * y0 + (s3 - 2 * s2 + s) * h * d0 +
                       (-2 * s3 + 3 * s2) * y1 + (s3 - s2) * h * d1;
  const double rate =
      ((6 * s2 - 6 * s) * (y0 - y1) + (3 * s2 - 4 * s + 1) * h * d0 + (3 * s2 - 2 * s) * h * d1) /
      h;
  const double accel =
      ((12 * s - 6) * (y0 - y1) + (6 * s - 4) * h * d0 + (6 * s - 2) * h * d1) / (h * h);
  return {value, rate, accel};
}

}  // namespace

void compute_pchip_slopes(ProfileData& d) {
  const std::size_t n = d.time.size();
  d.slope.assign(n, 0.0);
  auto secant = [&](std::size_t k) {
    return (d.value[k + 1] - d.value[k]) / (d.time[k + 1] - d.time[k]);
  };
  d.slope[0] = secant(0);  // one-sided at the ends, as Boost's pchip by default
  d.slope[n - 1] = secant(n - 2);
  for (std::size_t k = 1; k + 1 < n; ++k) {
    const double hm = d.time[k] - d.time[k - 1], hk = d.time[k + 1] - d.time[k];
    const double dm = secant(k - 1), dk = secant(k);
    if (dm == 0.0 || dk == 0.0 || (dm > 0.0) != (dk > 0.0)) continue;  // an extremum: flat
    const double w1 = 2 * hk + hm, w2 = hk + 2 * hm;
    d.slope[k] = (w1 + w2) / (w1 / dm + w2 / dk);
  }
}

ProfileInput::Sample ProfileInput::at(double t) const {
  const ProfileData& d = *data;
  if (t < d.start()) return {d.value.front(), 0.0, 0.0};
  if (t >= d.end()) {
    if (past_end != PastEnd::repeat || !(d.end() > d.start())) return {d.value.back(), 0.0, 0.0};
    t = d.start() + std::fmod(t - d.start(), d.end() - d.start());
  }
  // the interval [time[k], time[k + 1]) holding t
  const auto it = std::upper_bound(d.time.begin(), d.time.end(), t);
  const auto k = static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - d.time.begin(), 1) - 1);
  const double h = d.time[k + 1] - d.time[k], s = (t - d.time[k]) / h;
  if (interpolation == Interpolation::linear) {
    const double rate = (d.value[k + 1] - d.value[k]) / h;
    return {d.value[k] + rate * (t - d.time[k]), rate, 0.0};
  }
  return hermite(s, h, d.value[k], d.value[k + 1], d.slope[k], d.slope[k + 1]);
}

std::pair<double, double> ProfileInput::range() const {
  const auto [lo, hi] = std::minmax_element(data->value.begin(), data->value.end());
  return {*lo, *hi};
}

ProfileInput read_profile_input(const ParameterSet& p, const std::string& prefix) {
  ProfileInput in;
  in.interpolation = read_choice<ProfileInterpolation>(p, prefix + ".interpolation");
  in.past_end = read_choice<ProfilePastEnd>(p, prefix + ".past_end");
  in.data = p.attached(prefix + ".file");
  if (!in.data)
    throw InputError(prefix + ".file",
                     p.text(prefix + ".file").empty()
                         ? "expected the path of a CSV or HDF5 file holding the profile"
                         : "the profile file was not loaded (profiles are read by a study: "
                           "`rodend run`, rodend.run in Python)");
  return in;
}

}  // namespace rodend
