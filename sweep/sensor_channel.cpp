#include "sweep/sensor_channel.hpp"

#include <cmath>
#include <numbers>

namespace rodend {

NormalStream::NormalStream(std::uint64_t seed) {
  for (std::uint64_t& s : s_) {  // splitmix64
    std::uint64_t z = (seed += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    s = z ^ (z >> 31);
  }
}

std::uint64_t NormalStream::bits() {
  auto rotl = [](std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); };
  const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
  const std::uint64_t t = s_[1] << 17;
  s_[2] ^= s_[0];
  s_[3] ^= s_[1];
  s_[1] ^= s_[2];
  s_[0] ^= s_[3];
  s_[2] ^= t;
  s_[3] = rotl(s_[3], 45);
  return result;
}

double NormalStream::next() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  // two uniforms in (0, 1]: the top 53 bits, plus one ulp so that log never sees 0
  const double u1 = (static_cast<double>(bits() >> 11) + 1.0) * 0x1.0p-53;
  const double u2 = static_cast<double>(bits() >> 11) * 0x1.0p-53;
  const double r = std::sqrt(-2.0 * std::log(u1)), a = 2.0 * std::numbers::pi * u2;
  spare_ = r * std::sin(a);
  has_spare_ = true;
  return r * std::cos(a);
}

LowPass::LowPass(int order, double cutoff_hz)
    : order_(order), w_(2.0 * std::numbers::pi * cutoff_hz) {}

void LowPass::reset(double u) {
  y_ = u;
  dy_ = 0.0;
}

void LowPass::advance(double tau, double u0, double slope) {
  if (order_ == 0) {
    y_ = u0 + slope * tau;
    return;
  }
  if (order_ == 1) {
    // y' = w (u - y): y = u0 - slope/w + slope tau + (y0 - u0 + slope/w) exp(-w tau)
    const double lag = slope / w_;
    y_ = u0 - lag + slope * tau + (y_ - u0 + lag) * std::exp(-w_ * tau);
    return;
  }
  // y'' + 2 z w y' + w^2 y = w^2 u, z = 1/sqrt(2): the particular solution for the ramp is
  // u - 2 z slope / w (rate: slope); the rest, e, is the free oscillator's, advanced exactly
  const double z = std::numbers::sqrt2 / 2.0, sigma = z * w_, wd = w_ * z;  // sqrt(1 - z^2) = z
  const double offset = u0 - 2.0 * z * slope / w_;
  const double e0 = y_ - offset, de0 = dy_ - slope;
  const double decay = std::exp(-sigma * tau), c = std::cos(wd * tau), s = std::sin(wd * tau);
  const double e = decay * (e0 * c + (de0 + sigma * e0) / wd * s);
  const double de = decay * (de0 * c - (w_ * w_ * e0 + sigma * de0) / wd * s);
  y_ = offset + slope * tau + e;
  dy_ = slope + de;
}

SensorChannel::SensorChannel(const SensorSpec& spec, double noise_scale, long long seed,
                             long design_sample)
    : spec_(spec),
      signal_(*signal_by_name(spec.signal)),
      noise_(spec.noise_std * noise_scale),
      filter_(spec.filter_order, spec.cutoff),
      noise_stream_(sensor_seed(seed, spec.name, design_sample)) {}

void SensorChannel::sample(double t) {
  double y = filter_.output() + spec_.bias + noise_ * noise_stream_.next();
  if (spec_.quantisation > 0.0) y = spec_.quantisation * std::nearbyint(y / spec_.quantisation);
  times_.push_back(t);
  values_.push_back(y);
  ++next_;
}

void SensorChannel::start(const SignalFrame& f) {
  t_ = f.get(SignalId::time);
  u_ = f.get(signal_, spec_.component);
  filter_.reset(u_);
  next_ = static_cast<long long>(std::ceil(t_ * spec_.rate - 1e-9));
  if (static_cast<double>(next_) / spec_.rate <= t_) sample(t_);
  started_ = true;
}

void SensorChannel::advance(const SignalFrame& f) {
  if (!started_) return start(f);
  const double t = f.get(SignalId::time), u = f.get(signal_, spec_.component);
  if (!(t > t_)) return;
  const double slope = (u - u_) / (t - t_);
  double tf = t_;  // the filter's time
  for (double tk = static_cast<double>(next_) / spec_.rate; tk <= t;
       tk = static_cast<double>(next_) / spec_.rate) {
    filter_.advance(tk - tf, u_ + slope * (tf - t_), slope);
    tf = tk;
    sample(tk);
  }
  filter_.advance(t - tf, u_ + slope * (tf - t_), slope);
  t_ = t;
  u_ = u;
}

}  // namespace rodend
