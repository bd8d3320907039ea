// Profiles from data files in studies (docs/inputs.md "Profiles from data").
// A parameter group `<input>.profile` (motion, command, hinge) names a file when its input's
// selector (`<input>.shape` or `<input>.kind`) is "profile". The study reads each file once,
// into immutable data every case naming it shares (ParameterSet::attach); the file's content,
// not its path, enters the case id.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/params.hpp"
#include "core/scenes/profile.hpp"

namespace rodend {

/// Largest profile file read [bytes] (a day at 1 kHz of two columns is about 4 GB; a flight
/// or rig sequence of hours at 100 Hz is a few MB): anything larger is refused before reading.
inline constexpr std::uintmax_t kMaxProfileBytes = 256u << 20;

/// What a profile file must hold (read_profile_file).
struct ProfileRequest {
  std::string file;                ///< as the study names it (in messages)
  std::filesystem::path resolved;  ///< where it is read from
  std::string time_column, column;
  std::string unit;  ///< the value column's unit (the time column's is s)
};

/// Reads one profile file, CSV or HDF5 (told apart by the HDF5 signature in its first bytes),
/// and computes its pchip slopes. Throws InputError (no key path) whose message names the file
/// and the CSV line or HDF5 dataset element at fault: an unreadable file, a missing column or
/// unit, a unit other than the expected, a value that is not a finite number, a time that does
/// not increase, fewer than two samples.
ProfileData read_profile_file(const ProfileRequest& r);

/// The profile files a study has read: each (file, time column, value column) once. Safe to
/// use from several threads (the study validates large grids in parallel).
class ProfileStore {
 public:
  /// Relative paths are read from `folder` (the study file's folder).
  explicit ProfileStore(std::filesystem::path folder) : folder_(std::move(folder)) {}

  /// The profile the parameters name under `prefix` (e.g. "motion.profile"): the file at
  /// `<prefix>.file`, its `<prefix>.time_column` in seconds and its `<prefix>.column` in that
  /// leaf's unit. Throws InputError at key "parameters.<prefix>.file" naming the file and the
  /// line (CSV) or element (HDF5) at fault.
  std::shared_ptr<const ProfileData> load(const ParameterSet& p, const std::string& prefix);
  /// Every profile read, as recorded in the results: [{"file", "resolved_path",
  /// "content_fnv1a64", "column", "unit", "samples", "start_s", "end_s"}].
  Json records() const;

 private:
  std::filesystem::path folder_;
  mutable std::mutex mutex_;
  std::map<std::string, std::shared_ptr<const ProfileData>> loaded_;
};

/// The `<input>.profile` prefixes of the parameters whose input is a profile (its `shape` or
/// `kind` is "profile").
std::vector<std::string> profiles_in_use(const ParameterSet& p);

/// Whether an axis of a grid (its keys) may bring a profile into use: it sets a profile key, an
/// input's selector (`*.shape`, `*.kind`) or the scene. When it cannot, and no base draft uses
/// one, the grid's cases skip the profile lookups (fast validation of large grids).
bool profiles_possible_keys(const std::vector<std::string>& axis_keys);

/// Reads (through `store`) and attaches the data of every profile in use.
void attach_profiles(ParameterSet& p, ProfileStore& store);

/// Refuses a profile in use whose past_end is "error" and whose last sample comes before
/// `t_end` (the run's end): InputError at its file key.
void check_profiles_cover(const ParameterSet& p, double t_end);

/// The parameter values as they enter a case id: a profile in use by its file's content
/// ("fnv1a64:<hash>") instead of its path; the keys of profiles not in use left out (so the
/// ids of cases without profiles are those they had before profiles existed).
Json identity_values(const ParameterSet& p);

/// A profile as recorded in the results (ProfileStore::records).
Json profile_record(const ProfileData& d);

}  // namespace rodend
