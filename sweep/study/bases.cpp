// Each scene's base draft (its defaults and balanced preset, then the study's sections) and
// the signals it records: what every case of that scene starts from.
#include <memory>

#include "core/presets.hpp"
#include "sweep/profile.hpp"
#include "sweep/study/loader.hpp"

namespace rodend::study_detail {

namespace {

/// A scene's own error in a study of several scenes names the scene.
[[noreturn]] void rethrow_for_scene(const InputError& e, const std::string& name, bool several) {
  if (!several) throw e;
  throw InputError(e.key_path(), e.problem() + " (scene " + name + ")");
}

/// The base draft of one scene: its defaults and balanced preset, then the study's sections.
Draft base_draft(const std::string& name, const Json& doc, bool several, const Origins& origins) {
  Draft base;
  base.scene = name;
  base.skip_absent_parameters = several;
  base.parameters = ParameterSet::defaults_for(name);  // unknown scene -> key "scene"
  base.integrator = *preset_settings(name, choice_name(kDefaultPreset));  // overridden below
  try {
    for (const std::string& section : case_sections()) apply_section(base, doc, section, origins);
    apply_section(base, doc, "sensors", origins);
  } catch (const InputError& e) {
    rethrow_for_scene(e, name, several);
  }
  if (!doc["time"].contains("end")) throw InputError("time.end", "missing: the end time [s]");
  if (!doc["time"].contains("sample_interval"))
    throw InputError("time.sample_interval", "missing: the history sample interval [s]");
  return base;
}

}  // namespace

void build_bases(Grid& grid, const Study& study, const Json& doc, bool several) {
  SignalSelection sel = read_signal_selection(doc);
  for (const std::string& name : study.scenes) {
    Draft base = base_draft(name, doc, several, grid.origins);
    std::unique_ptr<Scene> scene;  // the scene's signal list needs a built scene
    try {
      attach_profiles(base.parameters, *grid.profiles);
      scene = build_checked(name, base.parameters);
    } catch (const InputError& e) {
      rethrow_for_scene(e, name, several);
    }
    grid.scene_signals.push_back(scene_signals(*scene, sel, study, several));
    grid.bases.push_back(std::move(base));
  }
  for (std::size_t i = 0; i < sel.provided.size(); ++i)
    if (!sel.provided[i])
      throw InputError("signals[" + std::to_string(i) + "]",
                       "signal '" + sel.names[i].get<std::string>() +
                           "' is recorded by no scene of this study (" + scene_list(study) + ")");
}

}  // namespace rodend::study_detail
