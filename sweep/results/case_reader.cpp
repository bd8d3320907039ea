// Reading a case file back: its record (resume, merge, compare) and its signals (compare,
// report, the Python module).
#include <hdf5.h>

#include <algorithm>
#include <limits>
#include <stdexcept>

#include "sweep/results.hpp"
#include "sweep/results/checksum.hpp"
#include "sweep/results/hdf5.hpp"

namespace rodend {
namespace {

using namespace results_detail;

/// A readable file of a layout this rodend does not read: not damage.
struct UnreadableVersion : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// One field of the case record from its root attribute (sweep/case_record.def).
void read_record_attribute(const Context& cx, hid_t g, const char* name, record_text& v) {
  v = read_attr_string(cx, g, name);
}
void read_record_attribute(const Context& cx, hid_t g, const char* name, record_integer& v) {
  v = read_attr_int64(cx, g, name);
}
void read_record_attribute(const Context& cx, hid_t g, const char* name, record_real& v) {
  v = read_attr_double(cx, g, name);
}
template <class T>  // json, features, run_status: from their text
void read_record_attribute(const Context& cx, hid_t g, const char* name, T& v) {
  const std::string text = read_attr_string(cx, g, name);
  try {
    record_field_from_text(text, v);
  } catch (const std::runtime_error& e) {
    cx.fail("attribute " + std::string(name) + ": " + e.what());
  }
}

/// The fields of the case record from the root attributes of `g`. A field the file does not
/// have (a file written before the field was added to the catalogue) keeps its default, except
/// a run status: no default is safe there (every schema wrote one, and a missing one read as
/// "ok" would pass a damaged file off as a good run).
void read_record_attributes(const Context& cx, hid_t g, CaseRecord& r) {
  for_each_record_field(r, [&](const RecordFieldSpec& f, auto& v) {
    const std::string name(f.name);
    if (cx.yes(H5Aexists(g, name.c_str()), "cannot look up attribute " + name))
      read_record_attribute(cx, g, name.c_str(), v);
    else if (f.type == RecordType::run_status)
      cx.fail("attribute " + name + " is missing (every case file records its run status)");
  });
}

CaseRecord read_case_locked(const fs::path& path) {
  const Context cx(path, "cannot read results file");
  Handle file =
      cx.own(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "cannot open the file");
  CaseRecord r;
  {
    const Handle root = cx.own(H5Gopen2(file.get(), "/", H5P_DEFAULT), H5Gclose, "no root");
    const hid_t g = root.get();
    if (const long long v = read_attr_int64(cx, g, "schema_version");
        v < kOldestReadableSchemaVersion || v > kResultsSchemaVersion)
      throw UnreadableVersion("cannot read results file " + path.string() + ": " +
                              "schema_version " + std::to_string(v) +
                              " is not readable by this rodend (it reads " +
                              std::to_string(kOldestReadableSchemaVersion) + " to " +
                              std::to_string(kResultsSchemaVersion) + ")");
    read_record_attributes(cx, g, r);
    r.metrics.fill(std::numeric_limits<double>::quiet_NaN());
    if (cx.yes(H5Lexists(g, "metrics", H5P_DEFAULT), "cannot look up /metrics")) {
      const Handle m =
          cx.own(H5Gopen2(g, "metrics", H5P_DEFAULT), H5Gclose, "cannot open /metrics");
      const auto cat = metric_catalogue();
      for (std::size_t i = 0; i < cat.size() && i < r.metrics.size(); ++i) {
        const std::string name(cat[i].name);
        if (cx.yes(H5Aexists(m.get(), name.c_str()), "cannot look up metric " + name))
          r.metrics[i] = read_attr_double(cx, m.get(), name.c_str());
      }
    }
  }
  cx.ok(file.close(), "cannot close the file");
  return r;
}

}  // namespace

std::optional<CaseRecord> read_case_record(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(fs::symlink_status(path, ec))) return std::nullopt;  // nor a link
  try {
    verify_case_file(path);
    Hdf5Lock lock;  // held for the whole open-read-close
    return read_case_locked(path);
  } catch (const std::exception&) {
    // unreadable, corrupt, or of another schema version: the caller treats it as absent
    return std::nullopt;
  }
}

std::optional<CaseRecord> read_case_record_strict(const fs::path& path) {
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(path, ec);
  if (st.type() == fs::file_type::not_found) return std::nullopt;
  if (ec) throw std::runtime_error(path.string() + ": " + ec.message());
  if (st.type() == fs::file_type::symlink) {  // never followed: it could lead anywhere
    const fs::path target = fs::read_symlink(path, ec);
    throw LinkedCaseFile(path.string() + " is a symbolic link" +
                         (ec ? std::string() : " (to " + target.string() + ")") +
                         ", not a case file rodend wrote; rodend never reads or writes through "
                         "a link");
  }
  if (!fs::is_regular_file(st)) throw std::runtime_error(path.string() + ": not a regular file");
  const bool verified = verify_case_file(path);  // outside the lock: reads the whole file
  Hdf5Lock lock;                                 // held for the whole open-read-close
  try {
    CaseRecord rec = read_case_locked(path);
    // an intact file of another case copied under this name: not this case's result
    if (rec.id != path.stem().string())
      throw std::runtime_error("cannot read results file " + path.string() + ": it holds case " +
                               rec.id + ", not " + path.stem().string() +
                               " (a case file copied or moved under another case's name)");
    return rec;
  } catch (const UnreadableVersion&) {
    throw;
  } catch (const std::exception& e) {
    // a file whose checksum holds is not damaged (opened elsewhere for writing, say); one
    // without a checksum (written before them) that HDF5 cannot read is
    if (!verified) throw CorruptCaseFile("corrupt case file " + path.string() + ": " + e.what());
    throw std::runtime_error(std::string(e.what()).rfind("cannot read", 0) == 0
                                 ? std::string(e.what())
                                 : "cannot read results file " + path.string() + ": " + e.what());
  }
}

std::vector<std::string> list_signals(const fs::path& case_file) {
  verify_case_file_once(case_file);  // never hands a damaged file to HDF5
  Hdf5Lock lock;
  const Context cx(case_file, "cannot read case file");
  Handle file = cx.own(H5Fopen(case_file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose,
                       "cannot open the file");
  std::vector<std::string> names;
  {
    const Handle g =
        cx.own(H5Gopen2(file.get(), "/signals", H5P_DEFAULT), H5Gclose, "no /signals group");
    names = group_members(cx, g.get());
  }
  cx.ok(file.close(), "cannot close the file");
  std::sort(names.begin(), names.end());
  return names;
}

SignalData read_signal(const fs::path& case_file, const std::string& name) {
  verify_case_file_once(case_file);  // never hands a damaged file to HDF5
  Hdf5Lock lock;
  const Context cx(case_file, "cannot read case file");
  Handle file = cx.own(H5Fopen(case_file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose,
                       "cannot open the file");
  SignalData s;
  {
    const std::string what = "cannot read signal " + name;
    const Handle d =
        cx.own(H5Dopen2(file.get(), ("/signals/" + name).c_str(), H5P_DEFAULT), H5Dclose, what);
    const Handle space = cx.own(H5Dget_space(d.get()), H5Sclose, what);
    const int rank = H5Sget_simple_extent_ndims(space.get());
    hsize_t dims[2] = {0, 1};
    if (rank < 1 || rank > 2 || H5Sget_simple_extent_dims(space.get(), dims, nullptr) < 0)
      cx.fail(what + ": not a 1-D or 2-D dataset");
    s.samples = static_cast<std::size_t>(dims[0]);
    s.width = rank == 2 ? static_cast<int>(dims[1]) : 1;
    s.values.resize(s.samples * static_cast<std::size_t>(s.width));
    if (!s.values.empty())
      cx.ok(H5Dread(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, s.values.data()),
            what);
    s.unit = read_dataset_unit(cx, d.get());
  }
  cx.ok(file.close(), "cannot close the file");
  return s;
}

}  // namespace rodend
