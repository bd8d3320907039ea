#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>

#include "app/report_sections.hpp"
#include "core/params.hpp"

namespace rodend::report {
namespace fs = std::filesystem;
namespace {

constexpr std::size_t max_groups = 12;        ///< grid points shown (the rest: analysis.json)
constexpr std::size_t metrics_per_table = 4;  ///< ranking columns side by side

double num(const Json& j) {
  return j.is_number() ? j.get<double>() : std::numeric_limits<double>::quiet_NaN();
}

std::string text(const Json& j, const char* key) {
  return j.is_object() && j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : "";
}

/// The shown unit and its factor from SI (analysis.json's `shown`), else the SI unit.
struct Shown {
  std::string unit;
  double factor = 1.0;
};

Shown shown_of(const Json& r) {
  Shown s{text(r, "units"), 1.0};
  if (r.contains("shown") && r["shown"].is_object()) {
    s.unit = text(r["shown"], "units");
    if (r["shown"].contains("factor")) s.factor = num(r["shown"]["factor"]);
  }
  return s;
}

std::string unit_suffix(const std::string& u) {
  return u.empty() || u == "1" ? std::string() : " " + u;
}

/// "3710 [2898, 4796]": a value and its interval (when there is one), scaled; an end the
/// analysis could not give (null: a quantile's order statistic beyond too few points) is
/// "none", never a blank.
std::string with_interval(const Json& value, const Json& iv, double f) {
  std::string out = short_number(num(value) * f);
  if (!iv.is_array() || iv.size() != 2 || (!iv[0].is_number() && !iv[1].is_number())) return out;
  const auto end = [f](const Json& e) {
    return e.is_number() ? short_number(e.get<double>() * f) : std::string("none");
  };
  return out + " <span class=\"iv\">[" + end(iv[0]) + ", " + end(iv[1]) + "]</span>";
}

std::string short_key(const std::string& k) {
  const std::string p = "parameters.";
  return k.rfind(p, 0) == 0 ? k.substr(p.size()) : k;
}

/// One row of the spread table: metric, mean, std, quantiles, exceedance, each with interval.
void spread_row(std::ostream& h, const std::string& m, const Json& r) {
  const Shown s = shown_of(r);
  h << "<tr><td class=\"t\">" << escape(m);
  if (!unit_suffix(s.unit).empty()) h << " [" << escape(s.unit) << "]";
  h << "</td>";
  const Json d = r.value("distribution", Json());
  if (!d.is_object()) {
    h << "<td colspan=\"6\" class=\"t\">no sample of the distribution</td></tr>\n";
    return;
  }
  h << "<td>" << with_interval(d.value("mean", Json()), d.value("mean_interval", Json()), s.factor)
    << "</td><td>"
    << with_interval(d.value("std", Json()), d.value("std_interval", Json()), s.factor) << "</td>";
  const Json qi = d.value("quantile_intervals", Json::object());
  const Json q = d.value("quantiles", Json::object());
  for (const char* p : {"0.05", "0.5", "0.95"})
    h << "<td>" << with_interval(q.value(p, Json()), qi.value(p, Json()), s.factor) << "</td>";
  h << "<td class=\"t\">";
  const Json ex = r.value("exceedance", Json::array());
  for (const Json& e : ex)
    h << "P(&gt; " << short_number(num(e.value("threshold", Json())) * s.factor)
      << escape(unit_suffix(s.unit)) << ") = <b>"
      << with_interval(e.value("probability", Json()), e.value("interval", Json()), 1.0) << "</b> ("
      << e.value("exceed", 0) << " of " << e.value("n", 0) << ")<br>";
  if (ex.empty()) h << "no threshold given";
  h << "</td></tr>\n";
}

/// A quantile interval with an end the analysis could not give (null) among the metrics.
bool open_end(const Json& metrics) {
  for (const auto& [m, r] : metrics.items()) {
    const Json d = r.value("distribution", Json());
    if (!d.is_object()) continue;
    const Json qi = d.value("quantile_intervals", Json::object());  // kept: items() refers to it
    for (const auto& [p, iv] : qi.items())
      if (iv.is_array() && iv.size() == 2 && iv[0].is_number() != iv[1].is_number()) return true;
  }
  return false;
}

/// level: "95 % intervals in brackets", as analyze prints it.
void spread_table(std::ostream& h, const Json& metrics, const std::string& level) {
  h << "<div class=\"wide\"><table><tr><th>metric</th><th>mean</th><th>std</th><th>5 %</th>"
       "<th>50 %</th><th>95 %</th><th>exceedance</th></tr>\n";
  for (const auto& [m, r] : metrics.items()) spread_row(h, m, r);
  h << "</table></div>\n<p class=\"note\">" << escape(level) << ".";
  if (open_end(metrics)) h << " An interval's end is none where too few points give it.";
  for (const auto& [m, r] : metrics.items()) {
    const std::string sample = text(r.value("distribution", Json::object()), "sample");
    if (!sample.empty()) {
      h << " Spread over the " << escape(sample) << "; its intervals from a bootstrap over "
        << "trajectories.";
      break;
    }
  }
  h << "</p>\n";
}

/// The factors ranked, a column per metric, a row per rank.
void ranking_table(std::ostream& h, const Json& metrics) {
  std::size_t rows = 0;
  h << "<div class=\"wide\"><table><tr><th>rank</th>";
  for (const auto& [m, r] : metrics.items()) {
    const Json rk = r.value("ranking", Json());
    const std::string u = text(rk, "units") == "1" ? "1" : shown_of(r).unit;
    h << "<th>" << escape(m) << "<br><small>by " << escape(text(rk, "by")) << " [" << escape(u)
      << "]</small></th>";
    rows = std::max(rows, rk.value("factors", Json::array()).size());
  }
  h << "</tr>\n";
  for (std::size_t i = 0; i < rows; ++i) {
    h << "<tr><td>" << i + 1 << "</td>";
    for (const auto& [m, r] : metrics.items()) {
      const Json rk = r.value("ranking", Json());
      const double f = text(rk, "units") == "1" ? 1.0 : shown_of(r).factor;
      const Json fs = rk.value("factors", Json::array());
      const Json e = i < fs.size() ? fs[i] : Json();
      h << "<td class=\"t\">";
      if (e.is_object())
        h << escape(short_key(text(e, "factor"))) << " "
          << with_interval(e.value("value", Json()), e.value("interval", Json()), f);
      h << "</td>";
    }
    h << "</tr>\n";
  }
  h << "</table></div>\n";
}

/// The rankings of the metrics that have one, a table per metrics_per_table of them.
void rankings(std::ostream& h, const Json& metrics) {
  Json chunk = Json::object();
  for (const auto& [m, r] : metrics.items()) {
    if (!r.is_object() || !r.contains("ranking") || !r["ranking"].is_object()) continue;
    chunk[m] = r;
    if (chunk.size() == metrics_per_table) {
      ranking_table(h, chunk);
      chunk = Json::object();
    }
  }
  if (!chunk.empty()) ranking_table(h, chunk);
}

std::string where(const Json& grid) {
  std::string out;
  for (const auto& [k, v] : grid.items())
    out += (out.empty() ? "" : ", ") + short_key(k) + " = " +
           (v.is_string() ? v.get<std::string>() : v.dump());
  return out;
}

}  // namespace

void write_answers(std::ostream& h, const fs::path& dir) {
  const fs::path file = dir / "analysis" / "analysis.json";
  if (!fs::is_regular_file(file)) {
    if (fs::is_regular_file(dir / "design.json"))
      h << "<h2>Answers</h2>\n<p>No analysis yet: <code>rodend analyze " << escape(dir.string())
        << "</code> computes each metric's spread, exceedance "
        << "probabilities and the factors' ranking, then <code>rodend report</code> shows them "
        << "here.</p>\n";
    return;
  }
  std::ifstream in(file);
  const Json doc = Json::parse(in, nullptr, false);
  if (doc.is_discarded() || !doc.contains("groups") || !doc["groups"].is_array()) {
    h << "<h2>Answers</h2>\n<p>" << escape(file.string()) << " is not readable JSON.</p>\n";
    return;
  }
  // the level as rodend analyze prints it: 99.9 %, never rounded up to 100 %; with
  // --bootstrap 0 the bootstrap intervals (std, ranking, a Morris spread) are absent
  char level[32];
  std::snprintf(level, sizeof level, "%.10g %%", num(doc.value("confidence", Json())) * 100);
  std::string levels = std::string(level) + " intervals in brackets";
  if (num(doc.value("bootstrap", Json())) == 0)
    levels += " (no intervals from a bootstrap: bootstrap 0)";
  h << "<h2 id=\"answers\">Answers</h2>\n";
  std::size_t k = 0;
  for (const Json& g : doc["groups"]) {
    if (k++ == max_groups) {
      h << "<p>" << doc["groups"].size() - max_groups << " more grid point(s): see "
        << escape(file.string()) << ".</p>\n";
      break;
    }
    const std::string at = where(g.value("grid", Json::object()));
    if (!at.empty()) h << "<h3>At " << escape(at) << "</h3>\n";
    const Json metrics = g.value("metrics", Json::object());
    spread_table(h, metrics, levels);
    rankings(h, metrics);
  }
}

}  // namespace rodend::report
