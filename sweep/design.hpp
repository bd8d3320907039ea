// Sampled designs (study key "design"; docs/uncertainty.md): parameters given as distributions
// instead of value lists, and the design points drawn from them in the resolver, so that the
// command line, shards, MPI and Python see the same points. A design is one more axis of the
// study (the last, fastest): its keys are "design.sample" (the point's index) and the factors'
// key paths, so every grid point runs every design point.
//
// Methods (sweep/design_methods.def): Monte Carlo, Latin hypercube and Sobol' points (sampling a
// population); Saltelli's pick-freeze blocks (first-order and total Sobol' indices); Morris
// trajectories (screening by elementary effects); the points of a CSV file. Distributions:
// sweep/distributions.def. The drawn points are drawn in the unit hypercube (std::mt19937_64, whose
// output the C++ standard fixes, and Boost.Random's Sobol' generator) and mapped through each
// factor's quantile function (Boost.Math), so a study and its seed give the same points on any
// machine.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/choice.hpp"
#include "core/params.hpp"

namespace rodend {

/// The catalogue of design methods (sweep/design_methods.def; names: "design.method").
#define RODEND_CHOICE_ENUM DesignMethod
#define RODEND_CHOICE_FILE "sweep/design_methods.def"
#include "core/choice.hpp"
/// The catalogue of distributions (sweep/distributions.def; names:
/// "design.factors[i].distribution").
#define RODEND_CHOICE_ENUM DistributionKind
#define RODEND_CHOICE_FILE "sweep/distributions.def"
#include "core/choice.hpp"
struct Design;
/// A method's draw (sweep/design_methods.def): fills the design's unit points from its size, seed
/// and method keys, or (a method without distributions) its factors and values.
using DrawPoints = void (*)(Design&);

/// How design.correlation gives the factors' dependence (a normal copula either way).
enum class CorrelationKind { spearman, pearson };

/// One line of sweep/design_methods.def (its columns are explained there).
struct DesignMethodInfo {
  DesignMethod method;
  std::string_view name;
  DrawPoints draw;
  bool distributions;  ///< its factors are design.factors with distributions (file: false)
  /// draws a sample of N points: also a saltelli design's base for A and B, and the methods
  /// that accept correlated factors (design.correlation)
  bool sample;
  std::size_t per_factor, extra;  ///< points per grid point: size (per_factor d + extra)
  std::size_t iid_blocks;         ///< the first iid_blocks x size points: an independent sample
  std::string_view description;
};
struct DistributionInfo {
  DistributionKind kind;
  std::string_view name;
  std::vector<std::string_view> keys;  ///< its parameters, in the factor's unit
  bool bounded;                        ///< finite support (what a Morris design needs)
  std::string_view description;
};
const std::vector<DesignMethodInfo>& design_method_catalogue();
const std::vector<DistributionInfo>& distribution_catalogue();
/// The keys of the "design" block (its scalar settings, then "factors"): the reader's, the
/// schema's and --set's one list.
const std::vector<std::string_view>& design_keys();
/// "spearman" (rank correlations of the factors) or "pearson" (the correlations of their normal
/// scores, the normal copula's own matrix).
const std::vector<std::pair<CorrelationKind, std::string_view>>& correlation_kinds();
const DistributionInfo& distribution_info(DistributionKind k);
const DesignMethodInfo& design_method_info(DesignMethod m);

// The draw functions the catalogue names (sweep/design.cpp), one per drawn method.
#define RODEND_CHOICE(id, name, doc, draw, ...) void draw(Design&);
#include "sweep/design_methods.def"
#undef RODEND_CHOICE

/// One factor's distribution; its parameters are in the unit of the key it samples.
struct Distribution {
  DistributionKind kind = DistributionKind::uniform;
  /// normal, lognormal: the variable's mean and standard deviation; truncated-normal: those
  /// of the parent normal
  double mean = 0.0, std = 0.0;
  double lower = 0.0, upper = 0.0, mode = 0.0;  ///< bounds (uniform, truncated, triangular)
  std::vector<double> values, weights;          ///< discrete: sorted values, weights summing to 1

  /// The inverse of the cumulative distribution at u in [0, 1] (clamped inside (0, 1) for an
  /// unbounded support).
  double quantile(double u) const;
  double moment_mean() const;  ///< E[X]
  double moment_std() const;   ///< sqrt(Var[X])
  /// {"distribution", its parameters, "mean", "std"}: mean and std are the moments (E[X],
  /// sqrt(Var[X])); a truncated normal's parent parameters are "parent_mean", "parent_std"
  Json to_json() const;
};

struct DesignFactor {
  std::string key;            ///< the key path it samples ("parameters.contact.clearance")
  std::string where;          ///< its place in the study ("design.factors[0]", "design.file")
  Distribution distribution;  ///< (a method with distributions)
  /// where its key is given, and what goes before a message on it: "design.factors[0].key" and
  /// ""; or "design.file" and "points.csv, line 1, column 2: "
  std::string key_where, context;
};
/// A factor's key path checked: a numeric key, not already in `before`. Throws InputError at
/// `key_where`, its problem starting with `context`.
void check_factor_key(const std::string& key, const std::string& key_where,
                      const std::string& context, const std::vector<DesignFactor>& before);

/// A resolved design: the points (unit hypercube and values) for one grid point.
struct Design {
  DesignMethod method = DesignMethod::monte_carlo;
  DesignMethod base = DesignMethod::monte_carlo;  ///< saltelli: how A and B are drawn
  std::size_t size = 0;                           ///< N: points, base size or trajectories
  std::uint64_t seed = 0;
  int levels = 4;  ///< morris: p
  /// file: design.file as given, the file it names (relative paths from the study file's
  /// folder) and the FNV-1a 64 hash of its bytes (recorded in design.json; the case ids carry
  /// each row's values, as every design's)
  std::string file;
  std::filesystem::path resolved;
  std::string content_fnv1a64;
  std::vector<DesignFactor> factors;
  /// design.correlation: its kind and matrix as given, and the normal copula's correlation
  /// matrix R (d x d, row-major; from Spearman's rho_S: R = 2 sin(pi rho_S / 6)); empty for
  /// independent factors
  CorrelationKind correlation_kind = CorrelationKind::spearman;
  std::vector<double> correlation, copula;
  std::vector<double> unit;    ///< points() x factors, row-major, in [0, 1]
  std::vector<double> values;  ///< the same mapped through the quantile functions

  std::size_t dims() const { return factors.size(); }
  /// Points per grid point: N, N (d + 2) for saltelli, N (d + 1) for morris.
  std::size_t points() const { return dims() == 0 ? 0 : values.size() / dims(); }
  double delta() const { return levels / (2.0 * (levels - 1)); }  ///< morris step (unit space)
  /// design.json: method, base, size, seed, levels and delta (morris), points, the factors with
  /// their distributions and units, and (morris) the unit-space points.
  Json to_json(const std::vector<std::string>& units) const;
  /// The --dry-run table: each factor's distribution moments beside the points' statistics.
  std::string statistics() const;
};

/// Bounds of the design block, the reader's and the schema's: factors (a Sobol' base of 2 d
/// dimensions stays in Boost's table of 3667) and Morris levels.
inline constexpr std::size_t kMaxDesignFactors = 1000;
inline constexpr int kMaxMorrisLevels = 1000;

/// Parses and draws the "design" block; `max_points` is the case limit left for it; `folder`:
/// where a relative design.file is read from (the study file's folder). Throws InputError naming
/// the key path under "design".
Design parse_design(const Json& block, std::size_t max_points,
                    const std::filesystem::path& folder = {});

/// Points of `n` x `dims` in the unit hypercube, row-major: Monte Carlo, Latin hypercube or
/// randomly shifted Sobol' points.
std::vector<double> unit_points(DesignMethod method, std::size_t n, std::size_t dims,
                                std::uint64_t seed);
/// Saltelli's N (d + 2) points: A, B, then A with column i from B, for i = 0..d-1 (OpenTURNS's
/// SobolIndicesExperiment order); A and B from a `base` sample of N x 2d.
std::vector<double> saltelli_unit_points(DesignMethod base, std::size_t n, std::size_t d,
                                         std::uint64_t seed);
/// Morris's r trajectories of d + 1 points on the p-level grid, each factor moved once by
/// p / (2 (p - 1)).
std::vector<double> morris_unit_points(std::size_t r, std::size_t d, int p, std::uint64_t seed);

/// The lower Cholesky factor L (L L^T = a) of a d x d symmetric matrix, row-major; empty when
/// a is not positive definite (a pivot <= 1e-12 of the largest diagonal entry).
std::vector<double> cholesky(const std::vector<double>& a, std::size_t d);
/// Independent unit points (n x d, row-major) made dependent through the normal copula of
/// Cholesky factor `lower`: u -> z = Phi^-1(u) -> L z -> Phi (OpenTURNS's NormalCopula).
void apply_normal_copula(std::vector<double>& unit, const std::vector<double>& lower,
                         std::size_t d);

}  // namespace rodend
