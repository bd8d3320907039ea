// Studies: a JSON file naming a scene, parameter overrides, a grid over parameters and
// integrator settings, time settings and the signals to record. A single case is a study with
// no grid. Every case is resolved and validated before anything runs.
//
// The scene may itself be a grid axis (key "scene", values scene names; then the top-level
// "scene" key is absent). Each case resolves its own scene's defaults and preset; a study-level
// or grid parameter key applies to the cases whose scene has it, and a key that no scene of the
// study has is an error (a typo is caught). Recorded signals: "all" is each scene's own list; a
// list of names records each where the case's scene provides it, and a name no scene provides
// is an error.
//
// The loader is sweep/study/, one stage per file (read, --set overrides, check keys, the grid and
// a sampled design, the scene axis, the signals, each scene's base draft, presets, resolve),
// listed at the top of its private header sweep/study/loader.hpp.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <iterator>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/integrator.hpp"
#include "core/params.hpp"
#include "core/signals.hpp"
#include "sweep/design.hpp"
#include "sweep/metrics.hpp"
#include "sweep/sensors.hpp"

namespace rodend {

/// Wear evolution (study key "wear_evolution"): a case becomes a loop of duty
/// cycles. Each update simulates one duty cycle (the whole run, time.end) on the worn surfaces
/// so far, scales its wear maps by the cycles the update stands for, and adds them; it stops at
/// a clearance or backlash limit, at max_cycles or after max_updates.
struct WearEvolutionSettings {
  bool enabled = false;
  double cycles_per_update = 1e4;  ///< duty cycles one update stands for [1]
  /// adaptive rule: an update stands for fewer cycles when its deepest depth change would
  /// exceed this [m]; 0 = fixed cycles_per_update
  double max_depth_change = 0.0;
  double max_cycles = 1e8;       ///< stop after this many cycles [1]
  double clearance_limit = 0.0;  ///< axial clearance at which the joint is worn out [m]; 0: none
  double backlash_limit = 0.0;   ///< surface backlash at which it is worn out [rad]; 0: none
  long max_updates = 1000;       ///< bound on the number of updates [1]
};

/// Storage of the sampled histories in the case files (study key "output"; README "Studies").
/// Neither changes what is simulated: the compression is lossless, so it does not enter the
/// case id (files written at different levels read the same and may be mixed in one study);
/// the precision changes the stored values, so float32 enters the id (a study resumed with
/// another precision reruns its cases instead of mixing 32- and 64-bit files; float64, the
/// default, leaves the ids of existing studies unchanged).
#define RODEND_CHOICE_ENUM HistoryPrecision
#define RODEND_CHOICE_FILE "sweep/history_precisions.def"
#include "core/choice.hpp"
struct OutputSettings {
  /// deflate level of the histories' chunks (libdeflate levels 1-12; 0 = stored uncompressed).
  /// Default 0, by measurement on studies/bench-32.json (bench/README.md): the histories are
  /// smooth doubles whose low bytes are noise, so level 1 shrinks them only 1.6x for 7.6x the
  /// write cost (a third of a case's instructions), and higher levels gain 1-2 % more;
  /// float32 halves them for nothing.
  int compression_level = 0;
  HistoryPrecision history_precision = HistoryPrecision::float64;
};

/// One fully resolved case of a study.
struct CaseSpec {
  std::string id;                     ///< 16 hex digits: FNV-1a 64 of canonical() (see case_id)
  long index = 0;                     ///< position in the expanded grid, 0-based
  Json coordinates = Json::object();  ///< grid key -> value for this case (empty without a grid)
  std::string scene;
  ParameterSet parameters;  ///< defaults plus study overrides plus grid values
  IntegratorSettings integrator;
  TimeSettings time;
  HealthLimits health;
  MetricsSettings metrics;
  std::vector<SignalId> signals;  ///< recorded signals, catalogue order, time first
  WearEvolutionSettings wear_evolution;
  OutputSettings output;   ///< how its histories are stored (the study's)
  SensorSettings sensors;  ///< what instruments record (sweep/sensors.hpp; none by default)
  /// its point of the study's sampled design ("design.sample"; -1 without a design): part of
  /// the id, so that two design points drawn alike (a discrete factor) stay two cases
  long design_sample = -1;

  /// The canonical resolved description: scene, every parameter value, recorded signals and
  /// the settings of sweep/settings.def as its `id` column says (integrator, time, health,
  /// metrics; the wear evolution only when enabled; history_precision only when float32). Its
  /// compact dump (sorted keys, shortest round-trip floats) is hashed into the id.
  Json canonical() const;
};

/// The cases of a study (memory flat in the number of cases). A grid is held
/// as what rebuilds a case from its index (the base drafts, the axes, one 64-bit id per case),
/// and each case is resolved when it is asked for: operator[] returns a fresh CaseSpec by value,
/// which the caller drops when done. Cases given explicitly (a hand-built study) are held as
/// they are.
class CaseList {
 public:
  /// Resolves case i of the grid (its id included).
  using Resolver = std::function<CaseSpec(std::size_t)>;
  CaseList() = default;
  CaseList(std::initializer_list<CaseSpec> cases) : held_(cases) {}
  explicit CaseList(std::vector<CaseSpec> cases) : held_(std::move(cases)) {}
  CaseList(std::size_t count, std::shared_ptr<const Resolver> resolve)
      : count_(count), resolve_(std::move(resolve)) {}

  /// What `rodend run --dry-run` prints of a case: its index, id, method, end time and grid
  /// coordinates.
  struct Row {
    long index = 0;
    std::string id;
    IntegratorMethod method{};
    double end_s = 0.0;
    Json coordinates;
  };
  /// Rows of a grid without resolving its cases, when its axes set neither the method nor the
  /// end time (the work per row is what is printed).
  using RowResolver = std::function<Row(std::size_t)>;
  void set_rows(std::shared_ptr<const RowResolver> rows) { rows_ = std::move(rows); }
  /// The row of case i.
  Row row(std::size_t i) const {
    if (rows_) return (*rows_)(i);
    const CaseSpec c = (*this)[i];
    return {c.index, c.id, c.integrator.method, c.time.end, c.coordinates};
  }

  std::size_t size() const { return resolve_ ? count_ : held_.size(); }
  bool empty() const { return size() == 0; }
  /// Case i, resolved now (a grid) or copied (held cases).
  CaseSpec operator[](std::size_t i) const { return resolve_ ? (*resolve_)(i) : held_[i]; }
  CaseSpec at(std::size_t i) const {
    if (i >= size()) throw std::out_of_range("case index " + std::to_string(i));
    return (*this)[i];
  }
  CaseSpec front() const { return at(0); }
  void clear() {
    held_.clear();
    resolve_.reset();
    rows_.reset();
    count_ = 0;
  }
  /// Resolved cases this list holds: 0 for a grid, whatever its size (the memory test).
  std::size_t resident() const { return held_.size(); }

  class iterator {
   public:
    using iterator_category = std::input_iterator_tag;
    using value_type = CaseSpec;
    using difference_type = std::ptrdiff_t;
    using pointer = void;
    using reference = CaseSpec;
    iterator(const CaseList* list, std::size_t i) : list_(list), i_(i) {}
    CaseSpec operator*() const { return (*list_)[i_]; }
    iterator& operator++() {
      ++i_;
      return *this;
    }
    bool operator==(const iterator& o) const { return i_ == o.i_; }
    bool operator!=(const iterator& o) const { return i_ != o.i_; }

   private:
    const CaseList* list_;
    std::size_t i_;
  };
  iterator begin() const { return {this, 0}; }
  iterator end() const { return {this, size()}; }

 private:
  std::vector<CaseSpec> held_;
  std::size_t count_ = 0;
  std::shared_ptr<const Resolver> resolve_;
  std::shared_ptr<const RowResolver> rows_;
};

/// Most cases a study may have (README "Studies"): a grid above it is refused at load.
inline constexpr std::size_t kMaxStudyCases = 10'000'000;

/// A loaded study.
struct Study {
  std::filesystem::path file;  ///< the study file
  std::string name;            ///< "name" key, else the file stem
  std::string description;
  std::string scene;  ///< "scene" key; empty when the scene is a grid axis
  /// every scene the study runs, in order of first use: {scene}, or the values of the grid
  /// axis "scene" (kinematic and full-system runs side by side in one study)
  std::vector<std::string> scenes;
  std::filesystem::path output_dir;    ///< "output" (or "output.directory"), else results/<name>
  OutputSettings output;               ///< "output.compression_level", ".history_precision"
  std::vector<std::string> axis_keys;  ///< grid coordinate keys, in axis order
  CaseList cases;                      ///< resolved one at a time from the grid (see CaseList)
  /// the sampled design ("design" key; docs/uncertainty.md), else null; its points are the
  /// last axis: axis_keys end with "design.sample" and the factors' keys
  std::shared_ptr<const Design> design;
  std::vector<std::string> design_units;  ///< each factor's SI unit, in factor order
  /// the profile files the cases read (sweep/profile.hpp; docs/inputs.md): [{"file",
  /// "resolved_path", "content_fnv1a64", "column", ...}], written to profiles.json
  Json profiles = Json::array();
  Json source;  ///< the study file as parsed, with the --set overrides applied
  std::vector<std::string> overrides;  ///< the --set key=value overrides, in order
  /// where a study without an "output" key writes (--results-root), for the resume command
  std::filesystem::path results_root = "results";
};

/// One setting of a study section (integrator, time, health, metrics, wear_evolution, output):
/// a line of sweep/settings.def, the list the loader reads and writes settings with;
/// `rodend schema` describes the sections from it.
struct StudyField {
  std::string section, name;
  std::string type;  ///< JSON type: "number", "integer" or "string"
  std::string unit;  ///< SI unit ("1" when dimensionless, "" for strings)
  std::string description;
  std::vector<std::string> choices;  ///< the allowed strings (empty: any)
  /// bounds the loader checks on reading (null: none checked there; integrator and time
  /// settings are checked together once a case is resolved); minimum excluded when
  /// exclusive_minimum
  Json minimum, maximum;
  bool exclusive_minimum = false;
  /// the default (null: none of its own: the integrator's is the scene's balanced preset, the
  /// time keys are required, the preset and the output directory have none)
  Json default_value;
};
/// Every setting of the sections, in the loader's order (settings.def).
std::vector<StudyField> study_fields();
/// The top-level keys of a study file.
const std::vector<std::string>& study_keys();

/// Applies `--set key.path=value` overrides (value: JSON, or else taken as a string) to a
/// parsed study document before parse_study: each replaces the value at its key path (a
/// parameter written nested or dotted is replaced wherever it was). A key path that no study
/// has, or a value of the wrong type, throws InputError naming `file`, the key and what was
/// expected. Returns the document with the overrides applied.
Json apply_overrides(Json doc, const std::vector<std::string>& overrides,
                     const std::filesystem::path& file);

/// FNV-1a 64-bit hash of a string, as 16 lowercase hex digits.
std::string fnv1a64_hex(std::string_view text);
/// The id of a case: hash of canonical().dump().
std::string case_id(const CaseSpec& c);

/// Reads, expands and validates a study. `results_root` is where studies without an "output"
/// key write (results/ of the working directory by default). Throws InputError naming the
/// file, the key path and, for a grid, the case. The file must be a regular file of at most
/// 16 MiB; duplicate keys and NUL characters are refused.
Study load_study(const std::filesystem::path& file,
                 const std::filesystem::path& results_root = "results",
                 const std::vector<std::string>& overrides = {});
/// The same from the file's text (what load_study does after reading the file): NUL bytes,
/// JSON syntax, duplicate keys, then parse_study.
Study parse_study_text(const std::string& text, const std::filesystem::path& file,
                       const std::filesystem::path& results_root = "results",
                       const std::vector<std::string>& overrides = {});
/// The same from an already parsed document; `file` is used in messages and for the name.
/// `overrides`: the --set texts already applied to `doc`, named in the provenance of the
/// parameters they set (their source "set"; the study's own "study", "grid", "design").
Study parse_study(const Json& doc, const std::filesystem::path& file,
                  const std::filesystem::path& results_root = "results",
                  const std::vector<std::string>& overrides = {});

}  // namespace rodend
