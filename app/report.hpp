// `rodend report RESULTS`: one self-contained HTML page per study (summary table with units,
// the study's figures embedded as base64 PNG, the study as run and its provenance).
#pragma once

#include <filesystem>

namespace rodend {

/// Writes `out` (default RESULTS/report.html) for the study results folder `dir`; the figures
/// are the PNGs in dir/plots (drawn by plots/plot_study.py). Returns the path written; throws
/// std::runtime_error naming the folder when it is not a study's results.
std::filesystem::path write_report(const std::filesystem::path& dir,
                                   const std::filesystem::path& out = {});

}  // namespace rodend
