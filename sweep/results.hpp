// Results on disk: one HDF5 file per case plus a summary table (HDF5 and CSV) per study.
//
// Thread-safety rule: Debian's HDF5 is built without thread safety, so every HDF5 call in the
// process is made by the functions of this file while they hold one process-wide mutex, for the
// whole open-write-close (or open-read-close) of a file. Nothing else may call HDF5.
//
// Crash-safety rule: a file appears under its final name only when complete: it is written to
// a hidden temporary name in the same directory, closed, then renamed (atomic on POSIX).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/integrator.hpp"
#include "sweep/metrics.hpp"
#include "sweep/study.hpp"

namespace rodend {

/// Layout version of the results files; bumped on any incompatible change.
inline constexpr int kResultsSchemaVersion = 1;

/// Sampled histories of one case: for each recorded signal, n_samples x width values, row-major.
struct History {
  std::vector<SignalId> signals;
  std::vector<std::vector<double>> values;  ///< one per signal
  long long samples = 0;
};

/// What one case produced, and what the summary keeps of it.
struct CaseRecord {
  std::string id;
  long index = 0;
  Json coordinates = Json::object();
  std::string status;        ///< "ok" or a RunStatus name
  std::string message;       ///< empty when ok
  double t_reached = 0.0;    ///< [s]
  double wall_time = 0.0;    ///< [s]
  long long steps_accepted = 0, steps_rejected = 0, rhs_calls = 0;
  std::string started_utc, finished_utc;  ///< ISO 8601
  MetricValues metrics{};
};

/// Process-wide provenance: rodend version and git revision, host, study file.
Json provenance(const Study& study);

/// Writes results/<study>/cases/<id>.h5 (temporary name, then rename).
void write_case_file(const std::filesystem::path& path, const CaseSpec& spec,
                     const CaseRecord& record, const History& history, const Json& provenance);

/// Reads the record of a complete case file; nullopt if the file is missing or unreadable.
std::optional<CaseRecord> read_case_record(const std::filesystem::path& path);

/// Writes summary.h5 and summary.csv in `dir` (temporary names, then rename): one row per case
/// in grid order.
void write_summary(const std::filesystem::path& dir, const Study& study,
                   const std::vector<CaseRecord>& rows, const Json& provenance);

}  // namespace rodend
