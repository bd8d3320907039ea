// parse_study: the loader's stages in their order (listed in sweep/study/loader.hpp).
#include <algorithm>
#include <memory>

#include "sweep/profile.hpp"
#include "sweep/study/loader.hpp"

namespace rodend {
namespace fs = std::filesystem;
using namespace study_detail;

namespace {

/// Name, description and where the results go.
void read_identity(Study& study, const Json& doc, const fs::path& file,
                   const fs::path& results_root) {
  study.file = file;
  study.source = doc;
  study.name = doc.contains("name") ? need_string(doc["name"], "name") : file.stem().string();
  if (study.name.empty() || study.name.find('/') != std::string::npos || study.name == "." ||
      study.name == "..")
    throw InputError("name", "expected a non-empty name without '/'");
  study.description =
      doc.contains("description") ? need_string(doc["description"], "description") : "";
  study.output_dir = results_root / study.name;
  study.results_root = results_root;
  if (doc.contains("output")) parse_output(doc["output"], study);
}

}  // namespace

Study parse_study(const Json& doc, const fs::path& file, const fs::path& results_root,
                  const std::vector<std::string>& overrides) {
  try {
    check_document(doc);
    Study study;
    read_identity(study, doc, file, results_root);
    auto grid = std::make_shared<Grid>();
    grid->origins.file = file.string();
    for (const std::string& o : overrides)
      grid->origins.set.emplace_back(o.substr(0, o.find('=')), o);
    grid->profiles = std::make_shared<ProfileStore>(file.parent_path());
    grid->axes = read_axes(study, doc);
    grid->scene_axis = find_scene_axis(grid->axes);
    read_scenes(study, doc, grid->axes, grid->scene_axis);
    const bool several = grid->scene_axis.axis >= 0;
    if (several) check_scene_axis_keys(study, doc, grid->axes);
    if (study.design) check_design_keys(*study.design, study.scenes);
    if (study.design) study.design_units = design_units(*study.design, study.scenes);
    if (!doc.contains("time"))
      throw InputError("time", "missing: {\"end\": ..., \"sample_interval\": ...}");
    build_bases(*grid, study, doc, several);
    const std::size_t total = count_cases(study, grid->axes);
    check_preset_axis(study, doc);
    grid->profiles_possible =
        profiles_possible_keys(study.axis_keys) ||
        std::any_of(grid->bases.begin(), grid->bases.end(),
                    [](const Draft& d) { return !profiles_in_use(d.parameters).empty(); });
    grid->scenes = study.scenes;
    grid->output = study.output;
    const std::shared_ptr<ProfileStore> profiles = grid->profiles;
    study.cases = index_cases(std::move(grid), total);
    study.profiles = profiles->records();
    return study;
  } catch (const InputError& e) {
    throw e.located(file.string());
  }
}

}  // namespace rodend
