// A sampled design in a study (sweep/design.hpp): its points as the grid's last axis, its
// factors' parameter keys checked against the study's scenes, and their SI units.
#include <algorithm>

#include "sweep/study/loader.hpp"

namespace rodend::study_detail {

namespace {

/// What to say when a factor's draw is a value its parameter refuses: an unbounded distribution
/// reaches values a bounded one would not.
std::string draw_hint(const Design& d, const DesignFactor& f) {
  if (!design_method_info(d.method).distributions)
    return f.key + " takes the values of the file " + d.file +
           " (row design.sample + 1 of its points): correct them there";
  const DistributionKind k = f.distribution.kind;
  if (k == DistributionKind::normal)
    return f.where +
           " is a normal distribution, which draws values of either sign and any size: "
           "for a quantity with limits use truncated-normal (with lower and upper) or, "
           "for a positive one, lognormal";
  if (!distribution_info(k).bounded)
    return f.where + " is a " + std::string(to_string(k)) +
           " distribution, unbounded: truncated-normal keeps the draws within lower and upper";
  return f.where + " draws values the parameter refuses: narrow its bounds";
}

}  // namespace

Axis design_axis(const Design& design) {
  Axis axis;
  const std::size_t n = design.points(), d = design.dims();
  axis.keys.push_back("design.sample");
  axis.wheres.push_back("design");
  axis.hints.emplace_back();
  axis.values.emplace_back();
  for (std::size_t p = 0; p < n; ++p) axis.values.back().emplace_back(static_cast<long>(p));
  for (std::size_t j = 0; j < d; ++j) {
    axis.keys.push_back(design.factors[j].key);
    axis.wheres.push_back(design.factors[j].where);
    axis.hints.push_back(draw_hint(design, design.factors[j]));
    std::vector<Json> column;
    column.reserve(n);
    for (std::size_t p = 0; p < n; ++p) column.emplace_back(design.values[p * d + j]);
    axis.values.push_back(std::move(column));
  }
  return axis;
}

void check_design_keys(const Design& design, const std::vector<std::string>& scenes) {
  for (const DesignFactor& f : design.factors) {
    if (f.key.rfind("parameters.", 0) != 0) continue;  // settings: checked by apply()
    const std::string path = f.key.substr(11);
    std::vector<ParameterSet> defaults;
    for (const std::string& scene : scenes) defaults.push_back(ParameterSet::defaults_for(scene));
    if (std::none_of(defaults.begin(), defaults.end(),
                     [&](const ParameterSet& p) { return p.has(path); })) {
      std::vector<const ParameterSet*> all;
      for (const ParameterSet& p : defaults) all.push_back(&p);
      std::string names;
      for (const std::string& n : scenes) names += (names.empty() ? "" : ", ") + n;
      throw InputError(
          f.key_where,
          f.context +
              (scenes.size() == 1
                   ? "unknown parameter '" + path + "' of scene " + names
                   : "no scene of this study (" + names + ") has parameter '" + path + "'") +
              " (see `rodend params " + (scenes.size() == 1 ? names : "SCENE") + "`)" +
              nearest_key("parameters", path, all));
    }
  }
}

std::vector<std::string> design_units(const Design& design,
                                      const std::vector<std::string>& scenes) {
  std::vector<std::string> units;
  for (const DesignFactor& f : design.factors) {
    std::string unit;
    if (f.key.rfind("parameters.", 0) == 0) {
      for (const std::string& scene : scenes) {
        const ParameterSet p = ParameterSet::defaults_for(scene);
        if (p.has(f.key.substr(11))) {
          unit = p.unit(f.key.substr(11));
          break;
        }
      }
    } else {
      const auto dot = f.key.find('.');
      if (const Setting* s = find_setting(f.key.substr(0, dot), f.key.substr(dot + 1)))
        unit = s->info.unit;
    }
    units.push_back(unit);
  }
  return units;
}

}  // namespace rodend::study_detail
