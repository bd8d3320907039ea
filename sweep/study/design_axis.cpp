// A sampled design in a study (sweep/design.hpp): its points as the grid's last axis, its
// factors' parameter keys checked against the study's scenes, and their SI units.
#include <algorithm>

#include "sweep/study/loader.hpp"

namespace rodend::study_detail {

Axis design_axis(const Design& design) {
  Axis axis;
  const std::size_t n = design.points(), d = design.dims();
  axis.keys.push_back("design.sample");
  axis.wheres.push_back("design");
  axis.values.emplace_back();
  for (std::size_t p = 0; p < n; ++p) axis.values.back().emplace_back(static_cast<long>(p));
  for (std::size_t j = 0; j < d; ++j) {
    axis.keys.push_back(design.factors[j].key);
    axis.wheres.push_back(design.factors[j].where);
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
    if (std::none_of(scenes.begin(), scenes.end(), [&](const std::string& scene) {
          return ParameterSet::defaults_for(scene).has(path);
        }))
      throw InputError(f.where + ".key", "no scene of this study has parameter '" + path +
                                             "' (see `rodend params SCENE`)");
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
