#include "app/report.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/integrator.hpp"
#include "sweep/results.hpp"

namespace rodend {
namespace fs = std::filesystem;
namespace {

std::string escape(const std::string& s) {
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

std::string number(double v) {
  return std::isnan(v) ? std::string() : shortest_decimal(v);
}

std::string base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(in[i]) << 16) |
                       (static_cast<unsigned char>(in[i + 1]) << 8) |
                       static_cast<unsigned char>(in[i + 2]);
    for (int s = 18; s >= 0; s -= 6) out += k[(v >> s) & 63];
  }
  if (i < in.size()) {
    unsigned v = static_cast<unsigned char>(in[i]) << 16;
    if (i + 1 < in.size()) v |= static_cast<unsigned char>(in[i + 1]) << 8;
    out += k[(v >> 18) & 63];
    out += k[(v >> 12) & 63];
    out += i + 1 < in.size() ? k[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

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

/// The figures of plots/ (PNG files), inlined in the page.
void write_figures(std::ostream& h, const fs::path& dir) {
  h << "<h2>Figures</h2>\n";
  std::vector<fs::path> pngs;
  if (fs::is_directory(dir / "plots"))
    for (const auto& e : fs::directory_iterator(dir / "plots"))
      if (e.path().extension() == ".png") pngs.push_back(e.path());
  std::sort(pngs.begin(), pngs.end());
  if (pngs.empty())
    h << "<p>No figures: draw them first with <code>/usr/bin/python3 plots/plot_study.py "
      << escape(dir.string()) << "</code>.</p>\n";
  for (const fs::path& p : pngs)
    h << "<figure><img alt=\"" << escape(p.stem().string()) << "\" src=\"data:image/png;base64,"
      << base64(read_file(p)) << "\"><figcaption>" << escape(p.filename().string())
      << "</figcaption></figure>\n";
}

/// The summary as a table, a column per metric, a row per case.
void write_summary_table(std::ostream& h, const SummaryTable& t) {
  h << "<h2>Summary</h2>\n<table><tr>";
  for (const std::string& c : t.columns) {
    const auto u = t.units.find(c);
    h << "<th>" << escape(c);
    if (u != t.units.end() && !u->second.empty()) h << " [" << escape(u->second) << "]";
    h << "</th>";
  }
  h << "</tr>\n";
  for (std::size_t i = 0; i < t.rows; ++i) {
    h << "<tr>";
    for (const std::string& c : t.columns) {
      if (t.is_text(c))
        h << "<td class=\"t\">" << escape(t.texts.at(c)[i]) << "</td>";
      else
        h << "<td>" << number(t.numbers.at(c)[i]) << "</td>";
    }
    h << "</tr>\n";
  }
  h << "</table>\n";
}

/// The page's head, title, the study's description and the count of cases.
void write_heading(std::ostream& h, const fs::path& dir, const SummaryTable& t, const Json& study) {
  const std::string name = study.is_object() && study.contains("name") && study["name"].is_string()
                               ? study["name"].get<std::string>()
                               : fs::absolute(dir).lexically_normal().filename().string();
  const std::size_t ok = count_ok(t);
  h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>rodend: "
    << escape(name)
    << "</title>\n<style>body{font-family:sans-serif;margin:2em;max-width:80em}"
       "table{border-collapse:collapse;font-size:small}td,th{border:1px solid #ccc;padding:"
       "2px 6px;text-align:right}th{background:#eee}td.t{text-align:left}"
       "pre{background:#f6f6f6;padding:1em;overflow:auto}img{max-width:100%}"
       "figure{margin:1em 0}</style></head><body>\n";
  h << "<h1>Study " << escape(name) << "</h1>\n";
  if (study.is_object() && study.contains("description") && study["description"].is_string())
    h << "<p>" << escape(study["description"].get<std::string>()) << "</p>\n";
  h << "<p>" << t.rows << " case(s): " << ok << " ok, " << t.rows - ok
    << " failed. Results in <code>" << escape(fs::absolute(dir).lexically_normal().string())
    << "</code>.</p>\n";
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
  write_figures(h, dir);
  write_summary_table(h, t);
  h << "<h2>Provenance</h2>\n<pre>" << escape(t.provenance.dump(2)) << "</pre>\n";
  h << "<h2>The study as run (study.json)</h2>\n<pre>"
    << escape(study.is_discarded() ? std::string("(unreadable)") : study.dump(2)) << "</pre>\n";
  h << "</body></html>\n";
  // a fresh file under an unpredictable name, then renamed: never written through a link
  write_text_file_atomically(out, "report", h.str(), /*durable=*/false);
  return out;
}

}  // namespace rodend
