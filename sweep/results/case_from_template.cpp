// Case files from templates (case_template.hpp): HDF5 builds a case file once per shape of case,
// under the lock and through the template driver (template_driver.hpp), and every case of that
// shape is the template with its values written in, outside the lock.
#include <hdf5.h>

#include <algorithm>
#include <iterator>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "sweep/results/case_file.hpp"
#include "sweep/results/case_template.hpp"
#include "sweep/results/checksum.hpp"
#include "sweep/results/memory_file.hpp"
#include "sweep/results/template_driver.hpp"

namespace rodend::results_detail {
namespace {

/// What a case file's key holds of its histories and arrays (the attributes' part: CaseSlots).
std::string history_shape(const History& h, const OutputSettings& out) {
  Json shape{{"samples", h.samples},
             {"precision", static_cast<int>(out.history_precision)},
             {"level", out.compression_level}};
  Json& signals = shape["signals"] = Json::array();
  for (SignalId id : h.signals) signals.push_back(std::string(signal_spec(id).name));
  Json& arrays = shape["arrays"] = Json::array();
  for (const CaseArray& a : h.arrays)
    arrays.push_back({a.group, a.name, a.unit, a.description, a.dims, a.dim_names});
  return shape.dump();
}

/// The case's raw data in the order the template's writers placed it: every chunk of every
/// signal, then every array that is not empty.
std::vector<CaseTemplate::Bytes> raw_data(const History& h,
                                          const std::vector<EncodedSignal>& encoded) {
  std::vector<CaseTemplate::Bytes> raw;
  for (const EncodedSignal& e : encoded) raw.insert(raw.end(), e.chunks.begin(), e.chunks.end());
  for (const CaseArray& a : h.arrays)
    if (!a.values.empty())
      raw.emplace_back(reinterpret_cast<const unsigned char*>(a.values.data()),
                       8 * a.values.size());
  return raw;
}

/// The attributes of a case file, written through `cx` (values, placeholders or collected).
void write_case_attributes(const Context& cx, hid_t root, const CaseParts& c) {
  write_case_root(cx, root, c.spec, c.record, c.prov);
  write_case_parameters(cx, root, c.spec.parameters);
  write_case_metrics(cx, root, c.record.metrics);
}

/// HDF5 builds the case file with placeholders (under the lock, without its histories: the
/// template driver), and the template is made of it (outside the lock). nullptr: the file
/// cannot be a template.
std::shared_ptr<const CaseTemplate> build_case_template(const fs::path& path, const CaseParts& c,
                                                        const CaseSlots& values) {
  CaseSlots built(CaseSlots::Mode::placeholders);
  TemplateTarget target;
  {
    Hdf5Lock lock;
    const Context plain(path, "cannot write results file");
    const Context cx(path, "cannot write results file", &built);
    build_template_file(plain, target, kUserBlock, [&](hid_t file) {
      const Handle root = plain.own(H5Gopen2(file, "/", H5P_DEFAULT), H5Gclose, "no root");
      // in the order of write_case_file's build: the attributes' slots, the raw data
      write_case_root(cx, root.get(), c.spec, c.record, c.prov);
      write_case_parameters(cx, root.get(), c.spec.parameters);
      write_case_signals(plain, root.get(), c.history, c.encoded, c.spec.output, &built);
      write_case_arrays(plain, root.get(), c.history, &built);
      write_case_metrics(cx, root.get(), c.record.metrics);
    });
  }
  const ByteSpan image = template_image(target, built, kUserBlock);
  if (image.empty() || built.key() != values.key()) return nullptr;
  return CaseTemplate::analyse(image, built);
}

/// The templates by key (a case's slots and history_shape), the most recently used last.
struct TemplateCache {
  std::mutex mutex;  ///< held while one is built: a case of the same key waits for it
  std::vector<std::pair<std::string, std::shared_ptr<const CaseTemplate>>> entries;
};
TemplateCache g_templates;
/// Templates kept: one per shape of the cases of a study (a failed case's histories are
/// shorter, a shape of its own); each holds its image but the raw data (~0.1 MB for bench-32).
constexpr std::size_t kTemplatesKept = 8;

}  // namespace

ByteSpan image_from_template(const fs::path& path, const CaseParts& c) {
  CaseSlots values(CaseSlots::Mode::collect);
  const Context cx(path, "cannot write results file", &values);
  write_case_attributes(cx, H5I_INVALID_HID, c);
  for (const CaseArray& a : c.history.arrays) check_case_array(cx, a);
  const std::vector<CaseTemplate::Bytes> raw = raw_data(c.history, c.encoded);
  const std::string key = values.key() + history_shape(c.history, c.spec.output);
  std::shared_ptr<const CaseTemplate> t;
  {
    std::lock_guard lock(g_templates.mutex);
    auto& e = g_templates.entries;
    auto it = std::find_if(e.begin(), e.end(), [&](const auto& x) { return x.first == key; });
    if (it == e.end()) {
      if (e.size() == kTemplatesKept) e.erase(e.begin());
      e.emplace_back(key, build_case_template(path, c, values));
      it = std::prev(e.end());
    }
    std::rotate(it, std::next(it), e.end());  // the most recently used last
    t = e.back().second;
  }
  if (!t) return {};
  const std::size_t size = t->image_size(values);
  unsigned char* const buffer = thread_scratch(ScratchSlot::image, size);
  t->patch(values, raw, buffer);
  return ByteSpan(buffer, size);
}

}  // namespace rodend::results_detail
