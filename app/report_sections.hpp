// The sections of `rodend report`'s page (app/report.cpp assembles them):
//   report_answers.cpp  "Answers": per metric its spread, exceedance and ranked factors, from
//                       analysis/analysis.json (written by `rodend analyze`)
//   report_figures.cpp  the figures of plots/, grouped by the question they answer, captioned
//                       from their PNG text chunks, embedded up to a byte budget
#pragma once

#include <cstddef>
#include <filesystem>
#include <ostream>
#include <string>

namespace rodend::report {

/// s with &, <, > and " as HTML entities.
std::string escape(const std::string& s);
/// A number with 4 significant digits ("–" for NaN).
std::string short_number(double v);

/// The "Answers" section when dir/analysis/analysis.json exists; a pointer to `rodend analyze`
/// when the study has a design (dir/design.json) but no analysis; nothing otherwise.
void write_answers(std::ostream& h, const std::filesystem::path& dir);

/// Figures embedded at most this many PNG bytes (base64 adds a third): the page stays under
/// 2 MB; the figures beyond it are listed with a link and their caption.
constexpr std::size_t figure_budget_bytes = 1'300'000;

/// The PNGs of dir/plots, grouped by question (the text chunk `rodend-question`) and captioned
/// (`Description`, else the file name), embedded up to budget bytes.
void write_figures(std::ostream& h, const std::filesystem::path& dir, std::size_t budget);

}  // namespace rodend::report
