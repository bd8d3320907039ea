// Writing the summary of a study: summary.h5 and summary.csv.
//
// Summary: summary.h5 (the checksum user block, group /summary, one 1-D dataset per column with
// units (not for text) and long_name, case_index the dimension scale of the others, attribute
// columns = JSON array of the names in order; root attribute summary_csv_crc32 (int64): the CRC-32
// of the summary.csv written with it) and summary.csv (one header line, one line per case, numbers
// as the shortest decimal that reads back as the same double). Schema 1 named the
// attributes unit and description and had no dimension scales; readers accept both. All string
//
// Written as a stream (memory flat in the number of cases): the rows come from a RecordSpool on the
// disk, a block at a time, and each block goes to summary.csv and to the columns of summary.h5
// (datasets of the final size, written by hyperslabs through the sink driver) before the next is
// read: the memory it takes does not grow with the number of cases.
#include <hdf5.h>
#include <libdeflate.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <stdexcept>

#include "sweep/results.hpp"
#include "sweep/results/atomic_file.hpp"
#include "sweep/results/checksum.hpp"
#include "sweep/results/hdf5.hpp"
#include "sweep/results/sink_driver.hpp"
#include "sweep/results/summary_table.hpp"

namespace rodend {
namespace {

using namespace results_detail;

/// A summary dataset: `rows` values of the column's type, contiguous (the default layout),
/// with its units and long_name.
Handle create_summary_column(const Context& cx, hid_t group, const Column& c, hsize_t rows) {
  const std::string what = "cannot write summary column " + c.name;
  const Handle space = vector_space(cx, rows);
  const Handle str = utf8_string_type(cx);
  const hid_t file_type = c.kind == Column::Kind::text      ? str.get()
                          : c.kind == Column::Kind::integer ? H5T_STD_I64LE
                                                            : H5T_IEEE_F64LE;
  // every row is written: no fill values written first (HDF5 requires them for strings)
  const Handle dcpl = cx.own(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, what);
  if (c.kind != Column::Kind::text) cx.ok(H5Pset_fill_time(dcpl.get(), H5D_FILL_TIME_NEVER), what);
  Handle d = cx.own(H5Dcreate2(group, c.name.c_str(), file_type, space.get(), H5P_DEFAULT,
                               dcpl.get(), H5P_DEFAULT),
                    H5Dclose, what);
  attr_units(cx, d.get(), c.unit, c.description, c.kind == Column::Kind::text);
  return d;
}

/// Writes `v` (a block of rows) into rows [begin, begin + its size) of dataset `d`.
void write_summary_block(const Context& cx, hid_t d, const std::string& name, const ColumnValues& v,
                         hsize_t begin) {
  const std::string what = "cannot write summary column " + name;
  const hsize_t n = v.size();
  if (n == 0) return;
  const Handle file_space = cx.own(H5Dget_space(d), H5Sclose, what);
  cx.ok(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, &begin, nullptr, &n, nullptr), what);
  const Handle mem_space = vector_space(cx, n);
  const Handle str = utf8_string_type(cx);
  hid_t mem_type = H5T_NATIVE_DOUBLE;
  const void* data = v.reals.data();
  std::vector<const char*> ptrs;
  if (v.kind == Column::Kind::text) {
    for (const std::string& s : v.texts) ptrs.push_back(s.c_str());
    mem_type = str.get();
    data = ptrs.data();
  } else if (v.kind == Column::Kind::integer) {
    mem_type = H5T_NATIVE_LLONG;
    data = v.integers.data();
  }
  // type conversion buffers of a block's size, not HDF5's default 1 MiB each (two per write:
  // the strings' conversion and its background)
  const Handle dxpl = cx.own(H5Pcreate(H5P_DATASET_XFER), H5Pclose, what);
  cx.ok(H5Pset_buffer(dxpl.get(), std::max<std::size_t>(n * 16, 4096), nullptr, nullptr), what);
  cx.ok(H5Dwrite(d, mem_type, mem_space.get(), file_space.get(), dxpl.get(), data), what);
}

/// Writes the checksum header (checksum_header) into the user block of the summary.h5 HDF5 has
/// just written to `h5`'s temporary file: the CRC-32 of every byte after the block.
void seal_summary(AtomicFile& h5) {
  struct stat st {};
  if (::fstat(h5.fd(), &st) != 0) h5.fail_write(errno);
  const auto size = static_cast<std::size_t>(st.st_size);
  if (size < kUserBlock + sizeof kHdf5Signature)
    throw std::logic_error("summary.h5 is shorter than its user block");
  std::vector<unsigned char> buf(std::size_t{1} << 20);
  std::uint32_t crc = 0;
  for (std::size_t offset = kUserBlock; offset < size;) {
    const std::size_t n = std::min(buf.size(), size - offset);
    const ssize_t r = ::pread(h5.fd(), buf.data(), n, static_cast<off_t>(offset));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) h5.fail_write(r < 0 ? errno : EIO);
    crc = libdeflate_crc32(crc, buf.data(), static_cast<std::size_t>(r));
    offset += static_cast<std::size_t>(r);
  }
  const auto header = checksum_header(crc, size);
  if (const int err = write_all(h5.fd(), header.data(), header.size(), 0); err != 0)
    h5.fail_write(err);
}

}  // namespace

namespace {

/// The root attributes of summary.h5 (all but summary_csv_crc32, written last).
void write_summary_root(const Context& cx, hid_t g, const Study& study, const Json& prov,
                        std::size_t row_count) {
  attr_int(cx, g, "schema_version", kResultsSchemaVersion);
  attr_string(cx, g, "study_name", study.name);
  const std::string study_file = prov_text(prov, "study_file");
  attr_string(cx, g, "study_file", study_file.empty() ? study.file.string() : study_file);
  for (const char* key : {"rodend_version", "git_revision", "host"})
    attr_string(cx, g, key, prov_text(prov, key));
  attr_int64(cx, g, "case_count", static_cast<long long>(row_count));
  attr_string(cx, g, "provenance_json", prov.dump());
  attr_string(cx, g, "study_json", study.source.dump());
}

/// The rows of `rows`, a block at a time, into the columns `datasets` of summary.h5 and into
/// summary.csv (`csv`, header first); returns the CRC-32 of summary.csv. Throws as soon as the
/// sink driver has latched a failure (a full disk), not after the remaining rows.
std::uint32_t write_summary_rows(const Context& cx, const std::vector<Column>& cols,
                                 const std::vector<Handle>& datasets, const RecordSpool& rows,
                                 const SinkTarget& sink, AtomicFile& csv) {
  const std::size_t row_count = rows.size();
  std::vector<std::string> names;
  for (const Column& c : cols) names.push_back(c.name);
  std::vector<CaseRecord> block;
  std::vector<ColumnValues> values(cols.size());
  std::string text = summary_csv_header(names);
  std::uint32_t crc = 0;
  for (std::size_t begin = 0;; begin += kSummaryRowsPerBlock) {
    const std::size_t end = std::min(row_count, begin + kSummaryRowsPerBlock);
    if (end > begin) {
      rows.read(begin, end, block);
      if (block.size() != end - begin)
        throw std::logic_error("the summary's rows gave " + std::to_string(block.size()) +
                               " records for " + std::to_string(end - begin) + " rows");
      for (std::size_t j = 0; j < cols.size(); ++j) {
        column_values(cols[j], block, values[j]);
        write_summary_block(cx, datasets[j].get(), cols[j].name, values[j], begin);
      }
      append_summary_csv_rows(values, end - begin, text);
      if (sink.error != 0) throw std::runtime_error("the sink driver latched a failure");
    }
    crc = libdeflate_crc32(crc, text.data(), text.size());
    csv.write(bytes_of(text));
    text.clear();
    if (end >= row_count) break;
  }
  return crc;
}

/// The column names (attribute `columns`) and case_index as the netCDF dimension of every
/// column: the table is one call away,
/// xarray.open_dataset(path, engine="h5netcdf", group="summary").to_dataframe()
void write_summary_dimensions(const Context& cx, hid_t summary, const std::vector<Column>& cols,
                              const std::vector<Handle>& datasets) {
  std::vector<std::string> names;
  for (const Column& c : cols) names.push_back(c.name);
  attr_string(cx, summary, "columns", Json(names).dump());
  std::vector<std::pair<hid_t, unsigned>> columns;
  hid_t index = H5I_INVALID_HID;
  for (std::size_t j = 0; j < cols.size(); ++j)
    if (cols[j].name == "case_index")
      index = datasets[j].get();
    else
      columns.emplace_back(datasets[j].get(), 0u);
  attach_scale(cx, index, "case_index", columns);
}

/// summary.h5 through the sink driver into `h5`'s temporary file, and summary.csv into `csv`.
/// Call under Hdf5Lock.
void write_summary_files(const Context& cx, const fs::path& h5_path, const Study& study,
                         const std::vector<Column>& cols, const RecordSpool& rows, const Json& prov,
                         SinkTarget& sink, AtomicFile& csv) {
  const Handle fapl = sink_access(cx, sink);
  // the user block: the checksum header, written once HDF5 is done (seal_summary)
  const Handle fcpl = cx.own(H5Pcreate(H5P_FILE_CREATE), H5Pclose, "cannot create the file");
  cx.ok(H5Pset_userblock(fcpl.get(), kUserBlock), "cannot create the file");
  Handle file = cx.own(H5Fcreate(h5_path.c_str(), H5F_ACC_TRUNC, fcpl.get(), fapl.get()), H5Fclose,
                       "cannot create the file");
  Handle root = cx.own(H5Gopen2(file.get(), "/", H5P_DEFAULT), H5Gclose, "no root");
  write_summary_root(cx, root.get(), study, prov, rows.size());
  Handle summary = create_group(cx, root.get(), "summary", /*track_link_order=*/true);
  std::vector<Handle> datasets;
  for (const Column& c : cols)
    datasets.push_back(create_summary_column(cx, summary.get(), c, rows.size()));
  const std::uint32_t crc = write_summary_rows(cx, cols, datasets, rows, sink, csv);
  write_summary_dimensions(cx, summary.get(), cols, datasets);
  // the summary.csv of the same run (summary_csv_matches, repair_summary_csv)
  attr_int64(cx, root.get(), "summary_csv_crc32", static_cast<long long>(crc));
  for (Handle& d : datasets) cx.ok(d.close(), "cannot close a summary column");
  cx.ok(summary.close(), "cannot close the summary group");
  cx.ok(root.close(), "cannot close the root group");
  // nothing of the file is open now, so this is the real close (the last flush, the
  // superblock), whose result counts
  cx.ok(file.close(), "cannot close the file");
}

}  // namespace

void write_summary(const fs::path& dir, const Study& study, const RecordSpool& rows,
                   const Json& prov) {
  const std::vector<Column> cols = summary_columns(study, rows.text_coordinates());
  // summary.csv and summary.h5 go to their temporary files block of rows by block of rows;
  // summary.h5 carries the CRC-32 of summary.csv and is renamed first, and only then
  // summary.csv: a run stopped between the two renames leaves a summary.csv that does not
  // match, which the next run (or merge) rewrites from summary.h5 (repair_summary_csv)
  AtomicFile csv(dir / "summary.csv", "summary file");
  const fs::path h5_path = dir / "summary.h5";
  AtomicFile h5(h5_path, "summary file");
  SinkTarget sink;
  sink.fd = h5.fd();
  try {
    Hdf5Lock lock;  // held for the whole create-write-close
    const Context cx(h5_path, "cannot write summary file");
    write_summary_files(cx, h5_path, study, cols, rows, prov, sink, csv);
  } catch (const std::exception&) {
    if (sink.error != 0) h5.fail_write(sink.error);  // the cause of what HDF5 reported
    throw;
  }
  if (sink.error != 0) h5.fail_write(sink.error);
  seal_summary(h5);
  csv.finish(/*durable=*/true);
  h5.finish(/*durable=*/true);
  h5.commit(/*durable=*/true);
  csv.commit(/*durable=*/true);
}

}  // namespace rodend
