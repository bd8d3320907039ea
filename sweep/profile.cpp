// Profiles from data files in studies: which are in use, reading each once, their place in the
// case id and in the results (sweep/profile.hpp).
#include "sweep/profile.hpp"

#include <fstream>

#include "core/scenes/drivers.hpp"
#include "core/scenes/parts.hpp"

namespace rodend {
namespace {

constexpr std::string_view kFileLeaf = ".profile.file";

/// The input a `<input>.profile.file` leaf belongs to, e.g. "motion".
std::string input_of(const std::string& file_path) {
  return file_path.substr(0, file_path.size() - kFileLeaf.size());
}

/// The text at `key` of `values` is the profile choice of the menu E.
template <Choice E>
bool names_profile(const Json& values, const std::string& key) {
  const auto it = values.find(key);
  return it != values.end() && it->is_string() &&
         choice_from_name<E>(it->get<std::string>()) == E::profile;
}

/// The input under `input` (a motion's shape or a hinge moment's kind) is a profile.
bool in_use(const Json& values, const std::string& input) {
  return names_profile<MotionShape>(values, input + ".shape") ||
         names_profile<HingeMomentKind>(values, input + ".kind");
}

/// Where the results folder of a run read `file` from, by its profiles.json (the study as run,
/// study.json, is loaded from the results folder, e.g. by `rodend merge`), or empty.
std::filesystem::path recorded_path(const std::filesystem::path& folder, const std::string& file) {
  std::ifstream in(folder / "profiles.json");
  if (!in) return {};
  const Json records = Json::parse(in, nullptr, false);
  if (!records.is_array()) return {};
  for (const Json& r : records)
    if (r.is_object() && r.value("file", "") == file) return r.value("resolved_path", "");
  return {};
}

bool ends_with(const std::string& s, std::string_view tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

}  // namespace

std::shared_ptr<const ProfileData> ProfileStore::load(const ParameterSet& p,
                                                      const std::string& prefix) {
  ProfileRequest r;
  r.file = p.text(prefix + ".file");
  if (r.file.empty())
    throw InputError("parameters." + prefix + ".file",
                     "expected the path of a CSV or HDF5 file holding the profile");
  const std::filesystem::path given(r.file);
  r.resolved = given.is_absolute() ? given : folder_ / given;
  if (std::error_code ec; !std::filesystem::exists(r.resolved, ec))
    if (const auto recorded = recorded_path(folder_, r.file); !recorded.empty())
      r.resolved = recorded;
  r.time_column = p.text(prefix + ".time_column");
  r.column = p.text(prefix + ".column");
  r.unit = p.unit(prefix + ".column");
  const std::string key = r.resolved.string() + '\n' + r.time_column + '\n' + r.column;
  const std::lock_guard lock(mutex_);
  if (const auto it = loaded_.find(key); it != loaded_.end()) return it->second;
  try {
    auto data = std::make_shared<const ProfileData>(read_profile_file(r));
    loaded_.emplace(key, data);
    return data;
  } catch (const InputError& e) {
    throw InputError("parameters." + prefix + ".file", e.problem());
  }
}

namespace {
/// profiles_in_use, from the parameters' values.
std::vector<std::string> in_use_of(const Json& values) {
  std::vector<std::string> out;
  for (const auto& [path, v] : values.items())
    if (ends_with(path, kFileLeaf) && in_use(values, input_of(path)))
      out.push_back(input_of(path) + ".profile");
  return out;
}
}  // namespace

std::vector<std::string> profiles_in_use(const ParameterSet& p) {
  return in_use_of(p.values());
}

bool profiles_possible_keys(const std::vector<std::string>& axis_keys) {
  for (const std::string& k : axis_keys)
    if (k == "scene" || k.find(".profile.") != std::string::npos || ends_with(k, ".shape") ||
        ends_with(k, ".kind"))
      return true;
  return false;
}

void attach_profiles(ParameterSet& p, ProfileStore& store) {
  for (const std::string& prefix : profiles_in_use(p)) {
    const std::string file = prefix + ".file";
    const auto have = p.attached(file);
    if (!have) p.attach(file, store.load(p, prefix));
  }
}

void check_profiles_cover(const ParameterSet& p, double t_end) {
  for (const std::string& prefix : profiles_in_use(p)) {
    const auto data = p.attached(prefix + ".file");
    if (!data || data->end() >= t_end ||
        read_choice<ProfilePastEnd>(p, prefix + ".past_end") != ProfilePastEnd::error)
      continue;
    throw InputError("parameters." + prefix + ".file",
                     data->file + ": its last sample is at " + format_number(data->end()) +
                         " s, before the run's end (time.end = " + format_number(t_end) +
                         " s), and " + prefix +
                         ".past_end is \"error\"; expected a profile covering the run, or "
                         "past_end \"hold\" or \"repeat\"");
  }
}

Json identity_values(const ParameterSet& p) {
  Json values = p.values();
  std::vector<std::string> unused;
  for (const auto& [path, v] : values.items()) {
    if (!ends_with(path, kFileLeaf)) continue;
    const std::string input = input_of(path);
    if (in_use(values, input)) continue;
    unused.push_back(input + ".profile.");
  }
  for (const std::string& prefix : in_use_of(values))
    if (const auto data = p.attached(prefix + ".file"))
      values[prefix + ".file"] = "fnv1a64:" + data->content_hash;
  for (const std::string& prefix : unused)
    for (auto it = values.begin(); it != values.end();)
      it = it.key().rfind(prefix, 0) == 0 ? values.erase(it) : std::next(it);
  return values;
}

Json profile_record(const ProfileData& d) {
  return {{"file", d.file},
          {"resolved_path", d.resolved},
          {"content_fnv1a64", d.content_hash},
          {"column", d.column},
          {"unit", d.unit},
          {"samples", d.time.size()},
          {"start_s", d.start()},
          {"end_s", d.end()}};
}

Json ProfileStore::records() const {
  const std::lock_guard lock(mutex_);
  Json out = Json::array();
  for (const auto& [key, d] : loaded_) out.push_back(profile_record(*d));
  return out;
}

}  // namespace rodend
