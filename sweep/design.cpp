#include "sweep/design.hpp"

#include <algorithm>
#include <boost/math/distributions/lognormal.hpp>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/triangular.hpp>
#include <boost/random/sobol.hpp>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <sstream>

#include "core/errors.hpp"
#include "core/json_text.hpp"
#include "sweep/results.hpp"

namespace rodend {
const std::vector<DesignMethodInfo>& design_method_catalogue() {
  static const std::vector<DesignMethodInfo> k{
#define RODEND_CHOICE(id, name, doc, draw, distributions, sample, per_factor, extra, iid) \
  {DesignMethod::id, name, draw, distributions, sample, per_factor, extra, iid, doc},
#include "sweep/design_methods.def"
#undef RODEND_CHOICE
  };
  return k;
}

const std::vector<DistributionInfo>& distribution_catalogue() {
  static const std::vector<DistributionInfo> k{
#define RODEND_CHOICE(id, name, doc, keys, bounded) \
  {DistributionKind::id, name, std::vector<std::string_view> keys, bounded, doc},
#include "sweep/distributions.def"
#undef RODEND_CHOICE
  };
  return k;
}

const std::vector<std::string_view>& design_keys() {
  static const std::vector<std::string_view> k{"method", "size",        "seed",    "levels",
                                               "base",   "correlation", "factors", "file"};
  return k;
}

const std::vector<std::pair<CorrelationKind, std::string_view>>& correlation_kinds() {
  static const std::vector<std::pair<CorrelationKind, std::string_view>> k{
      {CorrelationKind::spearman, "spearman"}, {CorrelationKind::pearson, "pearson"}};
  return k;
}

const DistributionInfo& distribution_info(DistributionKind k) {
  for (const auto& i : distribution_catalogue())
    if (i.kind == k) return i;
  return distribution_catalogue().front();
}

const DesignMethodInfo& design_method_info(DesignMethod m) {
  for (const auto& i : design_method_catalogue())
    if (i.method == m) return i;
  return design_method_catalogue().front();
}

namespace {

/// u kept inside (0, 1) where the support is unbounded (the quantile there is infinite).
double inside(double u) {
  constexpr double tiny = 0x1p-60;
  return std::clamp(u, tiny, 1.0 - 0x1p-53);
}

/// The lognormal's log-space parameters from the variable's mean m and std s.
std::pair<double, double> log_parameters(double m, double s) {
  const double var_log = std::log1p((s / m) * (s / m));
  return {std::log(m) - 0.5 * var_log, std::sqrt(var_log)};
}

/// Standard normal probabilities of the truncation bounds and the parent standardised.
struct Truncation {
  double alpha, beta, pa, pb, mass;
};
Truncation truncation(const Distribution& d) {
  const boost::math::normal n01;
  Truncation t{};
  t.alpha = (d.lower - d.mean) / d.std;
  t.beta = (d.upper - d.mean) / d.std;
  t.pa = boost::math::cdf(n01, t.alpha);
  t.pb = boost::math::cdf(n01, t.beta);
  t.mass = t.alpha > 0.0 ? boost::math::cdf(boost::math::complement(n01, t.alpha)) -
                               boost::math::cdf(boost::math::complement(n01, t.beta))
                         : t.pb - t.pa;
  return t;
}

double truncated_quantile(const Distribution& d, double u) {
  const boost::math::normal n01;
  const Truncation t = truncation(d);
  double z;
  if (t.alpha > 0.0) {  // the upper tail: work with complements, which keep their digits there
    const double qa = boost::math::cdf(boost::math::complement(n01, t.alpha));
    z = boost::math::quantile(boost::math::complement(n01, inside(qa - u * t.mass)));
  } else {
    z = boost::math::quantile(n01, inside(t.pa + u * t.mass));
  }
  return std::clamp(d.mean + d.std * z, d.lower, d.upper);
}

}  // namespace

double Distribution::quantile(double u) const {
  switch (kind) {
    case DistributionKind::uniform:
      return lower + u * (upper - lower);
    case DistributionKind::normal:
      return boost::math::quantile(boost::math::normal(mean, std), inside(u));
    case DistributionKind::truncated_normal:
      return truncated_quantile(*this, u);
    case DistributionKind::lognormal: {
      const auto [mu, sigma] = log_parameters(mean, std);
      return boost::math::quantile(boost::math::lognormal(mu, sigma), inside(u));
    }
    case DistributionKind::triangular:
      return boost::math::quantile(boost::math::triangular_distribution(lower, mode, upper),
                                   std::clamp(u, 0.0, 1.0));
    case DistributionKind::discrete: {
      double cumulative = 0.0;
      for (std::size_t i = 0; i < values.size(); ++i) {
        cumulative += weights[i];
        if (u <= cumulative) return values[i];
      }
      return values.back();
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double Distribution::moment_mean() const {
  switch (kind) {
    case DistributionKind::uniform:
      return 0.5 * (lower + upper);
    case DistributionKind::normal:
    case DistributionKind::lognormal:
      return mean;
    case DistributionKind::truncated_normal: {
      const Truncation t = truncation(*this);
      const boost::math::normal n01;
      return mean + std * (boost::math::pdf(n01, t.alpha) - boost::math::pdf(n01, t.beta)) / t.mass;
    }
    case DistributionKind::triangular:
      return (lower + mode + upper) / 3.0;
    case DistributionKind::discrete:
      return std::inner_product(values.begin(), values.end(), weights.begin(), 0.0);
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double Distribution::moment_std() const {
  switch (kind) {
    case DistributionKind::uniform:
      return (upper - lower) / std::sqrt(12.0);
    case DistributionKind::normal:
    case DistributionKind::lognormal:
      return std;
    case DistributionKind::truncated_normal: {
      const Truncation t = truncation(*this);
      const boost::math::normal n01;
      const double fa = boost::math::pdf(n01, t.alpha), fb = boost::math::pdf(n01, t.beta);
      const double a = std::isfinite(t.alpha) ? t.alpha * fa : 0.0;
      const double b = std::isfinite(t.beta) ? t.beta * fb : 0.0;
      const double r = (fa - fb) / t.mass;
      return std * std::sqrt(std::max(0.0, 1.0 + (a - b) / t.mass - r * r));
    }
    case DistributionKind::triangular: {
      const double a = lower, b = upper, c = mode;
      return std::sqrt((a * a + b * b + c * c - a * b - a * c - b * c) / 18.0);
    }
    case DistributionKind::discrete: {
      const double m = moment_mean();
      double v = 0.0;
      for (std::size_t i = 0; i < values.size(); ++i)
        v += weights[i] * (values[i] - m) * (values[i] - m);
      return std::sqrt(v);
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

Json Distribution::to_json() const {
  Json j = {{"distribution", std::string(to_string(kind))}};
  // a truncated normal's study keys mean and std are its parent normal's: recorded under
  // names that say so, mean and std below being always the distribution's own moments
  const bool parent = kind == DistributionKind::truncated_normal;
  for (const std::string_view key : distribution_info(kind).keys) {
    const std::string k(key);
    if (k == "mean") j[parent ? "parent_mean" : k] = mean;
    if (k == "std") j[parent ? "parent_std" : k] = std;
    if (k == "lower") j[k] = lower;
    if (k == "upper") j[k] = upper;
    if (k == "mode") j[k] = mode;
    if (k == "values") j[k] = values;
    if (k == "weights") j[k] = weights;
  }
  if (!j.contains("mean")) j["mean"] = moment_mean();
  if (!j.contains("std")) j["std"] = moment_std();
  return j;
}

// --- points in the unit hypercube ----------------------------------------------------------

namespace {

/// A double in (0, 1) from 53 random bits: the same on every machine (std::mt19937_64's output
/// is fixed by the standard; its distributions are not, so none is used).
double unit_double(std::mt19937_64& rng) {
  return (static_cast<double>(rng() >> 11) + 0.5) * 0x1p-53;
}

/// An integer uniform in [0, n), by rejection (no modulo bias), machine-independent.
std::uint64_t below(std::mt19937_64& rng, std::uint64_t n) {
  const std::uint64_t limit =
      std::numeric_limits<std::uint64_t>::max() - std::numeric_limits<std::uint64_t>::max() % n;
  std::uint64_t x;
  do x = rng();
  while (x >= limit);
  return x % n;
}

/// A permutation of 0..n-1 (Fisher-Yates).
std::vector<std::size_t> permutation(std::mt19937_64& rng, std::size_t n) {
  std::vector<std::size_t> p(n);
  std::iota(p.begin(), p.end(), std::size_t{0});
  for (std::size_t i = n; i > 1; --i) std::swap(p[i - 1], p[below(rng, i)]);
  return p;
}

std::vector<double> latin_hypercube(std::size_t n, std::size_t dims, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<double> u(n * dims);
  for (std::size_t j = 0; j < dims; ++j) {
    const std::vector<std::size_t> stratum = permutation(rng, n);
    for (std::size_t i = 0; i < n; ++i)
      u[i * dims + j] =
          (static_cast<double>(stratum[i]) + unit_double(rng)) / static_cast<double>(n);
  }
  return u;
}

/// Sobol' points (Boost.Random, Joe-Kuo directions) with a random shift modulo 1 per dimension
/// drawn from the seed (Cranley-Patterson rotation: Boost offers no scrambling; the shift keeps
/// the low discrepancy, makes the seed matter and keeps every point off the cube's faces).
std::vector<double> shifted_sobol(std::size_t n, std::size_t dims, std::uint64_t seed) {
  boost::random::sobol sequence(dims);
  std::mt19937_64 rng(seed);
  std::vector<double> shift(dims);
  for (double& s : shift) s = unit_double(rng);
  std::vector<double> u(n * dims);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < dims; ++j) {
      // Boost's sequence starts after the origin, the sequence's point 0: put it back, so that
      // the first 2^k points form the net that gives Sobol' points their balance
      const double point = i == 0 ? 0.0 : std::ldexp(static_cast<double>(sequence()), -64);
      double x = point + shift[j];
      if (x >= 1.0) x -= 1.0;
      u[i * dims + j] = std::clamp(x, 0x1p-60, 1.0 - 0x1p-53);
    }
  return u;
}

}  // namespace

void draw_monte_carlo(Design& d) {
  std::mt19937_64 rng(d.seed);
  d.unit.resize(d.size * d.dims());
  for (double& x : d.unit) x = unit_double(rng);
}
void draw_latin_hypercube(Design& d) {
  d.unit = latin_hypercube(d.size, d.dims(), d.seed);
}
void draw_sobol(Design& d) {
  d.unit = shifted_sobol(d.size, d.dims(), d.seed);
}
void draw_saltelli(Design& d) {
  d.unit = saltelli_unit_points(d.base, d.size, d.dims(), d.seed);
}
void draw_morris(Design& d) {
  d.unit = morris_unit_points(d.size, d.dims(), d.levels, d.seed);
}

std::vector<double> unit_points(DesignMethod method, std::size_t n, std::size_t dims,
                                std::uint64_t seed) {
  Design d;  // a design of `dims` factors of no matter which distribution, drawn by `method`
  d.method = method;
  d.size = n;
  d.seed = seed;
  d.factors.resize(dims);
  design_method_info(method).draw(d);
  return d.unit;
}

/// Saltelli's blocks from a base of N x 2d points: A (first d columns), B (last d), then for
/// each factor i, A with column i taken from B: the order of OpenTURNS's
/// SobolIndicesExperiment, which its SaltelliSensitivityAlgorithm reads.
std::vector<double> saltelli_unit_points(DesignMethod base, std::size_t n, std::size_t d,
                                         std::uint64_t seed) {
  const std::vector<double> ab = unit_points(base, n, 2 * d, seed);
  std::vector<double> u((d + 2) * n * d);
  for (std::size_t block = 0; block < d + 2; ++block)
    for (std::size_t r = 0; r < n; ++r)
      for (std::size_t j = 0; j < d; ++j) {
        const bool from_b = block == 1 || (block >= 2 && block - 2 == j);
        u[(block * n + r) * d + j] = ab[r * 2 * d + j + (from_b ? d : 0)];
      }
  return u;
}

/// Morris's trajectories (Morris 1991, in the form of Campolongo et al. 2007): a base point on
/// the p-level grid {0, 1/(p-1), ..., 1}, then each factor in a random order moved once by
/// delta = p / (2 (p - 1)), i.e. p/2 levels, up where that stays on the grid, else down.
std::vector<double> morris_unit_points(std::size_t r, std::size_t d, int p, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const auto levels = static_cast<std::uint64_t>(p);
  const std::uint64_t jump = levels / 2;
  std::vector<double> u;
  u.reserve(r * (d + 1) * d);
  std::vector<std::uint64_t> level(d);
  for (std::size_t t = 0; t < r; ++t) {
    for (std::uint64_t& l : level) l = below(rng, levels);
    auto push = [&] {
      for (std::uint64_t l : level)
        u.push_back(static_cast<double>(l) / static_cast<double>(p - 1));
    };
    push();
    for (std::size_t j : permutation(rng, d)) {
      level[j] = level[j] + jump <= levels - 1 ? level[j] + jump : level[j] - jump;
      push();
    }
  }
  return u;
}

std::vector<double> cholesky(const std::vector<double>& a, std::size_t d) {
  std::vector<double> l(d * d, 0.0);
  double largest = 0.0;
  for (std::size_t i = 0; i < d; ++i) largest = std::max(largest, std::abs(a[i * d + i]));
  for (std::size_t j = 0; j < d; ++j) {
    double pivot = a[j * d + j];
    for (std::size_t k = 0; k < j; ++k) pivot -= l[j * d + k] * l[j * d + k];
    if (!(pivot > 1e-12 * largest)) return {};
    l[j * d + j] = std::sqrt(pivot);
    for (std::size_t i = j + 1; i < d; ++i) {
      double s = a[i * d + j];
      for (std::size_t k = 0; k < j; ++k) s -= l[i * d + k] * l[j * d + k];
      l[i * d + j] = s / l[j * d + j];
    }
  }
  return l;
}

void apply_normal_copula(std::vector<double>& unit, const std::vector<double>& lower,
                         std::size_t d) {
  const boost::math::normal n01;
  std::vector<double> z(d);
  for (std::size_t p = 0; p * d < unit.size(); ++p) {
    for (std::size_t j = 0; j < d; ++j) z[j] = boost::math::quantile(n01, inside(unit[p * d + j]));
    for (std::size_t i = 0; i < d; ++i) {
      double s = 0.0;
      for (std::size_t k = 0; k <= i; ++k) s += lower[i * d + k] * z[k];
      unit[p * d + i] = boost::math::cdf(n01, s);
    }
  }
}

Json Design::to_json(const std::vector<std::string>& units) const {
  const bool drawn = design_method_info(method).distributions;
  Json j = {{"method", std::string(to_string(method))}, {"size", size}, {"points", points()}};
  if (drawn) j["seed"] = seed;
  if (!drawn)
    j.update({{"file", file},
              {"resolved_path", resolved.string()},
              {"content_fnv1a64", content_fnv1a64}});
  if (method == DesignMethod::saltelli) j["base"] = std::string(to_string(base));
  Json fs = Json::array();
  for (std::size_t i = 0; i < factors.size(); ++i) {
    Json f = {{"key", factors[i].key}, {"units", i < units.size() ? units[i] : ""}};
    if (drawn) f.update(factors[i].distribution.to_json());
    fs.push_back(std::move(f));
  }
  j["factors"] = std::move(fs);
  if (!copula.empty()) {
    Json given = Json::array(), normal = Json::array();
    for (std::size_t i = 0; i < dims(); ++i) {
      const auto row = static_cast<std::ptrdiff_t>(i * dims());
      const auto end = row + static_cast<std::ptrdiff_t>(dims());
      given.push_back(std::vector<double>(correlation.begin() + row, correlation.begin() + end));
      normal.push_back(std::vector<double>(copula.begin() + row, copula.begin() + end));
    }
    for (const auto& [k, name] : correlation_kinds())
      if (k == correlation_kind)
        j["correlation"] = {
            {"kind", std::string(name)}, {"matrix", given}, {"normal_copula", normal}};
  }
  if (method == DesignMethod::morris) {
    j["levels"] = levels;
    j["delta"] = delta();
    Json rows = Json::array();
    for (std::size_t p = 0; p < points(); ++p)
      rows.push_back(
          std::vector<double>(unit.begin() + static_cast<std::ptrdiff_t>(p * dims()),
                              unit.begin() + static_cast<std::ptrdiff_t>((p + 1) * dims())));
    j["unit_points"] = std::move(rows);
  }
  return j;
}

std::string Design::statistics() const {
  std::ostringstream o;
  const bool drawn = design_method_info(method).distributions;
  o << "design " << to_string(method);
  if (method == DesignMethod::saltelli) o << " (base " << to_string(base) << ")";
  if (!drawn) o << " " << file;
  o << ": size " << size;
  if (drawn) o << ", seed " << seed;
  o << ", " << points() << " points per grid point\n";
  o << "factor\tdistribution\tmean\tstd\tpoints_mean\tpoints_std\tpoints_min\tpoints_max\n";
  const std::size_t n = points(), d = dims();
  for (std::size_t j = 0; j < d; ++j) {
    double sum = 0.0, lo = values[j], hi = values[j];
    for (std::size_t p = 0; p < n; ++p) {
      const double x = values[p * d + j];
      sum += x;
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
    const double m = sum / static_cast<double>(n);
    double ss = 0.0;
    for (std::size_t p = 0; p < n; ++p) ss += (values[p * d + j] - m) * (values[p * d + j] - m);
    const double s = n > 1 ? std::sqrt(ss / static_cast<double>(n - 1)) : 0.0;
    const Distribution& dist = factors[j].distribution;
    if (drawn)
      o << factors[j].key << "\t" << to_string(dist.kind) << "\t"
        << shortest_decimal(dist.moment_mean()) << "\t" << shortest_decimal(dist.moment_std());
    else
      o << factors[j].key << "\t-\t-\t-";
    o << "\t" << shortest_decimal(m) << "\t" << shortest_decimal(s) << "\t" << shortest_decimal(lo)
      << "\t" << shortest_decimal(hi) << "\n";
  }
  return o.str();
}

}  // namespace rodend
