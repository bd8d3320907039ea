// Studies: a JSON file naming a scene, parameter overrides, a grid over parameters and
// integrator settings, time settings and the signals to record. A single case is a study with
// no grid. Every case is resolved and validated before anything runs.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/integrator.hpp"
#include "core/params.hpp"
#include "core/signals.hpp"
#include "sweep/metrics.hpp"

namespace rodend {

/// Wear evolution (study key "wear_evolution"; issue 11): a case becomes a loop of duty
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

  /// The canonical resolved description: scene, every parameter value, integrator, time,
  /// health, metrics settings, recorded signals and (only when enabled) the wear evolution. Its
  /// compact dump (sorted keys, shortest round-trip floats) is hashed into the id.
  Json canonical() const;

 private:
  Json canonical_run(const Json& signals) const;
};

/// A loaded study.
struct Study {
  std::filesystem::path file;  ///< the study file
  std::string name;            ///< "name" key, else the file stem
  std::string description;
  std::string scene;
  std::filesystem::path output_dir;    ///< "output" key, else results/<name>
  std::vector<std::string> axis_keys;  ///< grid coordinate keys, in axis order
  std::vector<CaseSpec> cases;
  Json source;  ///< the study file as parsed, with the --set overrides applied
  std::vector<std::string> overrides;  ///< the --set key=value overrides, in order
};

/// One setting of a study section (integrator, time, health, metrics, wear_evolution), from the
/// list the loader applies settings with; `rodend schema` describes the sections from it.
struct StudyField {
  std::string section, name;
  std::string type;  ///< JSON type: "number", "integer" or "string"
  std::string unit;  ///< SI unit ("1" when dimensionless, "" for strings)
  std::string description;
  std::vector<std::string> choices;  ///< the allowed strings (empty: any)
};
/// Every setting of the sections, in the loader's order.
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
/// file, the key path and, for a grid, the case.
Study load_study(const std::filesystem::path& file,
                 const std::filesystem::path& results_root = "results",
                 const std::vector<std::string>& overrides = {});
/// The same from an already parsed document; `file` is used in messages and for the name.
Study parse_study(const Json& doc, const std::filesystem::path& file,
                  const std::filesystem::path& results_root = "results");

}  // namespace rodend
