#include "app/report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/report_sections.hpp"
#include "core/integrator.hpp"
#include "sweep/results.hpp"

namespace rodend {
namespace fs = std::filesystem;

std::string report::escape(const std::string& s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string report::short_number(double v) {
  if (std::isnan(v)) return "–";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

namespace {

constexpr std::size_t summary_rows = 50;    ///< rows of the summary shown (all: summary.csv)
constexpr std::size_t summary_metrics = 8;  ///< metric columns shown when no analysis names them

/// A summary cell to six significant digits: a table a person reads (the metrics' own accuracy is
/// coarser than that); every digit is in summary.csv, which the note under the heading names.
std::string number(double v) {
  if (std::isnan(v)) return std::string();
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

using report::escape;

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// The cases that ended ok, from the summary's status column.
std::size_t count_ok(const SummaryTable& t) {
  std::size_t ok = 0;
  if (t.texts.count("status"))
    for (const std::string& s : t.texts.at("status"))
      if (choice_from_name<RunStatus>(s) == RunStatus::ok) ++ok;
  return ok;
}

/// The metrics the analysis names (analysis/analysis.json), else the first few summary metric
/// columns (after finished_utc) with a finite value.
std::vector<std::string> key_metrics(const SummaryTable& t, const fs::path& dir) {
  std::vector<std::string> out;
  const fs::path file = dir / "analysis" / "analysis.json";
  if (fs::is_regular_file(file)) {
    const Json doc = Json::parse(read_file(file), nullptr, false);
    if (doc.is_object() && doc.contains("groups") && doc["groups"].is_array() &&
        !doc["groups"].empty() && doc["groups"][0].contains("metrics"))
      for (const auto& [m, r] : doc["groups"][0]["metrics"].items())
        if (t.numbers.count(m)) out.push_back(m);
  }
  if (!out.empty()) return out;
  const auto fin = std::find(t.columns.begin(), t.columns.end(), "finished_utc");
  for (auto c = fin == t.columns.end() ? fin : fin + 1; c != t.columns.end(); ++c) {
    if (out.size() == summary_metrics) break;
    const auto v = t.numbers.find(*c);
    if (v != t.numbers.end() &&
        std::any_of(v->second.begin(), v->second.end(), [](double x) { return std::isfinite(x); }))
      out.push_back(*c);
  }
  return out;
}

/// The summary's columns shown: case id, the grid keys (the columns between scene and status,
/// and scene when it varies), status and the key metrics.
std::vector<std::string> summary_columns(const SummaryTable& t, const fs::path& dir) {
  std::vector<std::string> cols{"case_id"};
  const auto scene = std::find(t.columns.begin(), t.columns.end(), "scene");
  const auto status = std::find(t.columns.begin(), t.columns.end(), "status");
  if (scene != t.columns.end() && t.texts.count("scene")) {
    const auto& v = t.texts.at("scene");
    if (std::any_of(v.begin(), v.end(), [&](const std::string& x) { return x != v.front(); }))
      cols.push_back("scene");
  }
  if (scene != t.columns.end() && status != t.columns.end() && scene < status)
    cols.insert(cols.end(), scene + 1, status);
  if (status != t.columns.end()) cols.push_back("status");
  for (const std::string& m : key_metrics(t, dir)) cols.push_back(m);
  std::erase_if(cols, [&](const std::string& c) { return !t.is_text(c) && !t.numbers.count(c); });
  return cols;
}

/// The summary as a table: the grid axes and key metrics of the first summary_rows cases.
void write_summary_table(std::ostream& h, const SummaryTable& t, const fs::path& dir) {
  const std::vector<std::string> cols = summary_columns(t, dir);
  const std::size_t rows = std::min(t.rows, summary_rows);
  h << "<h2>Summary</h2>\n<p class=\"note\">" << (rows < t.rows ? "The first " : "The ") << rows
    << " of " << t.rows << " case(s), the grid axes and key metrics: " << cols.size() << " of "
    << t.columns.size()
    << " columns, numbers to six significant digits. The whole table, every digit, is "
       "<code>summary.csv</code> (and <code>summary.h5</code>) in the results folder.</p>\n<div "
       "class=\"wide\"><table><tr>";
  for (const std::string& c : cols) {
    const auto u = t.units.find(c);
    h << "<th>" << escape(c);
    if (u != t.units.end() && !u->second.empty()) h << " [" << escape(u->second) << "]";
    h << "</th>";
  }
  h << "</tr>\n";
  for (std::size_t i = 0; i < rows; ++i) {
    h << "<tr>";
    for (const std::string& c : cols) {
      if (t.is_text(c))
        h << "<td class=\"t\">" << escape(t.texts.at(c)[i]) << "</td>";
      else
        h << "<td>" << number(t.numbers.at(c)[i]) << "</td>";
    }
    h << "</tr>\n";
  }
  h << "</table></div>\n";
}

/// The page's head, title and the count of cases (the description follows the answers).
void write_heading(std::ostream& h, const fs::path& dir, const SummaryTable& t, const Json& study) {
  const std::string name = study.is_object() && study.contains("name") && study["name"].is_string()
                               ? study["name"].get<std::string>()
                               : fs::absolute(dir).lexically_normal().filename().string();
  const std::size_t ok = count_ok(t);
  h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>rodend: "
    << escape(name)
    << "</title>\n<style>body{font-family:sans-serif;margin:1em 2em;max-width:80em}"
       "h1{margin:0.2em 0}h2{margin:0.8em 0 0.3em}"
       "table{border-collapse:collapse;font-size:small}td,th{border:1px solid #ccc;padding:"
       "2px 6px;text-align:right}th{background:#eee}td.t{text-align:left}"
       ".iv{color:#666;font-size:smaller}.note{color:#555;font-size:small;margin:0.3em 0}"
       ".wide{overflow-x:auto}pre{background:#f6f6f6;padding:1em;overflow:auto}"
       "img{max-width:100%}figure{margin:1em 0}figcaption{font-size:small}</style></head>"
       "<body>\n";
  h << "<h1>Study " << escape(name) << "</h1>\n";
  h << "<p class=\"note\">" << t.rows << " case(s): " << ok << " ok, " << t.rows - ok
    << " failed. Results in <code>" << escape(fs::absolute(dir).lexically_normal().string())
    << "</code>.</p>\n";
}

void write_description(std::ostream& h, const Json& study) {
  if (study.is_object() && study.contains("description") && study["description"].is_string())
    h << "<h2>The study</h2>\n<p>" << escape(study["description"].get<std::string>()) << "</p>\n";
}

}  // namespace

fs::path write_report(const fs::path& dir, const fs::path& out_arg) {
  const SummaryTable t = read_summary(dir);
  const fs::path out = out_arg.empty() ? dir / "report.html" : out_arg;
  Json study = Json::object();
  if (fs::is_regular_file(dir / "study.json"))
    study = Json::parse(read_file(dir / "study.json"), nullptr, false);
  std::ostringstream h;
  write_heading(h, dir, t, study);
  report::write_answers(h, dir);
  write_description(h, study);
  report::write_figures(h, dir, report::figure_budget_bytes);
  write_summary_table(h, t, dir);
  h << "<h2>Provenance</h2>\n<pre>" << escape(t.provenance.dump(2)) << "</pre>\n";
  h << "<h2>The study as run (study.json)</h2>\n<pre>"
    << escape(study.is_discarded() ? std::string("(unreadable)") : study.dump(2)) << "</pre>\n";
  h << "</body></html>\n";
  // a fresh file under an unpredictable name, then renamed: never written through a link
  write_text_file_atomically(out, "report", h.str(), /*durable=*/false);
  return out;
}

}  // namespace rodend
