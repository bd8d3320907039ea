// Comparing two study results (`rodend compare A B`): summary metrics with per-metric
// tolerances, and histories pointwise up to the first impact, then as envelopes.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <map>
#include <string>

namespace rodend {

/// |a - b| <= abs + rel * scale, with scale max(|a|, |b|) for metrics and the reference's range
/// for histories.
struct Tolerance {
  double rel = 1e-6;
  double abs = 1e-12;
};

/// Tolerances of a comparison (the tolerance file). Defaults: metrics rel 1e-6, abs 1e-12;
/// histories rel 1e-6 of the reference signal's range, abs 1e-12, time shift 1 ms.
struct CompareSettings {
  Tolerance metric_default;
  std::map<std::string, Tolerance> metric;  ///< per metric, by catalogue name
  Tolerance history;
  double time_shift = 1e-3;   ///< [s] half-width of the envelope window after the first impact
  bool summary_only = false;  ///< compare only the summaries (the reference has no case files)
  int max_lines_per_case = 10;
};

/// Reads a tolerance file:
///   {"metrics": {"default": {"rel": r, "abs": a}, "<metric>": {"rel": r, "abs": a}, ...},
///    "histories": {"rel": r, "abs": a, "time_shift": s}}
/// Throws InputError (file, key path) for unknown keys or metric names and bad values.
CompareSettings load_tolerances(const std::filesystem::path& file);

/// Compares study results `a` (reference) and `b`; writes a readable report. Returns 0 when
/// equal within tolerance, 1 when different. Cases are paired by id, else by grid position
/// (same case_index and grid coordinates: the id changes with any parameter added to a scene),
/// with a note; metrics newer than the reference (absent from it) are noted, not compared. Throws
/// std::runtime_error when a folder is not a study or a file cannot be read (the CLI turns that
/// into exit code 2).
int compare_studies(const std::filesystem::path& a, const std::filesystem::path& b,
                    const CompareSettings& settings, std::ostream& report);

}  // namespace rodend
