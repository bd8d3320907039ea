// The grid: its axes (a key with values, linspace or logspace; zip groups), a sampled design's
// points as the last axis (design_axis.cpp), the coordinate keys and the number of cases.
#include <algorithm>
#include <cmath>
#include <memory>

#include "sweep/study/loader.hpp"

namespace rodend::study_detail {

namespace {

std::vector<Json> expand_values(const Json& a, const std::string& where) {
  std::vector<Json> out;
  const int forms = a.contains("values") + a.contains("linspace") + a.contains("logspace");
  if (forms != 1)
    throw InputError(where, "expected exactly one of \"values\", \"linspace\" or \"logspace\"");
  if (a.contains("values")) {
    const Json& v = a["values"];
    if (!v.is_array() || v.empty())
      throw InputError(where + ".values", "expected a non-empty array");
    for (const Json& e : v) out.push_back(e);
    return out;
  }
  const bool log = a.contains("logspace");
  const std::string key = where + (log ? ".logspace" : ".linspace");
  const Json& g = a[log ? "logspace" : "linspace"];
  if (!g.is_array() || g.size() != 3) throw InputError(key, "expected [start, stop, count]");
  const double start = need_number(g[0], key + "[0]");
  const double stop = need_number(g[1], key + "[1]");
  const long long n = need_integer(g[2], key + "[2]");
  if (n < 1 || n > static_cast<long long>(kMaxCases))
    throw InputError(key + "[2]", "expected a count in [1, 1e7]");
  if (log && !(start > 0.0 && stop > 0.0))
    throw InputError(key, "expected start > 0 and stop > 0 (the values, not exponents)");
  for (long long i = 0; i < n; ++i) {
    const double f = n == 1 ? 0.0 : static_cast<double>(i) / static_cast<double>(n - 1);
    double v = log ? std::exp(std::log(start) + f * (std::log(stop) - std::log(start)))
                   : start + f * (stop - start);
    if (i == n - 1) v = stop;  // end points exact
    if (i == 0) v = start;
    if (!std::isfinite(v))
      throw InputError(key,
                       "generates a value that is not a finite number; expected finite "
                       "start and stop");
    out.emplace_back(v);
  }
  return out;
}

Axis parse_axis(const Json& a, const std::string& where) {
  need_object(a, where);
  Axis axis;
  if (a.contains("zip")) {
    for (auto it = a.begin(); it != a.end(); ++it)
      if (it.key() != "zip") throw InputError(where + "." + it.key(), "unknown key in a zip group");
    const Json& members = a["zip"];
    if (!members.is_array() || members.empty())
      throw InputError(where + ".zip", "expected a non-empty array of axes");
    for (std::size_t i = 0; i < members.size(); ++i) {
      const std::string w = where + ".zip[" + std::to_string(i) + "]";
      if (members[i].is_object() && members[i].contains("zip"))
        throw InputError(w, "a zip group cannot contain another zip");
      Axis m = parse_axis(members[i], w);
      if (!axis.keys.empty() && m.size() != axis.size())
        throw InputError(w, "zip members must have the same length: " + std::to_string(m.size()) +
                                " vs " + std::to_string(axis.size()));
      axis.keys.push_back(m.keys[0]);
      axis.wheres.push_back(m.wheres[0]);
      axis.values.push_back(m.values[0]);
    }
    return axis;
  }
  for (auto it = a.begin(); it != a.end(); ++it)
    if (it.key() != "key" && it.key() != "values" && it.key() != "linspace" &&
        it.key() != "logspace")
      throw InputError(where + "." + it.key(),
                       "unknown key in a grid axis; expected key with values, linspace or "
                       "logspace, or zip");
  if (!a.contains("key"))
    throw InputError(where + ".key", "missing: the key path this axis varies");
  axis.keys.push_back(need_string(a["key"], where + ".key"));
  if (axis.keys.back().empty())
    throw InputError(where + ".key", "expected a key path such as parameters.contact.clearance");
  axis.wheres.push_back(where);
  axis.values.push_back(expand_values(a, where));
  return axis;
}

}  // namespace

std::vector<Axis> read_axes(Study& study, const Json& doc) {
  std::vector<Axis> axes;
  if (doc.contains("grid")) {
    const Json& g = doc["grid"];
    if (!g.is_array()) throw InputError("grid", "expected an array of axes");
    for (std::size_t i = 0; i < g.size(); ++i)
      axes.push_back(parse_axis(g[i], "grid[" + std::to_string(i) + "]"));
  }
  if (doc.contains("design")) {
    std::size_t grid_points = 1;
    for (const Axis& a : axes) grid_points *= std::max<std::size_t>(a.size(), 1);
    auto design = std::make_shared<Design>(
        parse_design(doc["design"], kMaxCases / std::max<std::size_t>(grid_points, 1),
                     study.file.parent_path()));
    axes.push_back(design_axis(*design));
    study.design = std::move(design);
  }
  return axes;
}

std::size_t count_cases(Study& study, const std::vector<Axis>& axes) {
  std::size_t total = 1;
  for (const Axis& a : axes) {
    for (const std::string& k : a.keys) {
      if (std::find(study.axis_keys.begin(), study.axis_keys.end(), k) != study.axis_keys.end())
        throw InputError("grid", "key '" + k + "' appears on more than one axis");
      study.axis_keys.push_back(k);
    }
    total *= a.size();
    if (total > kMaxCases)
      throw InputError("grid",
                       "more than 1e7 cases, the limit of a study (each case is "
                       "validated before anything runs): split the study into several");
  }
  return total;
}

}  // namespace rodend::study_detail
