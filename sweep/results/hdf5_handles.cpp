// HDF5 error reporting and the attribute, dataspace, group and dimension helpers of the results
// files (sweep/results/hdf5.hpp).
#include <hdf5_hl.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstdio>
#include <new>
#include <stdexcept>

#include "sweep/results/hdf5.hpp"

namespace rodend::results_detail {

namespace {

herr_t collect_error(unsigned n, const H5E_error2_t* e, void* data) {
  auto* out = static_cast<std::pair<std::string, std::string>*>(data);
  if (n == 0 && e->func_name) out->first = e->func_name;  // the API call
  if (e->desc) out->second = e->desc;                     // the innermost cause, last
  return 0;
}

herr_t find_allocation_failure(unsigned, const H5E_error2_t* e, void* data) {
  if (e->maj_num == H5E_RESOURCE && (e->min_num == H5E_CANTALLOC || e->min_num == H5E_NOSPACE))
    *static_cast<bool*>(data) = true;
  return 0;
}

}  // namespace

/// The current HDF5 error stack, shortened to "API call: innermost description".
std::string hdf5_error_text() {
  std::pair<std::string, std::string> parts;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, collect_error, &parts);
  if (parts.first.empty() && parts.second.empty()) return {};
  return parts.first.empty() ? parts.second : parts.first + ": " + parts.second;
}

/// True when the current HDF5 error is an allocation that failed (memory, not the file).
bool hdf5_out_of_memory() {
  bool found = false;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, find_allocation_failure, &found);
  return found;
}

// Writing helpers

Handle utf8_string_type(const Context& cx) {
  Handle t = cx.own(H5Tcopy(H5T_C_S1), H5Tclose, "cannot create a string type");
  cx.ok(H5Tset_size(t.get(), H5T_VARIABLE), "cannot create a string type");
  cx.ok(H5Tset_cset(t.get(), H5T_CSET_UTF8), "cannot create a string type");
  return t;
}

Handle scalar_space(const Context& cx) {
  return cx.own(H5Screate(H5S_SCALAR), H5Sclose, "cannot create a dataspace");
}

Handle vector_space(const Context& cx, hsize_t n) {
  return cx.own(H5Screate_simple(1, &n, nullptr), H5Sclose, "cannot create a dataspace");
}

namespace {

void write_attribute(const Context& cx, hid_t obj, const std::string& name, hid_t file_type,
                     hid_t mem_type, hid_t space, const void* data) {
  const std::string what = "cannot write attribute " + name;
  Handle a = cx.own(H5Acreate2(obj, name.c_str(), file_type, space, H5P_DEFAULT, H5P_DEFAULT),
                    H5Aclose, what);
  cx.ok(H5Awrite(a.get(), mem_type, data), what);
  cx.ok(a.close(), what);
}

}  // namespace

void attr_string(const Context& cx, hid_t obj, const std::string& name, const std::string& v) {
  const std::string value = cx.slots() ? cx.slots()->text(name, v) : v;
  if (cx.collecting()) return;
  const Handle t = utf8_string_type(cx);
  const Handle s = scalar_space(cx);
  const char* p = value.c_str();
  write_attribute(cx, obj, name, t.get(), t.get(), s.get(), &p);
}

namespace {

/// A scalar 8-byte number attribute (a slot with a CaseSlots), `v` its bytes in memory.
template <class T>
void attr_number(const Context& cx, hid_t obj, const std::string& name, hid_t file_type,
                 hid_t mem_type, T v) {
  static_assert(sizeof(T) == 8);
  std::uint64_t bits = std::bit_cast<std::uint64_t>(v);
  if (cx.slots()) bits = cx.slots()->number(name, bits);
  if (cx.collecting()) return;
  const Handle s = scalar_space(cx);
  write_attribute(cx, obj, name, file_type, mem_type, s.get(), &bits);
}

}  // namespace

void attr_double(const Context& cx, hid_t obj, const std::string& name, double v) {
  attr_number(cx, obj, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, v);
}

void attr_int64(const Context& cx, hid_t obj, const std::string& name, long long v) {
  attr_number(cx, obj, name, H5T_STD_I64LE, H5T_NATIVE_LLONG, v);
}

void attr_int(const Context& cx, hid_t obj, const std::string& name, int v) {
  if (cx.slots()) cx.slots()->fixed("int " + name + "=" + std::to_string(v));
  if (cx.collecting()) return;
  const Handle s = scalar_space(cx);
  write_attribute(cx, obj, name, H5T_STD_I32LE, H5T_NATIVE_INT, s.get(), &v);
}

void attr_int8(const Context& cx, hid_t obj, const std::string& name, signed char v) {
  if (cx.slots()) cx.slots()->fixed("int8 " + name + "=" + std::to_string(v));
  if (cx.collecting()) return;
  const Handle s = scalar_space(cx);
  write_attribute(cx, obj, name, H5T_STD_I8LE, H5T_NATIVE_SCHAR, s.get(), &v);
}

void attr_doubles(const Context& cx, hid_t obj, const std::string& name,
                  const std::vector<double>& v) {
  std::vector<std::uint64_t> bits(v.size());
  std::transform(v.begin(), v.end(), bits.begin(),
                 [](double x) { return std::bit_cast<std::uint64_t>(x); });
  if (cx.slots()) {
    cx.slots()->fixed("doubles " + name + "[" + std::to_string(v.size()) + "]");
    for (std::uint64_t& b : bits) b = cx.slots()->number(name, b);
  }
  if (cx.collecting()) return;
  const Handle s = vector_space(cx, v.size());
  write_attribute(cx, obj, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, s.get(), bits.data());
}

void attr_units(const Context& cx, hid_t dataset, const std::string& units,
                const std::string& long_name, bool text) {
  if (!text) attr_string(cx, dataset, "units", units);
  attr_string(cx, dataset, "long_name", long_name);
}

/// Makes `scale` the netCDF dimension `name` (a dimension scale, hdf5_hl) and attaches it as
/// axis `axis` of every dataset in `datasets`.
void attach_scale(const Context& cx, hid_t scale, const char* name,
                  const std::vector<std::pair<hid_t, unsigned>>& datasets) {
  const std::string what = std::string("cannot attach dimension scale ") + name;
  if (!cx.yes(H5DSis_scale(scale), what)) cx.ok(H5DSset_scale(scale, name), what);
  for (const auto& [d, axis] : datasets) cx.ok(H5DSattach_scale(d, scale, axis), what);
}

Handle dimension_without_variable(const Context& cx, hid_t group, const std::string& name,
                                  hsize_t size) {
  const std::string what = "cannot create dimension " + name;
  const Handle space = cx.own(H5Screate_simple(1, &size, nullptr), H5Sclose, what);
  Handle d = cx.own(H5Dcreate2(group, name.c_str(), H5T_IEEE_F32BE, space.get(), H5P_DEFAULT,
                               H5P_DEFAULT, H5P_DEFAULT),
                    H5Dclose, what);
  char label[96];
  std::snprintf(label, sizeof label, "This is a netCDF dimension but not a netCDF variable.%10d",
                static_cast<int>(size));
  cx.ok(H5DSset_scale(d.get(), label), what);
  return d;
}

Handle create_group(const Context& cx, hid_t parent, const std::string& name,
                    bool track_link_order) {
  if (cx.slots()) cx.slots()->fixed("group " + name);
  if (cx.collecting()) return Handle();
  const std::string what = "cannot create group " + name;
  Handle gcpl;
  if (track_link_order) {
    // so that tools iterating the group (h5py) list its members in creation order
    gcpl = cx.own(H5Pcreate(H5P_GROUP_CREATE), H5Pclose, what);
    cx.ok(H5Pset_link_creation_order(gcpl.get(), H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED),
          what);
  }
  return cx.own(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT,
                           track_link_order ? gcpl.get() : H5P_DEFAULT, H5P_DEFAULT),
                H5Gclose, what);
}

std::string prov_text(const Json& prov, const char* key) {
  if (!prov.is_object()) return {};
  const auto it = prov.find(key);
  return it != prov.end() && it->is_string() ? it->get<std::string>() : std::string();
}

// Reading helpers

namespace {

Handle open_attribute(const Context& cx, hid_t obj, const char* name) {
  const std::string what = std::string("cannot read attribute ") + name;
  Handle a = cx.own(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose, what);
  const Handle s = cx.own(H5Aget_space(a.get()), H5Sclose, what);
  if (H5Sget_simple_extent_npoints(s.get()) != 1) cx.fail(what + ": not a single value");
  return a;
}

}  // namespace

std::string read_attr_string(const Context& cx, hid_t obj, const char* name) {
  const std::string what = std::string("cannot read attribute ") + name;
  const Handle a = open_attribute(cx, obj, name);
  const Handle ft = cx.own(H5Aget_type(a.get()), H5Tclose, what);
  if (H5Tget_class(ft.get()) != H5T_STRING || !cx.yes(H5Tis_variable_str(ft.get()), what))
    cx.fail(what + ": not a variable-length string");
  const Handle mt = utf8_string_type(cx);
  char* raw = nullptr;
  cx.ok(H5Aread(a.get(), mt.get(), &raw), what);
  const Hdf5String owned(raw);
  return raw ? std::string(raw) : std::string();
}

namespace {

template <class T>
T read_attr_number(const Context& cx, hid_t obj, const char* name, hid_t mem_type) {
  const std::string what = std::string("cannot read attribute ") + name;
  const Handle a = open_attribute(cx, obj, name);
  const Handle ft = cx.own(H5Aget_type(a.get()), H5Tclose, what);
  const H5T_class_t c = H5Tget_class(ft.get());
  if (c != H5T_INTEGER && c != H5T_FLOAT) cx.fail(what + ": not a number");
  T v{};
  cx.ok(H5Aread(a.get(), mem_type, &v), what);
  return v;
}

}  // namespace

double read_attr_double(const Context& cx, hid_t obj, const char* name) {
  return read_attr_number<double>(cx, obj, name, H5T_NATIVE_DOUBLE);
}
long long read_attr_int64(const Context& cx, hid_t obj, const char* name) {
  return read_attr_number<long long>(cx, obj, name, H5T_NATIVE_LLONG);
}

namespace {

herr_t collect_name(hid_t, const char* name, const H5L_info_t*, void* data) {
  static_cast<std::vector<std::string>*>(data)->push_back(name);
  return 0;
}

}  // namespace

std::vector<std::string> group_members(const Context& cx, hid_t group) {
  std::vector<std::string> names;
  cx.ok(H5Literate(group, H5_INDEX_NAME, H5_ITER_INC, nullptr, collect_name, &names),
        "cannot list a group");
  return names;
}

std::string read_dataset_unit(const Context& cx, hid_t d) {
  // `units` (CF, schema 2); `unit` in schema 1 files
  for (const char* name : {"units", "unit"})
    if (cx.yes(H5Aexists(d, name), "cannot look up a unit")) return read_attr_string(cx, d, name);
  return {};
}

}  // namespace rodend::results_detail
