// Writing a case file: results/<study>/cases/<id>.h5.
//
// Case file layout (stable interface, schema_version 2; 1 is still read, see summary.cpp):
//   user block   512 bytes: the checksum header (Integrity, above)
//   /            attributes: schema_version (int), case_id, case_index (int64), scene, status,
//                message, t_reached_s, wall_time_s (double), steps_accepted, steps_rejected,
//                rhs_calls (int64), started_utc, finished_utc, rodend_version, git_revision,
//                host, study_file, coordinates_json, parameters_json, case_json (strings)
//   /parameters  one attribute per resolved parameter (dotted path): double, string, int8 0/1
//                for booleans, 1-D double for arrays; units_json = {"path": "unit"}
//   /signals     one dataset per recorded signal (catalogue name): float64 (or float32 with
//                output.history_precision), (samples,) or (samples, width), chunked (4096 rows),
//                shuffle + deflate at output.compression_level (no filters at level 0; the
//                standard filters, read by any HDF5 reader); attributes units, long_name;
//                /signals/time is the dimension scale "time" of axis 0 of every signal; axis
//                1 of a width-w signal is the dimension /component<w> (netCDF dimension
//                without a variable), so netCDF tools read the file as it is
//   /metrics     one scalar double attribute per metric (catalogue name), NaN when not
//                applicable; units_json = {"name": "unit"}
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <stdexcept>
#include <string_view>

#include "sweep/results.hpp"
#include "sweep/results/atomic_file.hpp"
#include "sweep/results/case_file.hpp"
#include "sweep/results/checksum.hpp"
#include "sweep/results/chunks.hpp"
#include "sweep/results/hdf5.hpp"
#include "sweep/results/memory_file.hpp"
#include "sweep/results/template_driver.hpp"

namespace rodend::results_detail {
namespace {

// histories are copied into the file's little-endian types byte for byte
static_assert(std::endian::native == std::endian::little, "rodend writes HDF5 chunks on LE hosts");

void check_history(const fs::path& path, const History& h) {
  auto bad = [&](const std::string& what) {
    throw std::runtime_error("cannot write results file " + path.string() + ": " + what);
  };
  if (h.samples < 0) bad("negative sample count");
  if (h.values.size() != h.signals.size())
    bad("history has a different count of signals and value arrays");
  for (std::size_t i = 0; i < h.signals.size(); ++i) {
    const SignalSpec& s = signal_spec(h.signals[i]);
    const auto expected = static_cast<std::size_t>(h.samples) * static_cast<std::size_t>(s.width);
    if (h.values[i].size() != expected)
      bad("signal " + std::string(s.name) + " has " + std::to_string(h.values[i].size()) +
          " values, expected " + std::to_string(expected));
  }
}

/// One field of the case record as a root attribute (sweep/case_record.def).
void write_record_attribute(const Context& cx, hid_t root, const std::string& name,
                            const record_text& v) {
  attr_string(cx, root, name, v);
}
void write_record_attribute(const Context& cx, hid_t root, const std::string& name,
                            record_integer v) {
  attr_int64(cx, root, name, v);
}
void write_record_attribute(const Context& cx, hid_t root, const std::string& name, record_real v) {
  attr_double(cx, root, name, v);
}
template <class T>  // json, features: their text
void write_record_attribute(const Context& cx, hid_t root, const std::string& name, const T& v) {
  attr_string(cx, root, name, record_field_text(v));
}
}  // namespace

void write_case_root(const Context& cx, hid_t root, const CaseSpec& spec, const CaseRecord& r,
                     const Json& prov) {
  attr_int(cx, root, "schema_version", kResultsSchemaVersion);
  for_each_record_field(r, [&](const RecordFieldSpec& f, const auto& v) {
    write_record_attribute(cx, root, std::string(f.name), v);
  });
  for (const char* key : {"rodend_version", "git_revision", "host", "study_file"})
    attr_string(cx, root, key, prov_text(prov, key));
  attr_string(cx, root, "parameters_json", spec.parameters.leaves().dump());
  attr_string(cx, root, "case_json", spec.canonical().dump());
}

void write_case_parameters(const Context& cx, hid_t root, const ParameterSet& params) {
  const Handle g = create_group(cx, root, "parameters");
  const Json values = params.values();
  Json units = Json::object();
  for (const auto& [path, v] : values.items()) {
    if (v.is_boolean()) {
      attr_int8(cx, g.get(), path, v.get<bool>() ? 1 : 0);
    } else if (v.is_number()) {
      attr_double(cx, g.get(), path, v.get<double>());
    } else if (v.is_string()) {
      attr_string(cx, g.get(), path, v.get<std::string>());
    } else if (v.is_array() &&
               std::all_of(v.begin(), v.end(), [](const Json& e) { return e.is_number(); })) {
      attr_doubles(cx, g.get(), path, v.get<std::vector<double>>());
    } else {
      cx.fail("parameter " + path + " has a value of unsupported type: " + v.dump());
    }
    units[path] = params.unit(path);
  }
  attr_string(cx, g.get(), "units_json", units.dump());
}

namespace {

/// The netCDF dimensions of the per-case arrays (CaseArray::dim_names): a dimension named
/// after a 1-D array of the group is that array (a coordinate), else one without a variable.
void attach_array_dimensions(const Context& cx, const History& h,
                             const std::map<std::string, Handle>& groups) {
  // group -> dimension -> (dataset, axis) to attach
  std::map<std::string, std::map<std::string, std::vector<std::pair<std::string, unsigned>>>> uses;
  std::map<std::string, std::map<std::string, hsize_t>> sizes;
  for (const CaseArray& a : h.arrays)
    for (std::size_t k = 0; k < a.dim_names.size() && k < a.dims.size(); ++k) {
      const std::string& dim = a.dim_names[k];
      if (!(a.dims.size() == 1 && a.name == dim))
        uses[a.group][dim].emplace_back(a.name, static_cast<unsigned>(k));
      sizes[a.group][dim] = static_cast<hsize_t>(a.dims[k]);
    }
  for (const auto& [group, dims] : sizes) {
    const hid_t g = groups.at(group).get();
    for (const auto& [dim, size] : dims) {
      const bool has_variable = std::any_of(h.arrays.begin(), h.arrays.end(), [&](const auto& a) {
        return a.group == group && a.name == dim && a.dims.size() == 1;
      });
      const std::string what = "cannot attach dimension " + group + "/" + dim;
      const Handle scale = has_variable
                               ? cx.own(H5Dopen2(g, dim.c_str(), H5P_DEFAULT), H5Dclose, what)
                               : dimension_without_variable(cx, g, dim, size);
      std::vector<Handle> open;
      std::vector<std::pair<hid_t, unsigned>> targets;
      for (const auto& [name, axis] : uses[group][dim]) {
        open.push_back(cx.own(H5Dopen2(g, name.c_str(), H5P_DEFAULT), H5Dclose, what));
        targets.emplace_back(open.back().get(), axis);
      }
      attach_scale(cx, scale.get(), dim.c_str(), targets);
    }
  }
}

}  // namespace

void check_case_array(const Context& cx, const CaseArray& a) {
  const std::string what = "cannot write " + a.group + "/" + a.name;
  std::size_t n = 1;
  for (std::size_t d : a.dims) n *= d;
  if (a.dims.empty() || a.dims.size() > 2 || n != a.values.size()) cx.fail(what + ": bad shape");
  for (double v : a.values)
    if (!std::isfinite(v)) cx.fail(what + ": a value is not finite");
}

void write_case_arrays(const Context& cx, hid_t root, const History& h, CaseSlots* raw) {
  std::map<std::string, Handle> groups;
  for (const CaseArray& a : h.arrays) {
    const std::string what = "cannot write " + a.group + "/" + a.name;
    check_case_array(cx, a);
    const std::size_t n = a.values.size();
    auto it = groups.find(a.group);
    if (it == groups.end()) it = groups.emplace(a.group, create_group(cx, root, a.group)).first;
    hsize_t dims[2] = {0, 0};
    for (std::size_t k = 0; k < a.dims.size(); ++k) dims[k] = static_cast<hsize_t>(a.dims[k]);
    const Handle space =
        cx.own(H5Screate_simple(static_cast<int>(a.dims.size()), dims, nullptr), H5Sclose, what);
    Handle d = cx.own(H5Dcreate2(it->second.get(), a.name.c_str(), H5T_IEEE_F64LE, space.get(),
                                 H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                      H5Dclose, what);
    if (n > 0) {
      const DroppingRawData dropping(raw != nullptr);  // a template's: each case writes its own
      cx.ok(H5Dwrite(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, a.values.data()),
            what);
    }
    if (raw && n > 0) {  // H5Dget_offset counts the user block, image offsets do not
      const haddr_t addr = H5Dget_offset(d.get());
      if (addr == HADDR_UNDEF || addr < kUserBlock) cx.fail(what + ": no address");
      raw->raw(addr - kUserBlock, 8 * n);
    }
    attr_units(cx, d.get(), a.unit, a.description);
    cx.ok(d.close(), what);
  }
  attach_array_dimensions(cx, h, groups);
}

void write_case_metrics(const Context& cx, hid_t root, const MetricValues& m) {
  const Handle g = create_group(cx, root, "metrics");
  Json units = Json::object();
  const auto cat = metric_catalogue();
  for (std::size_t i = 0; i < cat.size() && i < m.size(); ++i) {
    const std::string name(cat[i].name);
    attr_double(cx, g.get(), name, m[i]);
    units[name] = std::string(cat[i].unit);
  }
  attr_string(cx, g.get(), "units_json", units.dump());
}

}  // namespace rodend::results_detail

namespace rodend {

using namespace results_detail;

void write_case_file(const fs::path& path, const CaseSpec& spec, const CaseRecord& record,
                     const History& history, const Json& prov) {
  check_history(path, history);
  // the expensive part, in the calling thread: every chunk shuffled and deflated
  std::vector<EncodedSignal> encoded;
  encoded.reserve(history.signals.size());
  std::size_t estimate = 1 << 16;  // [bytes] attributes and HDF5's own structures
  for (std::size_t i = 0; i < history.signals.size(); ++i) {
    encoded.push_back(encode_signal(history.values[i], history.samples,
                                    signal_spec(history.signals[i]).width, spec.output));
    for (const auto& chunk : encoded.back().chunks) estimate += chunk.size();
  }
  for (const CaseArray& a : history.arrays) estimate += 8 * a.values.size() + (1 << 14);
  // HDF5's own structures per dataset (object header, attributes, chunk index; measured:
  // 4-9 kB): an estimate too small makes the core driver grow its buffer by a whole estimate
  // (a copy and a clear of the file so far, under the lock)
  estimate += history.signals.size() * (1 << 14);
  // chunks of a fixed size (not compressed): the case's image from its template, no HDF5
  ByteSpan image;
  const char* const templates = std::getenv("RODEND_CASE_TEMPLATES");
  if (spec.output.compression_level == 0 && !(templates && std::string_view(templates) == "0"))
    image = image_from_template(path, {spec, record, history, prov, encoded, estimate});
  if (image.empty()) {
    Hdf5Lock lock;  // held for the in-memory build: cheap calls only, the chunks are ready
    const Context cx(path, "cannot write results file");
    image = build_image(cx, kUserBlock, estimate, [&](hid_t file) {
      const Handle root = cx.own(H5Gopen2(file, "/", H5P_DEFAULT), H5Gclose, "no root");
      write_case_root(cx, root.get(), spec, record, prov);
      write_case_parameters(cx, root.get(), spec.parameters);
      write_case_signals(cx, root.get(), history, encoded, spec.output);
      write_case_arrays(cx, root.get(), history);
      write_case_metrics(cx, root.get(), record.metrics);
    });
  }
  encoded.clear();
  const auto header = checksum_header(image);
  // Not flushed to the disk (no fsync): a case file torn by an OS crash or a power loss fails
  // its checksum, and resume moves it aside and reruns the case (docs/testing.md, Faults).
  write_file_atomically(path, "results file", {ByteSpan(header), image}, /*durable=*/false);
}

}  // namespace rodend
