// The scene axis: a study's scenes (the "scene" key, or the values of a grid axis "scene") and,
// with several, the parameter keys checked against them.
#include <algorithm>

#include "sweep/study/loader.hpp"

namespace rodend::study_detail {

SceneAxis find_scene_axis(const std::vector<Axis>& axes) {
  for (std::size_t a = 0; a < axes.size(); ++a)
    for (std::size_t k = 0; k < axes[a].keys.size(); ++k)
      if (axes[a].keys[k] == "scene") return {static_cast<std::ptrdiff_t>(a), k};
  return {};
}

void read_scenes(Study& study, const Json& doc, const std::vector<Axis>& axes, SceneAxis sa) {
  if (sa.axis < 0) {
    if (!doc.contains("scene"))
      throw InputError("scene", "missing: which scene to run (or a grid axis \"scene\")");
    study.scene = need_string(doc["scene"], "scene");
    study.scenes = {study.scene};
    return;
  }
  const Axis& axis = axes[static_cast<std::size_t>(sa.axis)];
  if (doc.contains("scene"))
    throw InputError("scene", "the scene is also a grid axis (" + axis.wheres[sa.member] +
                                  "): give it in one place");
  const auto& values = axis.values[sa.member];
  for (std::size_t j = 0; j < values.size(); ++j) {
    const std::string where = axis.wheres[sa.member] + ".values[" + std::to_string(j) + "]";
    const std::string name = need_string(values[j], where);
    try {
      (void)ParameterSet::defaults_for(name);
    } catch (const InputError& e) {
      throw InputError(where, e.problem());
    }
    if (std::find(study.scenes.begin(), study.scenes.end(), name) == study.scenes.end())
      study.scenes.push_back(name);
  }
}

std::string scene_list(const Study& study) {
  std::string out;
  for (const std::string& n : study.scenes) out += (out.empty() ? "" : ", ") + n;
  return out;
}

void check_scene_axis_keys(const Study& study, const Json& doc, const std::vector<Axis>& axes) {
  std::vector<ParameterSet> defaults;
  for (const std::string& n : study.scenes) defaults.push_back(ParameterSet::defaults_for(n));
  std::vector<const ParameterSet*> all;
  for (const ParameterSet& p : defaults) all.push_back(&p);
  auto check_known = [&](const std::string& path, const std::string& where) {
    if (std::none_of(defaults.begin(), defaults.end(),
                     [&](const ParameterSet& p) { return p.has(path); }))
      throw InputError(where, "no scene of this study (" + scene_list(study) + ") has parameter '" +
                                  path + "' (see `rodend params SCENE`)" +
                                  nearest_key("parameters", path, all));
  };
  if (doc.contains("parameters")) {
    std::vector<std::pair<std::string, Json>> flat;
    flatten(need_object(doc["parameters"], "parameters"), "", flat);
    for (const auto& [k, v] : flat) check_known(k, "parameters." + k);
  }
  for (const Axis& a : axes)
    for (std::size_t k = 0; k < a.keys.size(); ++k)
      if (a.keys[k].rfind("parameters.", 0) == 0)
        check_known(a.keys[k].substr(11), a.wheres[k] + ".key");
}

}  // namespace rodend::study_detail
