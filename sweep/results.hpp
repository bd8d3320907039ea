// Results on disk: one HDF5 file per case plus a summary table (HDF5 and CSV) per study.
//
// Thread-safety rule: every HDF5 call in the process is made by the functions of sweep/results/
// while they hold one process-wide mutex (Hdf5Lock), for the whole open-write-close (or
// open-read-close) of a file. (Debian's HDF5 is thread-safe, but through one global lock of its
// own, so HDF5 work is serial either way.) Nothing else may call HDF5. The expensive part of
// writing a case file, compressing its histories, runs before the lock in the calling thread
// (sweep/results/chunks.hpp).
//
// Crash-safety rule: a file appears under its final name only when complete: it is written to
// a hidden temporary name in the same directory, closed, then renamed (atomic on POSIX;
// sweep/results/atomic_file.hpp, the one writer of every results file). A case file carries a
// checksum of its bytes (verify_case_file), checked before it is accepted.
//
// The rooms of sweep/results/ (this header is their public face):
//   lock.cpp, hdf5_handles.cpp  the HDF5 lock; handles, errors, attributes (hdf5.hpp)
//   atomic_file.cpp             the atomic writer; WriteFailureInjection
//   checksum.cpp                the checksum header: written, verified
//   memory_file.cpp             case files built in memory; sink_driver.cpp: summary.h5 streamed
//   chunks.cpp                  history chunks encoded off the lock; /signals
//   case_file.cpp               write_case_file; case_reader.cpp: records and signals read back
//   case_from_template.cpp      case files patched from a template built once per shape (issue
//                               33): case_template.cpp (bytes), template_driver.cpp (HDF5)
//   summary_table.cpp           the summary's columns and CSV text; summary.cpp writes it,
//                               summary_read.cpp reads (and repairs) it
//   spool.cpp                   RecordSpool; text.cpp: shortest_decimal, utc_now, provenance
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/integrator.hpp"
#include "sweep/metrics.hpp"
#include "sweep/study.hpp"

namespace rodend {

/// Layout version of the results files; bumped on any incompatible change. 2: CF `units` and
/// `long_name` attributes (1: `unit`, `description`), netCDF dimension scales (time, case_index).
inline constexpr int kResultsSchemaVersion = 2;
/// The oldest layout the readers (resume, merge, compare) still accept.
inline constexpr int kOldestReadableSchemaVersion = 1;

/// A per-case array that is not a time history (wear maps, wear-evolution histories): written
/// as dataset `group/name` with its unit and description as attributes.
struct CaseArray {
  std::string group, name, unit, description;
  std::vector<std::size_t> dims;  ///< row-major
  std::vector<double> values;
  /// netCDF dimension name of each axis (empty: none attached). An axis named after a 1-D
  /// array of the same group has that array as its coordinate (dimension scale); otherwise the
  /// dimension is created without a variable.
  std::vector<std::string> dim_names = {};
};

/// Sampled histories of one case: for each recorded signal, n_samples x width values, row-major.
struct History {
  std::vector<SignalId> signals;
  std::vector<std::vector<double>> values;  ///< one per signal
  long long samples = 0;
  std::vector<CaseArray> arrays;  ///< wear maps and the like (docs/results.md)
};

/// The types and places of the case record's fields (sweep/case_record.def).
enum class RecordType { text, integer, real, json, features, run_status };
enum class RecordPlace { identity, run, file };
/// The C++ type of each RecordType (the member types of CaseRecord).
using record_text = std::string;
using record_integer = long long;
using record_real = double;
using record_json = Json;             ///< an object unless set
using record_features = Features;     ///< stored as a JSON array of names
using record_run_status = RunStatus;  ///< a choice (core/choice.hpp), stored as its name
inline record_text record_default_text() {
  return {};
}
inline record_integer record_default_integer() {
  return 0;
}
inline record_real record_default_real() {
  return 0.0;
}
inline record_json record_default_json() {
  return Json::object();
}
inline record_features record_default_features() {
  return {};
}
inline record_run_status record_default_run_status() {
  return RunStatus::ok;
}

/// One field of the case record: a line of sweep/case_record.def.
struct RecordFieldSpec {
  std::string_view member, name, unit, description;
  RecordType type;
  RecordPlace place;
};
/// The fields of the case record, in catalogue order.
std::span<const RecordFieldSpec> record_catalogue();

/// What one case produced, and what the summary keeps of it: the fields of
/// sweep/case_record.def, then the metrics (sweep/metrics.def).
struct CaseRecord {
#define RODEND_RECORD_FIELD(member, type, place, name, unit, description) \
  record_##type member = record_default_##type();
#include "sweep/case_record.def"
#undef RODEND_RECORD_FIELD
  MetricValues metrics{};
};

/// The stored text of a json, features or choice field (a case file attribute, a summary cell,
/// the spool, the Python dictionary): compact JSON; features as the array of their names; a
/// choice (the run status) as its name.
std::string record_field_text(const Json& v);
std::string record_field_text(const Features& v);
template <Choice E>
std::string record_field_text(E v) {
  return std::string(choice_name(v));
}
/// A json, features or choice field back from its stored text; throws std::runtime_error when it
/// is not JSON of that kind (unknown feature names are dropped: a newer rodend's features), or
/// not one of the choice's names (naming the ones allowed).
void record_field_from_text(const std::string& text, Json& v);
void record_field_from_text(const std::string& text, Features& v);
template <Choice E>
void record_field_from_text(const std::string& text, E& v) {
  const std::optional<E> choice = choice_from_name<E>(text);
  if (!choice)
    throw std::runtime_error("unknown name \"" + text + "\"; expected " + choice_alternatives<E>());
  v = *choice;
}

/// Calls f(spec, value) for each field of `r` (a CaseRecord, const or not), in catalogue order.
template <class Record, class F>
void for_each_record_field(Record& r, F&& f) {
  const auto cat = record_catalogue();
  std::size_t i = 0;
#define RODEND_RECORD_FIELD(member, type, place, name, unit, description) f(cat[i++], r.member);
#include "sweep/case_record.def"
#undef RODEND_RECORD_FIELD
}
/// The record as bytes (every field of sweep/case_record.def, then the metrics), led by its
/// size [bytes] as a uint32: the spool's rows and the MPI runner's messages. decode_record reads
/// `n` bytes so written; throws std::runtime_error when they are short or malformed.
std::string encode_record(const CaseRecord& r);
CaseRecord decode_record(const char* p, std::size_t n);

/// A summary table read back from summary.h5.
struct SummaryTable {
  std::vector<std::string> columns;                       ///< in table order
  std::map<std::string, std::vector<double>> numbers;     ///< numeric columns
  std::map<std::string, std::vector<std::string>> texts;  ///< text columns
  std::map<std::string, std::string> units;               ///< unit of each column
  std::set<std::string> integers;  ///< the numeric columns stored as integers
  std::size_t rows = 0;
  Json provenance = Json::object();  ///< the root attribute provenance_json (rodend report)
  bool is_text(const std::string& c) const { return texts.count(c) > 0; }
};
/// Reads `dir/summary.h5`; throws std::runtime_error naming the file when it is missing or not
/// a rodend summary.
SummaryTable read_summary(const std::filesystem::path& dir);

/// One recorded signal of a case file: samples x width values, row-major.
struct SignalData {
  std::vector<double> values;
  std::size_t samples = 0;
  int width = 1;
  std::string unit;
  double at(std::size_t i, int c = 0) const {
    return values[i * static_cast<std::size_t>(width) + static_cast<std::size_t>(c)];
  }
};
/// Names of the signals in a case file (sorted); throws std::runtime_error.
std::vector<std::string> list_signals(const std::filesystem::path& case_file);
/// One signal of a case file; throws std::runtime_error.
SignalData read_signal(const std::filesystem::path& case_file, const std::string& name);

/// The shortest decimal that reads back as the same double, in the form Python's repr and
/// nlohmann::json use: fixed notation for exponents -4 to 15 (2e-4 is "0.0002", not
/// "0.00020000000000000001"), else d.ddde±XX ("1e-17"); "nan", "inf", "-inf".
std::string shortest_decimal(double v);

/// The current UTC time, ISO 8601 ("2024-05-01T10:00:00Z"): the time stamps of case records
/// and the provenance.
std::string utc_now();
/// Process-wide provenance: rodend version and git revision, host, study file.
Json provenance(const Study& study);

/// Initialises HDF5 for the calling thread (the library once, its error printing switched off
/// in this thread) while memory is still free: call it on the main thread before a parallel
/// region and first thing in each thread of it (HDF5 crashes when these allocations fail).
/// Throws std::bad_alloc when the memory HDF5 needs cannot be had.
void prepare_results_io();

/// How many times this process has entered HDF5 (taken the process-wide lock around every HDF5
/// call): the serial section of a sweep, in count (RODEND_LOCK_STATS=1 prints its time).
long long hdf5_lock_count();

/// Writes results/<study>/cases/<id>.h5 (temporary name, then rename). With uncompressed
/// histories (output.compression_level 0), HDF5 builds a case file once per shape of case (a
/// template, sweep/results/case_template.hpp) and the other cases of that shape are written without
/// HDF5, outside its lock; RODEND_CASE_TEMPLATES=0 in the environment has HDF5 build every one
/// (to compare the two).
void write_case_file(const std::filesystem::path& path, const CaseSpec& spec,
                     const CaseRecord& record, const History& history, const Json& provenance);

/// A results file whose bytes are damaged (CorruptFile: a case file or summary.h5;
/// CorruptCaseFile: a case file): its content does not match the checksum in its header,
/// it is shorter or longer than written, or it is not a case file at all (no checksum header
/// and not HDF5; an HDF5 file of an older rodend, without a checksum, that HDF5 cannot read).
class CorruptFile : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};
class CorruptCaseFile : public CorruptFile {
 public:
  using CorruptFile::CorruptFile;
};
/// A symbolic link under a case file's name: never read or written through (a resume moves the
/// link aside, a merge refuses it); what() names it and its target.
class LinkedCaseFile : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Checks the checksum of a case file (docs/signals.md, "Checksum"): true when it holds, false
/// for a file written before checksums (no user block: nothing to check). Throws
/// CorruptCaseFile naming the file and the damage, std::runtime_error when it cannot be read.
bool verify_case_file(const std::filesystem::path& case_file);

/// Checks the checksum of summary.h5 (the same header as a case file's): true when it holds,
/// false for a summary written before checksums. Throws CorruptFile naming the file and the
/// damage, std::runtime_error when it cannot be read.
bool verify_summary_file(const std::filesystem::path& summary_h5);

/// Writes `text` to `path` atomically: a fresh file (O_EXCL, O_NOFOLLOW) under an unpredictable
/// temporary name in the same directory, then renamed over `path` (flushed to the disk when
/// `durable`). A link under `path` is replaced, never followed. Throws std::runtime_error
/// naming `what` and `path`; `path` is then left as it was.
void write_text_file_atomically(const std::filesystem::path& path, const std::string& what,
                                const std::string& text, bool durable);

/// Reads the record of a complete case file; nullopt if the file is missing, unreadable or
/// corrupt.
std::optional<CaseRecord> read_case_record(const std::filesystem::path& path);
/// The same, but only a missing file gives nullopt: a file (or anything else) under that name
/// that cannot be read as a rodend case file throws naming it and the reason: CorruptCaseFile
/// when its bytes are damaged (verify_case_file), LinkedCaseFile for a symbolic link (not
/// followed), std::runtime_error otherwise (not a regular file, no permission, another schema
/// version, locked by another process).
std::optional<CaseRecord> read_case_record_strict(const std::filesystem::path& path);

/// The case records of a run, the rows of its summary, kept on the disk instead of in memory
/// (memory flat in the number of cases): an anonymous file in the results
/// directory (unlinked as soon as it is created, so that nothing is left behind, even by a
/// crash) to which each record is appended when its case completes, in any order, and an
/// offset per case. Read back in case order (slot order), whichever order the records came in.
/// Thread-safe.
class RecordSpool {
 public:
  /// The spool of the summary in `dir` (its file is there too; messages name dir/summary.h5);
  /// `slots`: the number of cases (slot = case position in the study).
  RecordSpool(const std::filesystem::path& dir, std::size_t slots);
  ~RecordSpool();
  RecordSpool(const RecordSpool&) = delete;
  RecordSpool& operator=(const RecordSpool&) = delete;

  /// Stores the record of case `slot` (a later put for the same slot replaces it). Throws
  /// std::runtime_error "cannot write summary file <dir>/summary.h5: ..." when the disk is full.
  void put(std::size_t slot, const CaseRecord& record);
  /// Records stored (the summary's rows), and of them those whose status is not "ok".
  std::size_t size() const;
  std::size_t failed() const;
  /// Rows [begin, end) (the records in slot order) into `out`, its old content replaced.
  void read(std::size_t begin, std::size_t end, std::vector<CaseRecord>& out) const;
  /// The grid coordinate keys to which some record gives a value that is not a number: their
  /// summary columns are text, the others numeric.
  std::set<std::string> text_coordinates() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Writes summary.h5 and summary.csv in `dir` (temporary names, then rename): one row per
/// record of `rows`, in slot (grid) order. Both are written as a stream, a block of rows at a
/// time (HDF5 writes summary.h5 to the disk as it goes): the memory it takes does not grow with
/// the number of rows. summary.h5 is renamed into place first, with the CRC-32 of the
/// summary.csv that follows it (root attribute summary_csv_crc32), then summary.csv; each is
/// flushed to the disk.
void write_summary(const std::filesystem::path& dir, const Study& study, const RecordSpool& rows,
                   const Json& provenance);

/// True unless `dir` holds a summary.h5 whose summary_csv_crc32 does not match summary.csv
/// (missing, or of another run: a run stopped between the two renames of write_summary).
bool summary_csv_matches(const std::filesystem::path& dir);
/// When summary.csv does not match summary.h5, rewrites it from summary.h5 (the same bytes
/// write_summary wrote, checked against summary_csv_crc32) and returns true.
bool repair_summary_csv(const std::filesystem::path& dir);

/// Testing: while one exists, the writes of results files (case files, summaries) fail with
/// ENOSPC once `bytes` bytes have been written in total, as on a full disk.
class WriteFailureInjection {
 public:
  explicit WriteFailureInjection(long long bytes);
  ~WriteFailureInjection();
  WriteFailureInjection(const WriteFailureInjection&) = delete;
  WriteFailureInjection& operator=(const WriteFailureInjection&) = delete;
};

}  // namespace rodend
