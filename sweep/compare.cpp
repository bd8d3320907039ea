#include "sweep/compare.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <ostream>
#include <set>
#include <sstream>

#include "core/errors.hpp"
#include "core/params.hpp"
#include "sweep/metrics.hpp"
#include "sweep/results.hpp"

namespace rodend {
namespace fs = std::filesystem;

namespace {

Tolerance read_tolerance(const Json& j, const Tolerance& base, const std::string& key,
                         const std::string& file) {
  if (!j.is_object()) throw InputError(key, "expected {\"rel\": r, \"abs\": a}", file);
  Tolerance t = base;
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (it.key() != "rel" && it.key() != "abs")
      throw InputError(key + "." + it.key(), "unknown key; expected rel or abs", file);
    if (!it->is_number() || !(it->get<double>() >= 0.0))
      throw InputError(key + "." + it.key(), "expected a number >= 0", file);
    (it.key() == "rel" ? t.rel : t.abs) = it->get<double>();
  }
  return t;
}

bool close_enough(double a, double b, const Tolerance& t, double scale) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  if (std::isinf(a) || std::isinf(b)) return a == b;
  return std::abs(a - b) <= t.abs + t.rel * scale;
}

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

/// Collects the differences of one comparison, with a cap on lines per case.
class Report {
 public:
  Report(std::ostream& out, int cap) : out_(out), cap_(cap) {}
  void diff(const std::string& where, const std::string& what) {
    ++count_;
    int& n = per_case_[where];
    if (++n <= cap_)
      out_ << "  DIFF " << where << ": " << what << "\n";
    else if (n == cap_ + 1)
      out_ << "  DIFF " << where << ": ... (more differences not shown)\n";
  }
  int count() const { return count_; }

 private:
  std::ostream& out_;
  int cap_;
  int count_ = 0;
  std::map<std::string, int> per_case_;
};

/// Compares one signal of one case: pointwise up to `t_event`, envelope after it.
void compare_signal(const std::string& where, const std::string& name, const SignalData& a,
                    const SignalData& b, const SignalData& ta, double t_event,
                    const CompareSettings& s, Report& rep) {
  if (a.width != b.width || a.samples != b.samples) {
    rep.diff(where, "signal " + name + " has shape " + std::to_string(b.samples) + "x" +
                        std::to_string(b.width) + ", reference " + std::to_string(a.samples) + "x" +
                        std::to_string(a.width));
    return;
  }
  for (int c = 0; c < a.width; ++c) {
    double lo = INFINITY, hi = -INFINITY;
    for (std::size_t i = 0; i < a.samples; ++i) {
      lo = std::min(lo, a.at(i, c));
      hi = std::max(hi, a.at(i, c));
    }
    const double range = std::isfinite(hi - lo) ? hi - lo : 0.0;
    const double band = s.history.abs + s.history.rel * range;
    const std::string label = name + (a.width > 1 ? "[" + std::to_string(c) + "]" : "");
    std::size_t j0 = 0;  // envelope window start
    for (std::size_t i = 0; i < a.samples; ++i) {
      const double t = ta.at(i), va = a.at(i, c), vb = b.at(i, c);
      if (!(t > t_event)) {
        if (!close_enough(va, vb, s.history, range)) {
          rep.diff(where, label + " at t = " + fmt(t) + " s: " + fmt(vb) + ", reference " +
                              fmt(va) + " (pointwise before the first impact; band " + fmt(band) +
                              ")");
          break;
        }
        continue;
      }
      // after the first impact: within the reference's envelope over [t - shift, t + shift]
      while (j0 < a.samples && ta.at(j0) < t - s.time_shift) ++j0;
      double wlo = INFINITY, whi = -INFINITY;
      for (std::size_t j = j0; j < a.samples && ta.at(j) <= t + s.time_shift; ++j) {
        wlo = std::min(wlo, a.at(j, c));
        whi = std::max(whi, a.at(j, c));
      }
      if (!(vb >= wlo - band && vb <= whi + band)) {
        rep.diff(where, label + " at t = " + fmt(t) + " s: " + fmt(vb) +
                            " outside the reference envelope [" + fmt(wlo) + ", " + fmt(whi) +
                            "] +- " + fmt(band) + " (time shift " + fmt(s.time_shift) + " s)");
        break;
      }
    }
  }
}

std::map<std::string, std::size_t> rows_by_id(const SummaryTable& t) {
  std::map<std::string, std::size_t> m;
  const auto it = t.texts.find("case_id");
  if (it == t.texts.end()) throw std::runtime_error("summary has no case_id column");
  for (std::size_t i = 0; i < it->second.size(); ++i) m[it->second[i]] = i;
  return m;
}

/// The grid-coordinate columns of a summary: those between case_index and status.
std::vector<std::string> grid_columns(const SummaryTable& t) {
  const auto first = std::find(t.columns.begin(), t.columns.end(), "case_index");
  const auto last = std::find(t.columns.begin(), t.columns.end(), "status");
  if (first == t.columns.end() || last == t.columns.end() || last < first) return {};
  return {first + 1, last};
}

/// Row i of `a` and row j of `b` are the same grid point of the same grid: equal case_index,
/// the same coordinate columns and equal coordinates.
bool same_grid_point(const SummaryTable& a, std::size_t i, const SummaryTable& b, std::size_t j) {
  if (!a.numbers.count("case_index") || !b.numbers.count("case_index")) return false;
  if (a.numbers.at("case_index")[i] != b.numbers.at("case_index")[j]) return false;
  const auto cols = grid_columns(a);
  if (cols != grid_columns(b)) return false;
  for (const std::string& c : cols) {
    if (a.is_text(c) != b.is_text(c)) return false;
    if (a.is_text(c) ? a.texts.at(c)[i] != b.texts.at(c)[j]
                     : a.numbers.at(c)[i] != b.numbers.at(c)[j])
      return false;
  }
  return true;
}

}  // namespace

CompareSettings load_tolerances(const fs::path& file) {
  // the study loader's checks: a regular file (not a FIFO, which would block), readable
  std::error_code ec;
  const fs::file_status st = fs::status(file, ec);
  if (ec || !fs::exists(st))
    throw InputError(
        "", "cannot open the tolerance file: " + (ec ? ec.message() : std::string("no such file")),
        file.string());
  if (!fs::is_regular_file(st))
    throw InputError("",
                     "is not a regular file (a directory, device, FIFO or socket); expected "
                     "a tolerance file (JSON)",
                     file.string());
  std::ifstream in(file);
  if (!in) throw InputError("", "cannot open the tolerance file", file.string());
  Json doc;
  try {
    doc = Json::parse(in);
  } catch (const Json::parse_error& e) {
    throw InputError("", std::string("JSON syntax error: ") + e.what(), file.string());
  }
  const std::string f = file.string();
  if (!doc.is_object()) throw InputError("", "expected a JSON object", f);
  CompareSettings s;
  for (auto it = doc.begin(); it != doc.end(); ++it) {
    if (it.key() == "metrics") {
      if (!it->is_object()) throw InputError("metrics", "expected an object", f);
      if (it->contains("default"))
        s.metric_default = read_tolerance((*it)["default"], s.metric_default, "metrics.default", f);
      for (auto m = it->begin(); m != it->end(); ++m) {
        if (m.key() == "default") continue;
        const auto cat = metric_catalogue();
        if (std::none_of(cat.begin(), cat.end(),
                         [&](const MetricSpec& sp) { return sp.name == m.key(); }))
          throw InputError("metrics." + m.key(), "unknown metric name (see `rodend metrics`)", f);
        s.metric[m.key()] = read_tolerance(*m, s.metric_default, "metrics." + m.key(), f);
      }
    } else if (it.key() == "histories") {
      if (!it->is_object()) throw InputError("histories", "expected an object", f);
      Json tol = Json::object();
      for (auto h = it->begin(); h != it->end(); ++h) {
        if (h.key() == "time_shift") {
          if (!h->is_number() || !(h->get<double>() >= 0.0))
            throw InputError("histories.time_shift", "expected a time >= 0 [s]", f);
          s.time_shift = h->get<double>();
        } else {
          tol[h.key()] = *h;
        }
      }
      s.history = read_tolerance(tol, s.history, "histories", f);
    } else {
      throw InputError(it.key(), "unknown key; expected metrics or histories", f);
    }
  }
  return s;
}

namespace {

/// A case of the reference (row i of A) and its counterpart (row j of B).
struct Pair {
  std::string id_a, id_b;
  std::size_t i, j;
};

/// Cases are paired by id. A case whose id changed but that sits at the same grid point
/// (same case_index and coordinates) is paired with its counterpart and compared, with a note:
/// the id hashes every resolved parameter, so a parameter added to a scene since the
/// reference (whose default keeps the old behaviour) changes every id and nothing else.
/// Whether the results moved is then for the metrics to say.
std::vector<Pair> pair_cases(const SummaryTable& ra, const SummaryTable& rb, std::ostream& out,
                             Report& rep) {
  const auto ia = rows_by_id(ra), ib = rows_by_id(rb);
  std::vector<Pair> pairs;
  std::set<std::string> paired_b;
  for (const auto& [id, i] : ia)
    if (ib.count(id)) {
      pairs.push_back({id, id, i, ib.at(id)});
      paired_b.insert(id);
    }
  for (const auto& [id, i] : ia) {
    if (ib.count(id)) continue;
    bool found = false;
    for (const auto& [id_b, j] : ib) {
      if (ia.count(id_b) || paired_b.count(id_b) || !same_grid_point(ra, i, rb, j)) continue;
      out << "  NOTE case " << id << " paired with case " << id_b
          << " (same grid point; the resolved description differs, e.g. a parameter was added)\n";
      pairs.push_back({id, id_b, i, j});
      paired_b.insert(id_b);
      found = true;
      break;
    }
    if (!found) rep.diff("case " + id, "missing (present in the reference)");
  }
  for (const auto& [id, row] : ib)
    if (!paired_b.count(id)) rep.diff("case " + id, "extra (absent from the reference)");
  return pairs;
}

/// The status and the metric columns of a pair: every catalogue metric of the reference.
void compare_metrics(const SummaryTable& ra, const SummaryTable& rb, const Pair& p,
                     const CompareSettings& s, Report& rep) {
  const std::size_t i = p.i, j = p.j;
  const std::string where = "case " + p.id_a;
  const std::string sa = ra.texts.at("status")[i], sb = rb.texts.at("status")[j];
  if (sa != sb) rep.diff(where, "status " + sb + ", reference " + sa);
  for (const MetricSpec& m : metric_catalogue()) {
    const std::string name(m.name);
    const bool in_a = ra.numbers.count(name), in_b = rb.numbers.count(name);
    if (!in_a && in_b) continue;  // newer than the reference (noted once)
    if (!in_a || !in_b) {
      rep.diff(where, "metric " + name + (in_a ? " missing" : " extra"));
      continue;
    }
    const double va = ra.numbers.at(name)[i], vb = rb.numbers.at(name)[j];
    const auto t = s.metric.count(name) ? s.metric.at(name) : s.metric_default;
    if (!close_enough(va, vb, t, std::max(std::abs(va), std::abs(vb))))
      rep.diff(where, "metric " + name + " = " + fmt(vb) + " [" + std::string(m.unit) +
                          "], reference " + fmt(va) + " (rel " + fmt(t.rel) + ", abs " +
                          fmt(t.abs) + ")");
  }
}

/// The histories of a pair: the case files intact and their own, the same signals and sample
/// times, each signal within tolerance.
void compare_histories(const fs::path& a, const fs::path& b, const SummaryTable& ra, const Pair& p,
                       const CompareSettings& s, Report& rep) {
  const std::string where = "case " + p.id_a;
  const fs::path fa = a / "cases" / (p.id_a + ".h5"), fb = b / "cases" / (p.id_b + ".h5");
  if (!fs::exists(fa) || !fs::exists(fb)) {
    rep.diff(where,
             std::string("case file missing in ") + (fs::exists(fa) ? "B" : "the reference"));
    return;
  }
  // each file intact and its case's own (not another case's file copied over it)
  for (const fs::path& f : {fa, fb}) read_case_record_strict(f);
  const auto sig_a = list_signals(fa), sig_b = list_signals(fb);
  const std::set<std::string> set_a(sig_a.begin(), sig_a.end()), set_b(sig_b.begin(), sig_b.end());
  for (const auto& n : set_a)
    if (!set_b.count(n)) rep.diff(where, "signal " + n + " missing");
  for (const auto& n : set_b)
    if (!set_a.count(n)) rep.diff(where, "signal " + n + " extra");
  if (!set_a.count("time") || !set_b.count("time")) {
    rep.diff(where, "no time signal");
    return;
  }
  const SignalData ta = read_signal(fa, "time"), tb = read_signal(fb, "time");
  if (ta.values != tb.values) {
    rep.diff(where, "different sample times");
    return;
  }
  double t_event = INFINITY;
  if (ra.numbers.count("first_contact_time") &&
      std::isfinite(ra.numbers.at("first_contact_time")[p.i]))
    t_event = ra.numbers.at("first_contact_time")[p.i];
  for (const auto& n : sig_a) {
    if (n == "time" || !set_b.count(n)) continue;
    compare_signal(where, n, read_signal(fa, n), read_signal(fb, n), ta, t_event, s, rep);
  }
}

}  // namespace

int compare_studies(const fs::path& a, const fs::path& b, const CompareSettings& s,
                    std::ostream& out) {
  const SummaryTable ra = read_summary(a), rb = read_summary(b);
  Report rep(out, s.max_lines_per_case);
  out << "compare " << b.string() << " against reference " << a.string() << "\n";
  if (s.summary_only) out << "  (summaries only: histories are not compared)\n";
  const std::vector<Pair> pairs = pair_cases(ra, rb, out, rep);
  // a metric the reference lacks is newer than it and has nothing to be compared with
  for (const MetricSpec& m : metric_catalogue()) {
    const std::string name(m.name);
    if (!ra.numbers.count(name) && rb.numbers.count(name))
      out << "  NOTE metric " << name << " is not in the reference (newer than it): not compared\n";
  }
  for (const Pair& p : pairs) {
    compare_metrics(ra, rb, p, s, rep);
    if (!s.summary_only) compare_histories(a, b, ra, p, s, rep);
  }
  if (rep.count() == 0) {
    out << "equal within tolerance: " << rows_by_id(ra).size() << " case(s)\n";
    return 0;
  }
  out << rep.count() << " difference(s)\n";
  return 1;
}

}  // namespace rodend
