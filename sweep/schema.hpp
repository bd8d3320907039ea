// `rodend schema`: a JSON Schema (draft 2020-12) of study files, generated from the lists the
// loader itself uses (study_keys, study_fields, the scene, signal and parameter catalogues), so
// an editor can check and complete a study and the shipped studies are checked against it.
#pragma once

#include <string>

#include "core/params.hpp"

namespace rodend {

/// The JSON Schema of a study file.
Json study_schema();
/// The settings of the study sections (sweep/settings.def) as a Markdown table: key path, JSON
/// type (and choices), unit, default, description (`rodend schema --markdown`; docs/studies.md).
std::string study_settings_markdown();

}  // namespace rodend
