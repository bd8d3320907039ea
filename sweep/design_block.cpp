// The study's "design" block read and checked (docs/uncertainty.md): method, size, seed, the
// method's own keys and the factors with their distributions; then the points drawn.
#include <algorithm>
#include <cmath>
#include <exception>
#include <filesystem>
#include <limits>
#include <numbers>

#include "core/errors.hpp"
#include "core/json_text.hpp"
#include "sweep/design.hpp"
#include "sweep/results.hpp"

namespace rodend {
namespace {

std::string quoted_names(const std::vector<std::string_view>& names) {
  std::string out;
  for (const auto n : names) out += (out.empty() ? "\"" : ", \"") + std::string(n) + "\"";
  return out;
}

double finite_number(const Json& v, const std::string& where) {
  if (!v.is_number()) throw InputError(where, "expected a number, got " + json_type_name(v));
  const double x = v.get<double>();
  if (!std::isfinite(x)) throw InputError(where, "expected a finite number");
  return x;
}

double number_at(const Json& obj, const std::string& key, const std::string& where) {
  if (!obj.contains(key)) throw InputError(where + "." + key, "missing: a number");
  return finite_number(obj[key], where + "." + key);
}

long long integer_at(const Json& v, const std::string& where) {
  if (!v.is_number_integer() && !(v.is_number() && v.get<double>() == std::floor(v.get<double>()) &&
                                  std::abs(v.get<double>()) < 9e15))
    throw InputError(where, "expected an integer, got " + v.dump());
  // never clamped: two seeds (or sizes) above the range would read as one, and share case ids
  constexpr auto kMax = static_cast<std::uint64_t>(std::numeric_limits<long long>::max());
  if (v.is_number_unsigned() && v.get<std::uint64_t>() > kMax)
    throw InputError(
        where, "expected an integer from 0 to 9223372036854775807 (2^63 - 1), got " + v.dump());
  return v.is_number_unsigned() ? static_cast<long long>(v.get<std::uint64_t>())
                                : v.get<long long>();
}

template <class Info, class Pick>
const Info& choice(const std::vector<Info>& catalogue, Pick name_of, const Json& v,
                   const std::string& where) {
  std::vector<std::string_view> names;
  for (const Info& i : catalogue) names.push_back(name_of(i));
  if (v.is_string())
    for (const Info& i : catalogue)
      if (name_of(i) == v.get<std::string>()) return i;
  throw InputError(where, (v.is_string() ? "unknown '" + v.get<std::string>() + "'"
                                         : "expected a string, got " + json_type_name(v)) +
                              "; expected one of " + quoted_names(names));
}

void check_keys(const Json& obj, const std::vector<std::string_view>& allowed,
                const std::string& where) {
  for (auto it = obj.begin(); it != obj.end(); ++it)
    if (std::find(allowed.begin(), allowed.end(), it.key()) == allowed.end())
      throw InputError(where + "." + it.key(), "unknown key; expected " + quoted_names(allowed));
}

void read_discrete(Distribution& d, const Json& f, const std::string& where) {
  const Json* vals = f.contains("values") ? &f["values"] : nullptr;
  if (!vals || !vals->is_array() || vals->empty())
    throw InputError(where + ".values", "expected a non-empty array of numbers");
  std::vector<std::pair<double, double>> vw;
  for (std::size_t i = 0; i < vals->size(); ++i)
    vw.emplace_back(finite_number((*vals)[i], where + ".values[" + std::to_string(i) + "]"), 1.0);
  if (f.contains("weights")) {
    const Json& w = f["weights"];
    if (!w.is_array() || w.size() != vw.size())
      throw InputError(where + ".weights", "expected an array of " + std::to_string(vw.size()) +
                                               " weights, one per value");
    for (std::size_t i = 0; i < vw.size(); ++i) {
      const std::string wi = where + ".weights[" + std::to_string(i) + "]";
      vw[i].second = finite_number(w[i], wi);
      if (vw[i].second < 0.0) throw InputError(wi, "expected a weight >= 0");
    }
  }
  double total = 0.0;
  for (const auto& p : vw) total += p.second;
  if (!(total > 0.0)) throw InputError(where + ".weights", "expected weights with a positive sum");
  std::stable_sort(vw.begin(), vw.end());
  for (const auto& [v, w] : vw) {
    d.values.push_back(v);
    d.weights.push_back(w / total);
  }
}

/// A lognormal of this mean and std whose every drawn value is a positive finite number: the
/// log's std sqrt(ln(1 + (std/mean)^2)) positive and finite (std/mean within about 1e-154 to
/// 1e154) and the quantiles at the ends of the unit interval inside (0, inf).
void check_lognormal_spread(const Distribution& d, const std::string& where) {
  const double ratio = d.std / d.mean;
  bool ok = std::isfinite(std::log1p(ratio * ratio)) && std::log1p(ratio * ratio) > 0.0;
  try {
    ok = ok && std::isfinite(d.quantile(1.0)) && d.quantile(0.0) > 0.0;
  } catch (const std::exception&) {  // Boost.Math's overflow or domain error
    ok = false;
  }
  if (!ok)
    throw InputError(where + ".std",
                     "std / mean = " + shortest_decimal(ratio) +
                         " gives a lognormal whose drawn values are not all positive finite "
                         "numbers (its log's std sqrt(ln(1 + (std/mean)^2)) is 0 or infinite, or "
                         "its quantiles overflow); expected a ratio between about 1e-154 and 1e154 "
                         "and a mean far from the largest double");
}

/// The distribution's own checks: positive spreads, ordered bounds, a truncation that keeps
/// some probability.
void check_distribution(const Distribution& d, const std::string& where) {
  using K = DistributionKind;
  if ((d.kind == K::normal || d.kind == K::truncated_normal || d.kind == K::lognormal) &&
      !(d.std > 0.0))
    throw InputError(where + ".std", "expected a standard deviation > 0");
  if ((d.kind == K::uniform || d.kind == K::truncated_normal || d.kind == K::triangular) &&
      !(d.lower < d.upper))
    throw InputError(where + ".upper", "expected upper > lower (the bounds are inverted or equal)");
  if (d.kind == K::lognormal && !(d.mean > 0.0))
    throw InputError(where + ".mean", "expected a mean > 0 (a lognormal variable is positive)");
  if (d.kind == K::lognormal) check_lognormal_spread(d, where);
  if (d.kind == K::triangular && !(d.mode >= d.lower && d.mode <= d.upper))
    throw InputError(where + ".mode", "expected lower <= mode <= upper");
  // an interval far in a tail holds no probability in double precision: its moments are not
  // finite numbers
  if (d.kind == K::truncated_normal &&
      !(std::isfinite(d.moment_mean()) && d.moment_std() > 0.0 && std::isfinite(d.moment_std())))
    throw InputError(where,
                     "the truncation [lower, upper] lies where the normal of this mean and "
                     "std has no probability; expected bounds within its support");
}

Distribution read_distribution(const Json& f, const std::string& where) {
  const DistributionInfo& info = choice(
      distribution_catalogue(), [](const DistributionInfo& i) { return i.name; },
      f.contains("distribution") ? f["distribution"] : Json(), where + ".distribution");
  std::vector<std::string_view> allowed{"key", "distribution"};
  allowed.insert(allowed.end(), info.keys.begin(), info.keys.end());
  check_keys(f, allowed, where);
  Distribution d;
  d.kind = info.kind;
  if (d.kind == DistributionKind::discrete) {
    read_discrete(d, f, where);
    return d;
  }
  for (const std::string_view key : info.keys) {
    const double x = number_at(f, std::string(key), where);
    if (key == "mean") d.mean = x;
    if (key == "std") d.std = x;
    if (key == "lower") d.lower = x;
    if (key == "upper") d.upper = x;
    if (key == "mode") d.mode = x;
  }
  check_distribution(d, where);
  return d;
}

}  // namespace

void check_factor_key(const std::string& key, const std::string& key_where,
                      const std::string& context, const std::vector<DesignFactor>& before) {
  if (key == "scene" || key.rfind("design", 0) == 0 || key == "integrator.preset" ||
      key.find('.') == std::string::npos)
    throw InputError(key_where, context + "'" + key +
                                    "' cannot be sampled; expected a numeric "
                                    "key path such as parameters.contact.clearance");
  for (const DesignFactor& f : before)
    if (f.key == key) throw InputError(key_where, context + "'" + key + "' is sampled twice");
}

namespace {

std::vector<DesignFactor> read_factors(const Json& block) {
  if (!block.contains("factors") || !block["factors"].is_array() || block["factors"].empty())
    throw InputError("design.factors",
                     "expected a non-empty array of factors {\"key\": ..., "
                     "\"distribution\": ..., its parameters}");
  const Json& fs = block["factors"];
  if (fs.size() > kMaxDesignFactors)
    throw InputError("design.factors",
                     "more than " + std::to_string(kMaxDesignFactors) + " factors");
  std::vector<DesignFactor> out;
  for (std::size_t i = 0; i < fs.size(); ++i) {
    const std::string where = "design.factors[" + std::to_string(i) + "]";
    if (!fs[i].is_object())
      throw InputError(where, "expected an object, got " + json_type_name(fs[i]));
    if (!fs[i].contains("key") || !fs[i]["key"].is_string() ||
        fs[i]["key"].get<std::string>().empty())
      throw InputError(where + ".key",
                       "expected the key path it samples, such as "
                       "parameters.contact.clearance");
    const std::string key = fs[i]["key"].get<std::string>();
    check_factor_key(key, where + ".key", "", out);
    out.push_back({key, where, read_distribution(fs[i], where), where + ".key", ""});
  }
  return out;
}

/// Points per grid point, checked against the cases left (without overflowing).
std::size_t count_points(DesignMethod m, std::size_t n, std::size_t d, std::size_t max_points) {
  const DesignMethodInfo& info = design_method_info(m);
  const std::size_t per = info.per_factor * d + info.extra;
  if (n > max_points / per)
    throw InputError("design.size", "makes more than " + std::to_string(max_points) +
                                        " cases with the grid, the limit of a study (1e7); "
                                        "expected a smaller size");
  return n * per;
}

void read_method_keys(Design& d, const Json& block) {
  if (block.contains("levels")) {
    if (d.method != DesignMethod::morris)
      throw InputError("design.levels", "only a morris design has levels");
    const long long p = integer_at(block["levels"], "design.levels");
    if (p < 2 || p > kMaxMorrisLevels || p % 2 != 0)
      throw InputError("design.levels", "expected an even number of levels in [2, " +
                                            std::to_string(kMaxMorrisLevels) +
                                            "] (the "
                                            "step p/(2(p-1)) then lands on the grid)");
    d.levels = static_cast<int>(p);
  }
  if (block.contains("base")) {
    if (d.method != DesignMethod::saltelli)
      throw InputError("design.base", "only a saltelli design has a base");
    std::vector<DesignMethodInfo> bases;
    for (const DesignMethodInfo& m : design_method_catalogue())
      if (m.sample) bases.push_back(m);
    d.base =
        choice(
            bases, [](const DesignMethodInfo& i) { return i.name; }, block["base"], "design.base")
            .method;
  }
}

/// design.correlation.matrix: d x d numbers in [-1, 1], a unit diagonal, symmetric.
std::vector<double> read_matrix(const Json& c, std::size_t d) {
  const std::string where = "design.correlation.matrix";
  const Json m = c.contains("matrix") ? c["matrix"] : Json();
  const std::string shape = "expected " + std::to_string(d) + " rows of " + std::to_string(d) +
                            " numbers, one per factor in the order of design.factors";
  if (!m.is_array() || m.size() != d) throw InputError(where, shape);
  std::vector<double> a(d * d);
  for (std::size_t i = 0; i < d; ++i) {
    const std::string row = where + "[" + std::to_string(i) + "]";
    if (!m[i].is_array() || m[i].size() != d) throw InputError(row, shape);
    for (std::size_t j = 0; j < d; ++j) {
      const std::string at = row + "[" + std::to_string(j) + "]";
      a[i * d + j] = finite_number(m[i][j], at);
      if (i == j && a[i * d + j] != 1.0) throw InputError(at, "expected 1 on the diagonal");
      if (std::abs(a[i * d + j]) > 1.0) throw InputError(at, "expected a correlation in [-1, 1]");
    }
  }
  for (std::size_t i = 0; i < d; ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (std::abs(a[i * d + j] - a[j * d + i]) > 1e-12)
        throw InputError(where + "[" + std::to_string(i) + "][" + std::to_string(j) + "]",
                         "expected a symmetric matrix: it differs from [" + std::to_string(j) +
                             "][" + std::to_string(i) + "]");
  return a;
}

/// design.correlation {"kind", "matrix"}: the factors' dependence as a normal copula, for the
/// methods that draw a sample.
void read_correlation(Design& d, const Json& block) {
  if (!block.contains("correlation")) return;
  std::vector<std::string_view> accept;
  for (const DesignMethodInfo& m : design_method_catalogue())
    if (m.sample) accept.push_back(m.name);
  if (!design_method_info(d.method).sample)
    throw InputError("design.correlation",
                     "a " + std::string(to_string(d.method)) +
                         " design needs independent factors (its estimator moves one factor "
                         "at a time); correlated factors: expected method " +
                         quoted_names(accept) + ", analysed by the sampling-based measures");
  const Json& c = block["correlation"];
  if (!c.is_object())
    throw InputError(
        "design.correlation",
        "expected {\"kind\": \"spearman\" or \"pearson\", \"matrix\": [[1, r], [r, 1]]}");
  check_keys(c, {"kind", "matrix"}, "design.correlation");
  d.correlation_kind = choice(
                           correlation_kinds(), [](const auto& k) { return k.second; },
                           c.contains("kind") ? c["kind"] : Json(), "design.correlation.kind")
                           .first;
  const std::size_t n = d.factors.size();
  d.correlation = read_matrix(c, n);
  d.copula = d.correlation;
  if (d.correlation_kind == CorrelationKind::spearman)
    for (double& r : d.copula) r = r == 1.0 ? 1.0 : 2.0 * std::sin(std::numbers::pi * r / 6.0);
  if (cholesky(d.copula, n).empty())
    throw InputError("design.correlation.matrix",
                     "not positive definite: no set of factors has these correlations (a "
                     "valid correlation matrix has only positive eigenvalues)");
}

/// The method's own block of a design without distributions (file): design.file, resolved from
/// `folder`, and nothing else; the method's draw reads the points.
void read_points_block(Design& d, const Json& block, const std::filesystem::path& folder,
                       std::size_t max_points) {
  check_keys(block, {"method", "file"}, "design");
  if (!block.contains("file") || !block["file"].is_string() ||
      block["file"].get<std::string>().empty())
    throw InputError("design.file",
                     "expected the path of a CSV file of points (a header row of factor key "
                     "paths, then one row per case), relative to the study file's folder");
  d.file = block["file"].get<std::string>();
  const std::filesystem::path given(d.file);
  d.resolved = given.is_absolute() || folder.empty() ? given : folder / given;
  design_method_info(d.method).draw(d);
  if (d.size > max_points)
    throw InputError("design.file", d.file + " has " + std::to_string(d.size) +
                                        " rows, which make more than " +
                                        std::to_string(max_points) +
                                        " cases with the grid, the limit of a study (1e7)");
}

/// The drawn points mapped through the factors' quantile functions (after the copula).
void map_points(Design& d) {
  const std::size_t dims = d.factors.size();
  if (!d.copula.empty()) apply_normal_copula(d.unit, cholesky(d.copula, dims), dims);
  const std::size_t points = d.unit.size() / dims;
  d.values.resize(points * dims);
  for (std::size_t p = 0; p < points; ++p)
    for (std::size_t j = 0; j < dims; ++j)
      d.values[p * dims + j] = d.factors[j].distribution.quantile(d.unit[p * dims + j]);
}

}  // namespace

Design parse_design(const Json& block, std::size_t max_points,
                    const std::filesystem::path& folder) {
  if (!block.is_object())
    throw InputError("design", "expected an object {\"method\", \"size\", \"seed\", \"factors\"}");
  check_keys(block, design_keys(), "design");
  Design d;
  d.method = choice(
                 design_method_catalogue(), [](const DesignMethodInfo& i) { return i.name; },
                 block.contains("method") ? block["method"] : Json(), "design.method")
                 .method;
  if (!design_method_info(d.method).distributions) {
    read_points_block(d, block, folder, max_points);
    return d;
  }
  if (block.contains("file"))
    throw InputError("design.file", "only a file design reads a file of points");
  if (!block.contains("size")) throw InputError("design.size", "missing: the number of points");
  const long long n = integer_at(block["size"], "design.size");
  if (n < 1) throw InputError("design.size", "expected a size >= 1, got " + std::to_string(n));
  if (!block.contains("seed"))
    throw InputError("design.seed",
                     "missing: an integer seed (the same seed draws the same points)");
  const long long seed = integer_at(block["seed"], "design.seed");
  if (seed < 0) throw InputError("design.seed", "expected an integer seed >= 0");
  read_method_keys(d, block);
  d.factors = read_factors(block);
  read_correlation(d, block);
  d.size = static_cast<std::size_t>(n);
  d.seed = static_cast<std::uint64_t>(seed);
  count_points(d.method, d.size, d.factors.size(), max_points);  // throws above the limit
  if (d.method == DesignMethod::morris)
    for (const DesignFactor& f : d.factors)
      if (!distribution_info(f.distribution.kind).bounded)
        throw InputError(f.where + ".distribution",
                         "a morris design needs bounded distributions (its grid reaches both "
                         "ends): expected uniform, truncated-normal, triangular or discrete");
  design_method_info(d.method).draw(d);
  map_points(d);
  return d;
}

}  // namespace rodend
