// Presets in a study: integrator.preset read as a whole IntegratorSettings (the scene's own),
// and a preset axis, which sets every integrator field, refused beside another integrator
// setting. (The other preset rules: a scene's base draft starts from its balanced preset,
// bases.cpp; a preset is applied before the keys beside it, apply_section in apply.cpp; --set
// integrator.preset replaces the study's integrator settings, overrides.cpp.)
#include <algorithm>

#include "core/presets.hpp"
#include "sweep/study/loader.hpp"

namespace rodend::study_detail {

void read_preset(Draft& d, const Setting& s, const Json& v, const std::string& key) {
  const std::string name = need_string(v, key);
  const auto p = preset_settings(d.scene, name);
  if (!p)
    throw InputError(
        key, "unknown preset '" + name + "'; expected " + alternatives(s.check.choices, false));
  d.integrator = *p;
}

void check_preset_axis(const Study& study, const Json& doc) {
  const auto& keys = study.axis_keys;
  if (std::find(keys.begin(), keys.end(), "integrator.preset") == keys.end()) return;
  for (const std::string& k : keys)
    if (k != "integrator.preset" && k.rfind("integrator.", 0) == 0)
      throw InputError("grid", "axes integrator.preset and " + k +
                                   " contradict each other (a preset sets every integrator "
                                   "field); expected one of them");
  if (doc.contains("integrator"))
    for (auto it = doc["integrator"].begin(); it != doc["integrator"].end(); ++it)
      if (it.key() != "preset")
        throw InputError("integrator." + it.key(),
                         "set beside a grid axis integrator.preset, which sets every "
                         "integrator field; expected the preset axis alone, or the "
                         "setting as an axis without presets");
}

}  // namespace rodend::study_detail
