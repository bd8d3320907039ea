// Study loading (sweep/study.hpp), private to sweep/study/: what the loader's stages share.
// parse_study (parse.cpp) runs the stages in this order:
//   read.cpp         the file's text and its JSON (load_study, parse_study_text)
//   overrides.cpp    --set key=value written into the document (apply_overrides)
//   check_keys.cpp   the document as a whole: an object, shallow, no NUL, only study keys
//   grid.cpp         the grid's axes (values, linspace, logspace, zip) and the number of cases
//   design_axis.cpp  a sampled design's points as the last axis; its keys and units
//   scenes.cpp       the scene axis: the study's scenes; parameter keys checked against them
//   signals.cpp      the selection of recorded signals, each scene's list, the history size
//   bases.cpp        each scene's base draft: defaults, balanced preset, the study's sections
//   presets.cpp      integrator.preset; a preset axis stands alone
//   resolve.cpp      case i rebuilt from the grid, every case checked once, the CaseList
// with what they use:
//   settings.cpp     sweep/settings.def: the reader and writer of every setting, study_fields
//   apply.cpp        a value applied to a draft by key path; a section; the "output" key
//   json.cpp         typed JSON values, nesting depth, flattening, lists of names
//   case_id.cpp      the canonical form of a case and its id
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "core/scene.hpp"
#include "sweep/profile.hpp"
#include "sweep/study.hpp"

namespace rodend::study_detail {
namespace fs = std::filesystem;

/// Limits on what a study may ask for (README "Studies"): cases per study, nesting of the
/// document (the memory of one case's histories: signals.cpp).
constexpr std::size_t kMaxCases = kMaxStudyCases;
constexpr std::size_t kMaxDepth = 64;

// --- JSON helpers (json.cpp) --------------------------------------------------------------
/// Nesting depth of a document, without recursion (a deeply nested input must not overflow the
/// stack here, nor later in the recursive copies and dumps this file makes of it).
std::size_t nesting_depth(const Json& doc);
double need_number(const Json& v, const std::string& key);
long long need_integer(const Json& v, const std::string& key);
std::string need_string(const Json& v, const std::string& key);
const Json& need_object(const Json& v, const std::string& key);
/// "a, b or c" (quoted: "\"a\", \"b\" or \"c\"").
std::string alternatives(const std::vector<std::string>& names, bool quoted,
                         const char* last = " or ");
/// Flattens {"contact": {"clearance": 1e-4}} into {"contact.clearance": 1e-4}; dotted keys pass.
/// An empty object below `node` is kept as a value ({"clearance": {}} -> "clearance": {}).
void flatten(const Json& node, const std::string& prefix,
             std::vector<std::pair<std::string, Json>>& out);

// --- a case being resolved ----------------------------------------------------------------
/// A case being resolved: the draft every setting is applied to.
struct Draft {
  std::string scene;
  ParameterSet parameters;
  IntegratorSettings integrator;
  TimeSettings time;
  HealthLimits health;
  MetricsSettings metrics;
  WearEvolutionSettings wear_evolution;
  SensorSettings sensors;
  /// the study's storage settings: read with the same reader (parse_output), never per case
  OutputSettings output;
  /// scene-axis studies: a parameter key this case's scene does not have is skipped (the study
  /// checks that some scene of it has the key)
  bool skip_absent_parameters = false;
};

/// Where a study's values came from, for the parameters' provenance (ParameterSet::set): the
/// study file and the key paths --set gave (each with its "key=value" text; the last wins).
struct Origins {
  std::string file;
  std::vector<std::pair<std::string, std::string>> set;

  /// The --set text that gave `key` or a section holding it ("parameters", "grid"), or "".
  std::string set_text(const std::string& key) const {
    for (auto it = set.rbegin(); it != set.rend(); ++it)
      if (key == it->first || key.rfind(it->first + ".", 0) == 0) return it->second;
    return "";
  }
  /// A study-level value at `key` ("parameters.contact.clearance").
  std::pair<std::string, std::string> of_study(const std::string& key) const {
    const std::string by_set = set_text(key);
    if (!by_set.empty()) return {"set", "--set " + by_set};
    return {"study", key + " in " + file};
  }
  /// A grid or design value at `key`, from the axis at `where` ("grid[0]", "design.factors[1]").
  std::pair<std::string, std::string> of_axis(const std::string& where) const {
    const std::string section = where.substr(0, where.find_first_of(".["));
    const std::string by_set = set_text(section);
    return {section == "design" ? "design" : "grid",
            where + " in " + file + (by_set.empty() ? "" : " (as --set " + by_set + ")")};
  }
};

// --- the settings of the sections: sweep/settings.def (settings.cpp) ----------------------
/// What a setting's value must be beyond its JSON type (the `check` column of settings.def).
struct Check {
  enum class Rule { later, now, at_least, above, int_range, one_of };
  Rule rule = Rule::later;
  double lo = 0.0, hi = 0.0;
  std::string what;                  ///< int_range: what the integer is ("a deflate level")
  std::vector<std::string> choices;  ///< the allowed strings (one_of; later: for the schema)
};
/// How a setting enters the canonical form (the `id` column of settings.def).
enum class InId { in_id, in_id_as_double, not_in_id, in_id_if_not_default, special };
/// The `kind` column: the JSON type of the value.
enum class Kind { number, integer, string, choice };

/// The member a setting is, of a draft (read) or of a resolved case (written).
using Member = std::variant<double*, int*, long*, long long*, std::string*, HistoryPrecision*,
                            IntegratorMethod*, ContactOnset*>;
using ConstMember =
    std::variant<const double*, const int*, const long*, const long long*, const std::string*,
                 const HistoryPrecision*, const IntegratorMethod*, const ContactOnset*>;

/// One line of settings.def.
struct Setting {
  StudyField info;
  Check check;
  InId id = InId::special;
  Member (*of_draft)(Draft&) = nullptr;  ///< null: a special setting, read by explicit code
  ConstMember (*of_case)(const CaseSpec&) = nullptr;
};
/// Every line of settings.def, in its order: the one list the reader (apply, parse_output),
/// the writer (CaseSpec::canonical), the schema and the docs table (study_fields) use.
const std::vector<Setting>& settings();
/// The setting `section`.`name`, or null.
const Setting* find_setting(std::string_view section, std::string_view name);
/// The names of the settings of a section, in settings.def order.
std::vector<std::string> setting_names(std::string_view section);
/// The sections a case is resolved from (the keys a grid axis or --set may address):
/// parameters and every section of settings.def but output, which is the study's.
const std::vector<std::string>& case_sections();
/// Sets one setting of a draft (the reader settings.def generates); `key` is its full path.
void read_setting(Draft& d, const Setting& s, const Json& v, const std::string& key);
/// The settings of a case in its canonical form, added to `out` (settings.def, column id).
void write_settings(const CaseSpec& c, Json& out);

// --- applying values to a draft (apply.cpp) -----------------------------------------------
/// The "output" key: the results directory as a string, or an object of the output settings
/// of settings.def (directory, compression_level, history_precision).
void parse_output(const Json& v, Study& study);
/// Applies one setting addressed by a full key path (parameters.*, or a section of
/// settings.def but output). Throws InputError with that key path. `from`: where the value
/// came from (source, note), recorded in a parameter's provenance.
void apply(Draft& d, const std::string& key, const Json& v,
           const std::pair<std::string, std::string>& from = {});
/// Applies a section object ("integrator": {...}) as settings under that section.
void apply_section(Draft& d, const Json& doc, const std::string& section, const Origins& origins);

// --- the stages --------------------------------------------------------------------------

// check_keys.cpp
/// The document as a whole: an object, nested a few levels, no NUL, only study keys.
void check_document(const Json& doc);

// overrides.cpp
/// "; nearest: SECTION.KEY, expected TYPE [UNIT]": the key of `section` nearest to `rest` (a
/// parameter of any of `params` for "parameters", else a setting), or "" when there is none.
std::string nearest_key(const std::string& section, const std::string& rest,
                        const std::vector<const ParameterSet*>& params);
/// Throws the InputError of an unknown key (`key`, `section`.`rest`) of a study of `scene`: the
/// scene's name (where to see its parameters) and the nearest key, for --set and study files.
[[noreturn]] void unknown_key(const std::string& key, const std::string& section,
                              const std::string& rest, const ParameterSet& params,
                              const std::string& scene);

// grid.cpp, design_axis.cpp
struct Axis {
  std::vector<std::string> keys;          // several for a zip group
  std::vector<std::string> wheres;        // per key, its place in the study ("grid[0].zip[1]")
  std::vector<std::vector<Json>> values;  // per key, same length
  std::vector<std::string> hints;         // per key (or none): added to a case's error on it
  std::size_t size() const { return values.empty() ? 0 : values.front().size(); }
};
/// The grid's axes, each a single key or a zip group (cartesian product, last axis fastest),
/// then a sampled design's points as one more axis, the last.
std::vector<Axis> read_axes(Study& study, const Json& doc);
/// The coordinate keys, each on one axis, and the number of cases (at most kMaxCases).
std::size_t count_cases(Study& study, const std::vector<Axis>& axes);
/// The design's points as an axis: "design.sample" (the point's index) zipped with each factor's
/// values.
Axis design_axis(const Design& design);
/// Every sampled parameter is a parameter of some scene of the study (a typo is caught at its
/// place in the design).
void check_design_keys(const Design& design, const std::vector<std::string>& scenes);
/// Each design factor's SI unit: the parameter's (from the first scene that has it) or the
/// setting's.
std::vector<std::string> design_units(const Design& design, const std::vector<std::string>& scenes);

// scenes.cpp
/// Where the grid's "scene" axis is, if it has one.
struct SceneAxis {
  std::ptrdiff_t axis = -1;  // index into the axes, -1 without a scene axis
  std::size_t member = 0;    // its key's place in a zip group
};
SceneAxis find_scene_axis(const std::vector<Axis>& axes);
/// The scenes: the "scene" key, or the values of the grid axis "scene", in order of first use.
void read_scenes(Study& study, const Json& doc, const std::vector<Axis>& axes, SceneAxis sa);
/// The study's scenes, comma-separated (for messages).
std::string scene_list(const Study& study);
/// With a scene axis, a parameter key (study level or grid) applies where the case's scene has
/// it; one that no scene of the study has is an error (a typo).
void check_scene_axis_keys(const Study& study, const Json& doc, const std::vector<Axis>& axes);

// signals.cpp
/// The recorded signals: "all" (default) or a list of names.
struct SignalSelection {
  Json names;
  bool all = true;
  std::vector<bool> provided;  // per listed name: some scene of the study records it
};
SignalSelection read_signal_selection(const Json& doc);
/// The signals a scene records of the selection, in catalogue order, time first.
std::vector<SignalId> scene_signals(const Scene& scene, SignalSelection& sel, const Study& study,
                                    bool several);
/// A case's histories are held in memory until its file is written: refuse sizes that cannot be.
void check_history_size(const TimeSettings& t, const std::vector<SignalId>& signals);

// bases.cpp, presets.cpp, resolve.cpp
/// What rebuilds a case from its grid index (memory flat in the number of cases): the base draft
/// and signals of each scene, the axes, and one 64-bit id per case once validated.
struct Grid {
  std::vector<Axis> axes;
  SceneAxis scene_axis;
  std::vector<std::string> scenes;
  std::vector<Draft> bases;
  std::vector<std::vector<SignalId>> scene_signals;
  OutputSettings output;
  std::vector<std::uint64_t> ids;          // filled by the validation pass
  Origins origins;                         // the parameters' provenance
  std::shared_ptr<ProfileStore> profiles;  // the profile files, each read once (sweep/profile.hpp)
  bool profiles_possible = true;           // some case may use one (else their lookup is skipped)
};
/// Each scene's base draft and recorded signals; a scene's own error names it when the study
/// has several.
void build_bases(Grid& grid, const Study& study, const Json& doc, bool several);
/// integrator.preset (special in settings.def): a whole IntegratorSettings, the scene's own.
void read_preset(Draft& d, const Setting& s, const Json& v, const std::string& key);
/// A preset sets every integrator field, so a preset axis would silently override any other
/// integrator setting of the study (the summary would then show a method the case did not
/// run): refuse the combination.
void check_preset_axis(const Study& study, const Json& doc);
/// Builds the scene to run its own physical checks; its key paths are under "parameters.".
std::unique_ptr<Scene> build_checked(const std::string& scene, const ParameterSet& params);
/// The case ids of a grid whose axes set only parameters and design.sample (no profile, one
/// scene): the canonical text of its base cut where those values go, so that a case's id is
/// the hash of the pieces and of its values' text, exactly case_id of the case resolved
/// (tests/test_study.cpp) without building and printing its canonical form.
class IdTemplate {
 public:
  /// nullopt when the grid does not qualify (its ids then come from case_id). `base`: the
  /// base draft as a case.
  static std::optional<IdTemplate> of(const Grid& g, const CaseSpec& base);
  /// The id of the case at axis positions `pos`.
  std::uint64_t id(const Grid& g, const std::vector<std::size_t>& pos) const;

 private:
  struct Slot {
    std::size_t axis, member;
    bool integer;  // design.sample (an integer in the id), else a parameter (as a double)
  };
  std::vector<Slot> slots_;          // in the order of the text
  std::vector<std::string> pieces_;  // slots_.size() + 1
  std::uint64_t prefix_hash_ = 0;    // FNV-1a 64 state after pieces_[0]
};

/// Every case resolved and checked once (its id kept), distinct points checked to be distinct
/// cases; the CaseList resolves a case again when it is asked for (study.cases[i]).
CaseList index_cases(std::shared_ptr<Grid> grid, std::size_t total);

}  // namespace rodend::study_detail
