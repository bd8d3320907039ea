// Reading the summary back: the table (rodend report, compare, the Python module), and the check
// and repair of a summary.csv that does not match its summary.h5.
#include <hdf5.h>
#include <libdeflate.h>

#include <algorithm>
#include <fstream>
#include <stdexcept>

#include "sweep/results.hpp"
#include "sweep/results/atomic_file.hpp"
#include "sweep/results/checksum.hpp"
#include "sweep/results/hdf5.hpp"
#include "sweep/results/summary_table.hpp"

namespace rodend {
namespace {

using namespace results_detail;

/// The kind of summary dataset `d` (from its HDF5 type) and its number of rows, into `v`.
hsize_t open_summary_column(const Context& cx, hid_t d, const std::string& what, ColumnValues& v) {
  const Handle space = cx.own(H5Dget_space(d), H5Sclose, what);
  const Handle type = cx.own(H5Dget_type(d), H5Tclose, what);
  const H5T_class_t cls = H5Tget_class(type.get());
  v.kind = cls == H5T_STRING    ? Column::Kind::text
           : cls == H5T_INTEGER ? Column::Kind::integer
                                : Column::Kind::real;
  return static_cast<hsize_t>(H5Sget_simple_extent_npoints(space.get()));
}

/// Rows [begin, begin + n) of summary dataset `d` into `v` (of the kind open_summary_column
/// gave), its old values replaced.
void read_summary_block(const Context& cx, hid_t d, const std::string& what, hsize_t begin,
                        hsize_t n, ColumnValues& v) {
  v.texts.clear();
  v.integers.assign(v.kind == Column::Kind::integer ? n : 0, 0);
  v.reals.assign(v.kind == Column::Kind::real ? n : 0, 0.0);
  if (n == 0) return;
  const Handle file_space = cx.own(H5Dget_space(d), H5Sclose, what);
  cx.ok(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, &begin, nullptr, &n, nullptr), what);
  const Handle mem_space = vector_space(cx, n);
  if (v.kind == Column::Kind::text) {
    const Handle str = utf8_string_type(cx);
    std::vector<char*> raw(n, nullptr);
    cx.ok(H5Dread(d, str.get(), mem_space.get(), file_space.get(), H5P_DEFAULT, raw.data()), what);
    for (char* p : raw) {
      v.texts.emplace_back(p ? p : "");
      H5free_memory(p);
    }
  } else if (v.kind == Column::Kind::integer) {
    cx.ok(H5Dread(d, H5T_NATIVE_LLONG, mem_space.get(), file_space.get(), H5P_DEFAULT,
                  v.integers.data()),
          what);
  } else {
    cx.ok(H5Dread(d, H5T_NATIVE_DOUBLE, mem_space.get(), file_space.get(), H5P_DEFAULT,
                  v.reals.data()),
          what);
  }
}

}  // namespace

SummaryTable read_summary(const fs::path& dir) {
  const fs::path path = dir / "summary.h5";
  if (!fs::exists(path))
    throw std::runtime_error(dir.string() + " is not a rodend study: no summary.h5");
  verify_summary_file(path);  // never hands a damaged file to HDF5
  Hdf5Lock lock;
  const Context cx(path, "cannot read summary");
  Handle file =
      cx.own(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "cannot open the file");
  SummaryTable t;
  {
    const Handle root = cx.own(H5Gopen2(file.get(), "/", H5P_DEFAULT), H5Gclose, "no root");
    if (cx.yes(H5Aexists(root.get(), "provenance_json"), "cannot look up provenance_json"))
      t.provenance = Json::parse(read_attr_string(cx, root.get(), "provenance_json"), nullptr,
                                 /*allow_exceptions=*/false);
    if (!t.provenance.is_object()) t.provenance = Json::object();
    const Handle g =
        cx.own(H5Gopen2(file.get(), "/summary", H5P_DEFAULT), H5Gclose, "no /summary group");
    const Json cols = Json::parse(read_attr_string(cx, g.get(), "columns"));
    for (const Json& c : cols) t.columns.push_back(c.get<std::string>());
    for (const std::string& name : t.columns) {
      const std::string what = "cannot read summary column " + name;
      const Handle d = cx.own(H5Dopen2(g.get(), name.c_str(), H5P_DEFAULT), H5Dclose, what);
      ColumnValues v;
      const hsize_t n = open_summary_column(cx, d.get(), what, v);
      t.rows = static_cast<std::size_t>(n);
      t.units[name] = read_dataset_unit(cx, d.get());
      read_summary_block(cx, d.get(), what, 0, n, v);
      if (v.kind == Column::Kind::text) {
        t.texts[name] = std::move(v.texts);
      } else if (v.kind == Column::Kind::integer) {
        t.integers.insert(name);
        t.numbers[name].assign(v.integers.begin(), v.integers.end());
      } else {
        t.numbers[name] = std::move(v.reals);
      }
    }
  }
  cx.ok(file.close(), "cannot close the file");
  return t;
}

bool summary_csv_matches(const fs::path& dir) {
  const fs::path h5 = dir / "summary.h5";
  std::error_code ec;
  if (!fs::is_regular_file(h5, ec)) return true;
  long long stored = -1;
  {
    try {
      verify_summary_file(h5);
    } catch (const std::exception&) {
      return true;  // damaged: left for read_summary (and repair_summary_csv) to report
    }
    Hdf5Lock lock;
    const Context cx(h5, "cannot read summary");
    try {
      Handle file = cx.own(H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose,
                           "cannot open the file");
      const Handle root = cx.own(H5Gopen2(file.get(), "/", H5P_DEFAULT), H5Gclose, "no root");
      if (!cx.yes(H5Aexists(root.get(), "summary_csv_crc32"), "cannot look up summary_csv_crc32"))
        return true;  // written before the pair was tied: nothing to compare
      stored = read_attr_int64(cx, root.get(), "summary_csv_crc32");
    } catch (const std::exception&) {
      return true;  // not readable: left for read_summary to report
    }
  }
  // the CRC-32 of summary.csv, read in blocks (never whole in memory)
  std::ifstream in(dir / "summary.csv", std::ios::binary);
  if (!in) return false;
  std::uint32_t crc = 0;
  std::vector<char> block(1 << 16);
  while (in) {
    in.read(block.data(), static_cast<std::streamsize>(block.size()));
    crc = libdeflate_crc32(crc, block.data(), static_cast<std::size_t>(in.gcount()));
  }
  return static_cast<long long>(crc) == stored;
}

bool repair_summary_csv(const fs::path& dir) {
  if (summary_csv_matches(dir)) return false;
  const fs::path h5 = dir / "summary.h5";
  if (!fs::exists(h5))
    throw std::runtime_error(dir.string() + " is not a rodend study: no summary.h5");
  // summary.csv again from summary.h5, a block of rows at a time (as write_summary wrote it),
  // kept only if its CRC-32 is the one summary.h5 was written with
  verify_summary_file(h5);
  AtomicFile csv(dir / "summary.csv", "summary file");
  std::uint32_t crc = 0;
  long long stored = -1;
  {
    Hdf5Lock lock;
    const Context cx(h5, "cannot read summary");
    Handle file =
        cx.own(H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "cannot open the file");
    {
      const Handle root = cx.own(H5Gopen2(file.get(), "/", H5P_DEFAULT), H5Gclose, "no root");
      stored = read_attr_int64(cx, root.get(), "summary_csv_crc32");
    }
    const Handle g =
        cx.own(H5Gopen2(file.get(), "/summary", H5P_DEFAULT), H5Gclose, "no /summary group");
    std::vector<std::string> names;
    for (const Json& c : Json::parse(read_attr_string(cx, g.get(), "columns")))
      names.push_back(c.get<std::string>());
    std::vector<Handle> datasets;
    std::vector<ColumnValues> values(names.size());
    hsize_t rows = 0;
    for (std::size_t j = 0; j < names.size(); ++j) {
      const std::string what = "cannot read summary column " + names[j];
      datasets.push_back(cx.own(H5Dopen2(g.get(), names[j].c_str(), H5P_DEFAULT), H5Dclose, what));
      rows = open_summary_column(cx, datasets[j].get(), what, values[j]);
    }
    std::string text = summary_csv_header(names);
    for (hsize_t begin = 0;; begin += kSummaryRowsPerBlock) {
      const hsize_t n = std::min<hsize_t>(kSummaryRowsPerBlock, rows - begin);
      for (std::size_t j = 0; j < names.size(); ++j)
        read_summary_block(cx, datasets[j].get(), "cannot read summary column " + names[j], begin,
                           n, values[j]);
      append_summary_csv_rows(values, n, text);
      crc = libdeflate_crc32(crc, text.data(), text.size());
      csv.write(bytes_of(text));
      text.clear();
      if (begin + n >= rows) break;
    }
  }
  if (static_cast<long long>(crc) != stored)
    throw std::runtime_error("cannot rewrite " + (dir / "summary.csv").string() + " from " +
                             h5.string() +
                             ": the table read back does not give the summary.csv "
                             "it was written with (summary_csv_crc32)");
  csv.finish(/*durable=*/true);
  csv.commit(/*durable=*/true);
  return true;
}

}  // namespace rodend
