// Sampled designs (issue 30; sweep/design.hpp): the distributions' quantile functions against
// closed forms, the structure of each method's points, and a design as the last axis of a study
// (same seed -> same points and ids; another seed -> other points).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <numbers>
#include <set>

#include "fixture.hpp"
#include "sweep/design.hpp"
#include "sweep/study.hpp"

using namespace rodend;

namespace {

Json doc_with(const Json& design) {
  Json doc = Json::parse(R"({"name": "d", "scene": "gravity-drop",
                             "time": {"end": 0.01, "sample_interval": 1e-3}})");
  doc["design"] = design;
  return doc;
}

Json uniform_clearance() {
  return Json::parse(R"({"key": "parameters.contact.clearance", "distribution": "uniform",
                         "lower": 1e-4, "upper": 5e-4})");
}

Json two_factor_design(const std::string& method, int size, int seed) {
  return {{"method", method},
          {"size", size},
          {"seed", seed},
          {"factors",
           {uniform_clearance(),
            Json::parse(R"({"key": "parameters.contact.restitution", "distribution":
                            "triangular", "lower": 0.3, "mode": 0.6, "upper": 0.9})")}}};
}

Distribution make(DistributionKind k, double a, double b, double c = 0.0, double d = 0.0) {
  Distribution x;
  x.kind = k;
  if (k == DistributionKind::uniform) x.lower = a, x.upper = b;
  if (k == DistributionKind::normal || k == DistributionKind::lognormal) x.mean = a, x.std = b;
  if (k == DistributionKind::truncated_normal) x.mean = a, x.std = b, x.lower = c, x.upper = d;
  if (k == DistributionKind::triangular) x.lower = a, x.mode = b, x.upper = c;
  return x;
}

}  // namespace

TEST_CASE("quantile functions match their closed forms", "[design]") {
  using K = DistributionKind;
  CHECK(make(K::uniform, 2.0, 6.0).quantile(0.25) == Approx(3.0).epsilon(1e-15));
  // the normal's 97.5 % point is mean + 1.959963985 std (any table)
  CHECK(make(K::normal, 1.0, 0.5).quantile(0.975) == Approx(1.0 + 0.5 * 1.959963985).epsilon(1e-9));
  // lognormal of mean m, std s: median exp(mu) = m / sqrt(1 + (s/m)^2)
  CHECK(make(K::lognormal, 2.0, 1.0).quantile(0.5) == Approx(2.0 / std::sqrt(1.25)).epsilon(1e-12));
  // triangular: F(x) = (x-a)^2 / ((b-a)(c-a)) below the mode -> x = a + sqrt(u (b-a)(c-a))
  CHECK(make(K::triangular, 0.0, 1.0, 4.0).quantile(0.1) == Approx(std::sqrt(0.4)).epsilon(1e-12));
  // a truncated normal symmetric about its mean has it as median; its ends are the bounds
  const Distribution t = make(K::truncated_normal, 3.0, 1.0, 2.0, 4.0);
  CHECK(t.quantile(0.5) == Approx(3.0).epsilon(1e-12));
  CHECK(t.quantile(0.0) == Approx(2.0).epsilon(1e-12));
  CHECK(t.quantile(1.0) == Approx(4.0).epsilon(1e-12));
  // its variance, closed form: 1 - 2 phi(1) / (2 Phi(1) - 1) for [-1, 1] (std 1)
  const double phi1 = std::exp(-0.5) / std::sqrt(2.0 * M_PI), mass = std::erf(1.0 / std::sqrt(2.0));
  CHECK(t.moment_std() == Approx(std::sqrt(1.0 - 2.0 * phi1 / mass)).epsilon(1e-12));
  Distribution d;
  d.kind = K::discrete;
  d.values = {1.0, 2.0, 5.0};
  d.weights = {0.2, 0.5, 0.3};
  CHECK(d.quantile(0.1) == 1.0);
  CHECK(d.quantile(0.6) == 2.0);
  CHECK(d.quantile(0.71) == 5.0);
  CHECK(d.moment_mean() == Approx(0.2 + 1.0 + 1.5));
}

TEST_CASE("a Latin hypercube has one point in each stratum of every factor", "[design]") {
  const std::size_t n = 50, dims = 3;
  const std::vector<double> u = unit_points(DesignMethod::latin_hypercube, n, dims, 11);
  for (std::size_t j = 0; j < dims; ++j) {
    std::set<long> strata;
    for (std::size_t i = 0; i < n; ++i) strata.insert(static_cast<long>(u[i * dims + j] * n));
    CHECK(strata.size() == n);
  }
}

TEST_CASE("shifted Sobol' points keep the net property: 2^k points 1/2^k apart", "[design]") {
  // the first 2^k points of a Sobol' coordinate are j / 2^k; a shift modulo 1 keeps the gaps
  const std::size_t n = 64, dims = 4;
  const std::vector<double> u = unit_points(DesignMethod::sobol, n, dims, 5);
  for (std::size_t j = 0; j < dims; ++j) {
    std::vector<double> c;
    for (std::size_t i = 0; i < n; ++i) c.push_back(u[i * dims + j]);
    std::sort(c.begin(), c.end());
    for (std::size_t i = 1; i < n; ++i) CHECK(c[i] - c[i - 1] == Approx(1.0 / n).margin(1e-12));
  }
  CHECK(unit_points(DesignMethod::sobol, n, dims, 6) != u);  // the seed moves them
}

TEST_CASE("Saltelli's blocks: A, B, and A with column i from B", "[design]") {
  const std::size_t n = 8, d = 3;
  const std::vector<double> u = saltelli_unit_points(DesignMethod::monte_carlo, n, d, 2);
  REQUIRE(u.size() == n * (d + 2) * d);
  auto at = [&](std::size_t block, std::size_t r, std::size_t j) {
    return u[(block * n + r) * d + j];
  };
  for (std::size_t i = 0; i < d; ++i)
    for (std::size_t r = 0; r < n; ++r)
      for (std::size_t j = 0; j < d; ++j) CHECK(at(2 + i, r, j) == at(j == i ? 1 : 0, r, j));
  CHECK(at(0, 0, 0) != at(1, 0, 0));
}

TEST_CASE("Morris trajectories move each factor once by p/(2(p-1)) on the grid", "[design]") {
  const std::size_t r = 20, d = 5;
  const int p = 4;
  const std::vector<double> u = morris_unit_points(r, d, p, 9);
  REQUIRE(u.size() == r * (d + 1) * d);
  const double delta = p / (2.0 * (p - 1));
  for (std::size_t t = 0; t < r; ++t) {
    std::set<std::size_t> moved;
    for (std::size_t k = 1; k <= d; ++k) {
      std::size_t changes = 0;
      for (std::size_t j = 0; j < d; ++j) {
        const double a = u[(t * (d + 1) + k - 1) * d + j], b = u[(t * (d + 1) + k) * d + j];
        const double level = b * (p - 1);
        CHECK(std::abs(level - std::round(level)) < 1e-12);  // on the grid
        if (a != b) {
          ++changes;
          moved.insert(j);
          CHECK(std::abs(b - a) == Approx(delta).epsilon(1e-12));
        }
      }
      CHECK(changes == 1);
    }
    CHECK(moved.size() == d);
  }
}

TEST_CASE("a design is the study's last axis; same seed, same points and ids", "[design]") {
  Json doc = doc_with(two_factor_design("latin-hypercube", 16, 4));
  doc["grid"] = Json::parse(R"([{"key": "integrator.rel_tol", "values": [1e-6, 1e-7]}])");
  const Study a = parse_study(doc, "d.json", "/tmp/rodend-results");
  const Study b = parse_study(doc, "d.json", "/tmp/rodend-results");
  REQUIRE(a.cases.size() == 32);
  CHECK(a.axis_keys == std::vector<std::string>{"integrator.rel_tol", "design.sample",
                                                "parameters.contact.clearance",
                                                "parameters.contact.restitution"});
  CHECK(a.design_units == std::vector<std::string>{"m", "1"});
  for (std::size_t i = 0; i < a.cases.size(); ++i) {
    CHECK(a.cases[i].id == b.cases[i].id);
    CHECK(a.cases[i].design_sample == static_cast<long>(i % 16));
    CHECK(a.cases[i].parameters.number("contact.clearance") == a.design->values[(i % 16) * 2]);
  }
  // the second grid point runs the same design points
  CHECK(a.cases[3].coordinates["parameters.contact.clearance"] ==
        a.cases[19].coordinates["parameters.contact.clearance"]);
  doc["design"]["seed"] = 5;
  const Study c = parse_study(doc, "d.json", "/tmp/rodend-results");
  CHECK(c.cases[0].id != a.cases[0].id);
  CHECK(c.design->values != a.design->values);
}

TEST_CASE("discrete points drawn alike stay distinct cases", "[design]") {
  const Json design = Json::parse(R"({"method": "monte-carlo", "size": 20, "seed": 1, "factors": [
      {"key": "parameters.contact.clearance", "distribution": "discrete",
       "values": [1e-4, 2e-4], "weights": [1, 3]}]})");
  const Study s = parse_study(doc_with(design), "d.json", "/tmp/rodend-results");
  std::set<std::string> ids;
  std::size_t small = 0;
  for (const CaseSpec& c : s.cases) {
    ids.insert(c.id);
    small += c.parameters.number("contact.clearance") == 1e-4;
  }
  CHECK(ids.size() == 20);
  CHECK(small > 0);
  CHECK(small < 20);
}

TEST_CASE("a design over a scene axis samples each scene's points", "[design]") {
  Json doc = doc_with(two_factor_design("sobol", 8, 1));
  doc.erase("scene");
  doc["grid"] =
      Json::parse(R"([{"key": "scene", "values": ["gravity-drop", "rod-end-kinematic"]}])");
  const Study s = parse_study(doc, "d.json", "/tmp/rodend-results");
  REQUIRE(s.cases.size() == 16);
  CHECK(s.cases[0].scene == "gravity-drop");
  CHECK(s.cases[8].scene == "rod-end-kinematic");
  CHECK(s.cases[8].parameters.number("contact.clearance") ==
        s.cases[0].parameters.number("contact.clearance"));
}

TEST_CASE("every distribution's drawn points have its closed-form moments", "[design]") {
  // a Latin hypercube of 4096 points: the quantile function (Boost.Math) integrated by
  // stratified sampling against the moments' closed forms (design.cpp): an error of the sample
  // mean of a smooth monotone quantile is O(std / N) for LHS, far inside 1 % of the std
  const Json factors = Json::parse(R"([
    {"key": "parameters.contact.clearance", "distribution": "uniform", "lower": 1e-4, "upper": 5e-4},
    {"key": "parameters.contact.restitution", "distribution": "triangular", "lower": 0.3, "mode": 0.4, "upper": 0.9},
    {"key": "parameters.ball.mass", "distribution": "lognormal", "mean": 0.2, "std": 0.05},
    {"key": "parameters.contact.stiffness_scale", "distribution": "truncated-normal", "mean": 1.0, "std": 0.3, "lower": 0.8, "upper": 2.0},
    {"key": "parameters.friction.dynamic_coefficient", "distribution": "normal", "mean": 0.1, "std": 0.01},
    {"key": "parameters.friction.static_coefficient", "distribution": "discrete", "values": [0.12, 0.2, 0.15], "weights": [2, 1, 1]}
  ])");
  const Json block = {
      {"method", "latin-hypercube"}, {"size", 4096}, {"seed", 3}, {"factors", factors}};
  const Design d = parse_design(block, 10'000'000);
  REQUIRE(d.dims() == distribution_catalogue().size());
  for (std::size_t j = 0; j < d.dims(); ++j) {
    double sum = 0.0, sq = 0.0;
    for (std::size_t p = 0; p < d.points(); ++p) sum += d.values[p * d.dims() + j];
    const double mean = sum / d.points();
    for (std::size_t p = 0; p < d.points(); ++p)
      sq += std::pow(d.values[p * d.dims() + j] - mean, 2);
    const double sd = std::sqrt(sq / (d.points() - 1));
    const Distribution& x = d.factors[j].distribution;
    INFO(d.factors[j].key);
    CHECK(std::abs(mean - x.moment_mean()) < 0.01 * x.moment_std());
    CHECK(std::abs(sd - x.moment_std()) < 0.01 * x.moment_std());
  }
}

TEST_CASE("design.json records every distribution's moments as mean and std", "[design]") {
  // a truncated normal's study keys mean and std are its parent's: design.json gives them as
  // parent_mean and parent_std, and mean and std as the moments (closed form: the variance of
  // the parent N(3, 1) on [2, 4] as in the test above; N(1, 0.35) on [0.5, 2]: 1.0521, 0.2999,
  // as OpenTURNS's TruncatedNormal gives them)
  using K = DistributionKind;
  const Json t = make(K::truncated_normal, 3.0, 1.0, 2.0, 4.0).to_json();
  const double phi1 = std::exp(-0.5) / std::sqrt(2.0 * M_PI), mass = std::erf(1.0 / std::sqrt(2.0));
  CHECK(t.at("mean").get<double>() == Approx(3.0).epsilon(1e-12));
  CHECK(t.at("std").get<double>() == Approx(std::sqrt(1.0 - 2.0 * phi1 / mass)).epsilon(1e-12));
  CHECK(t.at("parent_mean").get<double>() == 3.0);
  CHECK(t.at("parent_std").get<double>() == 1.0);
  const Json u = make(K::truncated_normal, 1.0, 0.35, 0.5, 2.0).to_json();
  CHECK(u.at("mean").get<double>() == Approx(1.0521).margin(5e-5));
  CHECK(u.at("std").get<double>() == Approx(0.2999).margin(5e-5));
  CHECK(u.at("parent_std").get<double>() == 0.35);
  // the others: their own mean and std (given, or the moments)
  CHECK(make(K::lognormal, 2.0, 0.5).to_json().at("std").get<double>() == 0.5);
  CHECK(make(K::triangular, 0.0, 1.0, 4.0).to_json().at("mean").get<double>() == Approx(5.0 / 3));
  CHECK_FALSE(make(K::normal, 1.0, 0.5).to_json().contains("parent_mean"));
}

TEST_CASE("a lognormal whose drawn values would overflow is a bad input naming its std",
          "[design]") {
  // std/mean = 1e160: (std/mean)^2 overflows, the log's std is infinite (Boost.Math's "Scale
  // parameter is inf" while drawing); 1e-200: it underflows to a log std of 0
  for (const double sd : {1e160 * 3e-4, 1e-200 * 3e-4}) {
    Json f = Json::parse(R"({"key": "parameters.contact.clearance", "distribution": "lognormal",
                             "mean": 3e-4})");
    f["std"] = sd;
    const Json block = {{"method", "monte-carlo"}, {"size", 4}, {"seed", 1}, {"factors", {f}}};
    INFO(sd);
    CHECK_THROWS_WITH(parse_design(block, 1000),
                      Catch::Contains("design.factors[0].std") &&
                          Catch::Contains("not all positive finite numbers"));
  }
  // mean near the largest double: the quantiles overflow though the ratio is fine
  Json f = Json::parse(R"({"key": "parameters.contact.clearance", "distribution": "lognormal",
                           "mean": 1e307, "std": 1e308})");
  const Json block = {{"method", "monte-carlo"}, {"size", 4}, {"seed", 1}, {"factors", {f}}};
  CHECK_THROWS_WITH(parse_design(block, 1000), Catch::Contains("design.factors[0].std"));
  // an ordinary spread passes
  f["mean"] = 0.2;
  f["std"] = 0.05;
  const Json fine = {{"method", "monte-carlo"}, {"size", 4}, {"seed", 1}, {"factors", {f}}};
  CHECK_NOTHROW(parse_design(fine, 1000));
}

TEST_CASE("overrides change the design's scalar keys and refuses the rest", "[design]") {
  const Json doc = doc_with(two_factor_design("monte-carlo", 8, 1));
  const Json seeded = apply_overrides(doc, {"design.seed=2", "design.size=4"}, "d.json");
  CHECK(seeded["design"]["seed"] == 2);
  CHECK(parse_study(seeded, "d.json", "/tmp/r").cases.size() == 4);
  CHECK_THROWS_WITH(apply_overrides(doc, {"design.factors=1"}, "d.json"),
                    Catch::Contains("design.factors: expected one of design.method"));
}

namespace {

/// Spearman's rank correlation of columns a and b of n x d points (no ties: continuous factors).
double spearman(const std::vector<double>& v, std::size_t d, std::size_t a, std::size_t b) {
  const std::size_t n = v.size() / d;
  auto ranks = [&](std::size_t c) {
    std::vector<std::size_t> idx(n);
    for (std::size_t i = 0; i < n; ++i) idx[i] = i;
    std::sort(idx.begin(), idx.end(), [&](auto x, auto y) { return v[x * d + c] < v[y * d + c]; });
    std::vector<double> r(n);
    for (std::size_t i = 0; i < n; ++i) r[idx[i]] = static_cast<double>(i);
    return r;
  };
  const std::vector<double> ra = ranks(a), rb = ranks(b);
  const double m = (n - 1) / 2.0;
  double sab = 0.0, saa = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    sab += (ra[i] - m) * (rb[i] - m);
    saa += (ra[i] - m) * (ra[i] - m);
  }
  return sab / saa;
}

Json correlated_design(const std::string& method, const Json& matrix,
                       const std::string& kind = "spearman") {
  Json block = two_factor_design(method, 4000, 5);
  block["correlation"] = {{"kind", kind}, {"matrix", matrix}};
  return block;
}

}  // namespace

TEST_CASE("correlated factors: the points have the Spearman correlation asked", "[design]") {
  // 4000 Monte Carlo points: the sample Spearman correlation's standard error is about
  // (1 - rho^2) / sqrt(n) = 0.008 at rho = 0.7; 0.03 is nearly 4 of them. Independent factors
  // (the same design without the matrix) stay near 0: the copula, not the sampler, correlates.
  const Design d = parse_design(correlated_design("monte-carlo", {{1, 0.7}, {0.7, 1}}), 10'000'000);
  CHECK(std::abs(spearman(d.values, 2, 0, 1) - 0.7) < 0.03);
  CHECK(std::abs(d.copula[1] - 2 * std::sin(std::numbers::pi * 0.7 / 6)) < 1e-15);
  const Design free = parse_design(two_factor_design("monte-carlo", 4000, 5), 10'000'000);
  CHECK(std::abs(spearman(free.values, 2, 0, 1)) < 0.04);
  // the marginals are kept: the uniform clearance's mean (std error 1.8e-6 m) and bounds
  double sum = 0.0;
  for (std::size_t p = 0; p < d.points(); ++p) {
    CHECK(d.values[2 * p] >= 1e-4);
    CHECK(d.values[2 * p] <= 5e-4);
    sum += d.values[2 * p];
  }
  CHECK(std::abs(sum / d.points() - 3e-4) < 8e-6);
  // negative, on a Latin hypercube, given as the normal copula's own (Pearson) matrix:
  // rho_S = 6/pi asin(R/2)
  const Design lhs = parse_design(
      correlated_design("latin-hypercube", {{1, -0.5}, {-0.5, 1}}, "pearson"), 10'000'000);
  CHECK(std::abs(spearman(lhs.values, 2, 0, 1) - 6 / std::numbers::pi * std::asin(-0.25)) < 0.03);
  CHECK(lhs.to_json({"m", "1"})["correlation"]["kind"] == "pearson");
}

TEST_CASE("a correlation matrix is checked, and refused by saltelli and morris", "[design]") {
  const auto refused = [](const Json& block, const std::string& text) {
    CHECK_THROWS_WITH(parse_design(block, 10'000'000), Catch::Contains(text));
  };
  refused(correlated_design("saltelli", {{1, 0.5}, {0.5, 1}}),
          "design.correlation: a saltelli design needs independent factors");
  refused(correlated_design("morris", {{1, 0.5}, {0.5, 1}}),
          "expected method \"monte-carlo\", \"latin-hypercube\", \"sobol\"");
  refused(correlated_design("sobol", {{1, 0.5}, {0.4, 1}}),
          "design.correlation.matrix[1][0]: expected a symmetric matrix");
  refused(correlated_design("sobol", {{1, 0.5}, {0.5, 0.9}}),
          "design.correlation.matrix[1][1]: expected 1 on the diagonal");
  refused(correlated_design("sobol", {{1, 1.5}, {1.5, 1}}),
          "design.correlation.matrix[0][1]: expected a correlation in [-1, 1]");
  refused(correlated_design("sobol", {{1, 0.5}}), "design.correlation.matrix: expected 2 rows");
  refused(correlated_design("sobol", {{1, 1}, {1, 1}}), "not positive definite");
  refused(correlated_design("sobol", {{1, 0.5}, {0.5, 1}}, "kendall"),
          "design.correlation.kind: unknown 'kendall'");
  Json three = two_factor_design("monte-carlo", 8, 1);
  three["factors"].push_back(Json::parse(R"({"key": "parameters.contact.stiffness_scale",
      "distribution": "uniform", "lower": 0.5, "upper": 2})"));
  three["correlation"] = {{"kind", "pearson"},
                          {"matrix", {{1, 0.9, 0.9}, {0.9, 1, -0.9}, {0.9, -0.9, 1}}}};
  refused(three, "design.correlation.matrix: not positive definite");
}

// The ids of a design over parameters come from its id template (the base's canonical text cut
// where the sampled values go, sweep/study/loader.hpp) and the dry-run's rows from the grid
// without resolving a case: both must be what resolving each case gives.
TEST_CASE("a design's ids and rows without resolving equal those of the resolved cases",
          "[design]") {
  Json doc = doc_with(two_factor_design("sobol", 16, 3));
  const bool with_grid = GENERATE(false, true);
  if (with_grid)  // a grid axis over a parameter before the design's
    doc["grid"] = Json::parse(R"([{"key": "parameters.ball.mass", "values": [0.2, 1]}])");
  const Study s = parse_study(doc, "d.json", "/tmp/rodend-results");
  REQUIRE(s.cases.size() == (with_grid ? 32u : 16u));
  for (std::size_t i = 0; i < s.cases.size(); ++i) {
    const CaseSpec c = s.cases[i];
    CHECK(c.id == case_id(c));  // the stored id (template) against the canonical form's
    const CaseList::Row r = s.cases.row(i);
    CHECK(r.index == c.index);
    CHECK(r.id == c.id);
    CHECK(r.method == c.integrator.method);
    CHECK(r.end_s == c.time.end);
    CHECK(r.coordinates == c.coordinates);
  }
  // the design of bench/design.sh, on rod-end-actuator (its integrator preset, four factors)
  const Study a = parse_study(Json::parse(R"({"name": "b", "scene": "rod-end-actuator",
      "time": {"end": 2.4, "sample_interval": 1e-3},
      "design": {"method": "sobol", "size": 32, "seed": 1, "factors": [
        {"key": "parameters.contact.clearance", "distribution": "triangular", "lower": 1e-4,
         "mode": 2e-4, "upper": 5e-4},
        {"key": "parameters.socket.misalignment_z", "distribution": "truncated-normal",
         "mean": 0, "std": 3e-5, "lower": -9e-5, "upper": 9e-5},
        {"key": "parameters.hinge.constant_moment", "distribution": "normal", "mean": 0,
         "std": 100},
        {"key": "parameters.friction.dynamic_coefficient", "distribution": "uniform",
         "lower": 0.05, "upper": 0.12}]}})"),
                              "b.json", "/tmp/rodend-results");
  for (std::size_t i = 0; i < a.cases.size(); ++i) CHECK(a.cases[i].id == case_id(a.cases[i]));
  // a setting on an axis: no template; the ids are still the canonical form's
  doc["grid"] = Json::parse(R"([{"key": "integrator.rel_tol", "values": [1e-6, 1e-7]}])");
  const Study t = parse_study(doc, "d.json", "/tmp/rodend-results");
  for (std::size_t i = 0; i < t.cases.size(); ++i) CHECK(t.cases[i].id == case_id(t.cases[i]));
}

namespace {

void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

Study file_study(const std::filesystem::path& folder) {
  return parse_study(doc_with({{"method", "file"}, {"file", "points.csv"}}), folder / "d.json",
                     folder / "results");
}

}  // namespace

TEST_CASE("a file design runs each row as one case, its values in the ids", "[design]") {
  const test::TempDir dir("design-file");
  // a byte-order mark, a comment line and a blank line are skipped; the columns in any order
  write_text(dir.path() / "points.csv",
             "\xef\xbb\xbf# measured\nparameters.contact.restitution,parameters.contact.clearance\n"
             "0.5,1e-4\n\n0.7, 2.5e-4\n0.6,3e-4\n");
  const Study a = file_study(dir.path());
  REQUIRE(a.cases.size() == 3);
  CHECK(a.axis_keys == std::vector<std::string>{"design.sample", "parameters.contact.restitution",
                                                "parameters.contact.clearance"});
  CHECK(a.design_units == std::vector<std::string>{"1", "m"});
  const double restitution[] = {0.5, 0.7, 0.6}, clearance[] = {1e-4, 2.5e-4, 3e-4};
  for (std::size_t i = 0; i < 3; ++i) {
    CHECK(a.cases[i].design_sample == static_cast<long>(i));
    CHECK(a.cases[i].parameters.number("contact.restitution") == restitution[i]);
    CHECK(a.cases[i].parameters.number("contact.clearance") == clearance[i]);
  }
  const Json j = a.design->to_json(a.design_units);
  CHECK(j["method"] == "file");
  CHECK(j["file"] == "points.csv");
  CHECK(j["size"] == 3);
  CHECK(j["points"] == 3);
  CHECK(j["content_fnv1a64"].get<std::string>().size() == 16);
  CHECK_FALSE(j.contains("seed"));
  CHECK_FALSE(j["factors"][0].contains("distribution"));
  CHECK(j["factors"][1]["units"] == "m");
  // one cell changed: that row's case gets a new id, the others keep theirs
  write_text(dir.path() / "points.csv",
             "parameters.contact.restitution,parameters.contact.clearance\n"
             "0.5,1e-4\n0.7,2.6e-4\n0.6,3e-4\n");
  const Study b = file_study(dir.path());
  CHECK(b.cases[0].id == a.cases[0].id);
  CHECK(b.cases[1].id != a.cases[1].id);
  CHECK(b.cases[2].id == a.cases[2].id);
  CHECK(b.design->to_json(b.design_units)["content_fnv1a64"] != j["content_fnv1a64"]);
}

TEST_CASE("a file design's bad file: missing, an unknown column, a cell not a number", "[design]") {
  const test::TempDir dir("design-file");
  auto problem = [&](const std::string& text) -> std::string {
    if (!text.empty()) write_text(dir.path() / "points.csv", text);
    try {
      file_study(dir.path());
    } catch (const InputError& e) {
      CHECK(e.key_path() == "design.file");
      return e.problem();
    }
    return "no error";
  };
  CHECK_THAT(problem(""), Catch::Contains("points.csv: no such file"));
  CHECK_THAT(problem("parameters.contact.restitutoin\n0.5\n"),
             Catch::Contains("points.csv, line 1 (the header), column 1: unknown parameter "
                             "'contact.restitutoin'") &&
                 Catch::Contains("contact.restitution"));  // the nearest name
  CHECK_THAT(problem("parameters.contact.restitution\n0.5\n0.x\n"),
             Catch::Contains("points.csv, line 3, column 'parameters.contact.restitution': "
                             "'0.x'; expected a finite number"));
  CHECK_THAT(problem("parameters.contact.restitution\nnan\n"),
             Catch::Contains("expected a finite number"));
  CHECK_THAT(problem("parameters.contact.restitution,parameters.contact.restitution\n0.5,0.6\n"),
             Catch::Contains("is sampled twice"));
  CHECK_THAT(problem("# only a comment\n"), Catch::Contains("has no header"));
  CHECK_THAT(problem("parameters.contact.restitution\n"), Catch::Contains("no row of points"));
}
