// Parameter sets: a tree of named values, each with its unit and provenance.
//
// A scene's defaults (core/scenes/<scene>.params.json and the part files it names,
// core/scenes/parts/*.part.json, embedded in the binary; composed by core/scene_parameters.hpp)
// are leaves of the form
//   {"value": 0.2, "unit": "kg", "source": "thesis", "note": "thesis §3.3"}
// with source one of "thesis", "assumed" (the note gives the reason) or "derived" (the note
// says from what): the menu core/parameter_sources.def. String leaves may list their allowed
// "choices" (in the files, a "catalogue" of the code instead). Overrides address leaves by dotted
// key path
// ("contact.clearance") and must match the leaf's type.
#pragma once

#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "core/choice.hpp"
#include "core/errors.hpp"
#include "core/math.hpp"

namespace rodend {

/// Where a parameter's value comes from (a leaf's "source").
#define RODEND_CHOICE_ENUM ParameterSource
#define RODEND_CHOICE_FILE "core/parameter_sources.def"
#include "core/choice.hpp"

using Json = nlohmann::json;
struct ProfileData;  // core/profile_data.hpp

class ParameterSet {
 public:
  ParameterSet() = default;
  /// Parses a parameter tree; `origin` names it in error messages. Checks every leaf's form.
  static ParameterSet from_json(const Json& tree, const std::string& origin);
  /// The embedded defaults of a scene: its scene file composed with its parts (defined with the
  /// scene catalogue, core/scene_catalog.cpp: the parameters know no scene).
  static ParameterSet defaults_for(std::string_view scene);

  /// Replaces the value at `path`. Throws InputError (key path `path`) for an unknown key or a
  /// value of the wrong type or outside the leaf's choices. With a `source` (where the value
  /// came from: "study", "grid", "design", "set"), the leaf's "source" and "note" become it and
  /// the note, and the replaced default's value, source and note are kept under "default".
  void set(const std::string& path, const Json& value, const std::string& source = "",
           const std::string& note = "");
  bool has(const std::string& path) const;

  double number(const std::string& path) const;
  std::string text(const std::string& path) const;
  bool flag(const std::string& path) const;
  Vec3 vec3(const std::string& path) const;

  /// All leaves as {"dotted.path": value}, keys sorted.
  Json values() const;
  /// All leaves as {"dotted.path": {"value", "unit", "source", "note"}}.
  Json leaves() const;
  /// Every leaf path, sorted.
  std::vector<std::string> paths() const;
  /// The unit of a leaf ("" if none).
  std::string unit(const std::string& path) const;

  /// Attaches the data a string leaf names (a profile's `file`), read by the study that
  /// resolved these parameters: immutable, and shared by every copy of the set (every case that
  /// names the file). Setting the leaf again detaches it. leaves() then gives the leaf the
  /// file's resolved path and content hash.
  void attach(const std::string& path, std::shared_ptr<const ProfileData> data);
  /// The data attached at `path`, or null.
  std::shared_ptr<const ProfileData> attached(const std::string& path) const;

 private:
  const Json& leaf(const std::string& path) const;
  Json tree_;
  std::map<std::string, std::shared_ptr<const ProfileData>> attached_;
};

}  // namespace rodend
