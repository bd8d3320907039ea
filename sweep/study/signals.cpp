// The recorded signals: the study's selection ("all" or a list of names), the list each scene
// records of it, and the memory a case's histories need.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "sweep/study/loader.hpp"

namespace rodend::study_detail {

namespace {

/// A case's histories are held in memory until its file is written (README "Studies").
constexpr double kMaxHistoryBytes = 2147483648.0;  // 2 GiB

}  // namespace

SignalSelection read_signal_selection(const Json& doc) {
  SignalSelection s;
  s.names = doc.contains("signals") ? doc["signals"] : Json("all");
  s.all = s.names.is_string() && s.names.get<std::string>() == "all";
  if (!s.all && !s.names.is_array())
    throw InputError("signals", "expected \"all\" or an array of signal names");
  s.provided.assign(s.all ? 0 : s.names.size(), false);
  return s;
}

std::vector<SignalId> scene_signals(const Scene& scene, SignalSelection& sel, const Study& study,
                                    bool several) {
  const auto provided = scene.signals();
  if (sel.all) return {provided.begin(), provided.end()};
  std::vector<SignalId> signals{SignalId::time};
  for (std::size_t i = 0; i < sel.names.size(); ++i) {
    const std::string key = "signals[" + std::to_string(i) + "]";
    const std::string sname = need_string(sel.names[i], key);
    const auto id = signal_by_name(sname);
    if (!id) throw InputError(key, "unknown signal '" + sname + "' (see `rodend signals`)");
    if (std::find(provided.begin(), provided.end(), *id) == provided.end()) {
      if (!several)
        throw InputError(key, "signal '" + sname + "' is not recorded by scene " + study.scene);
      continue;
    }
    sel.provided[i] = true;
    if (std::find(signals.begin(), signals.end(), *id) == signals.end()) signals.push_back(*id);
  }
  std::sort(signals.begin(), signals.end());
  return signals;
}

void check_history_size(const TimeSettings& t, const std::vector<SignalId>& signals) {
  double width = 0.0;
  for (SignalId id : signals) width += signal_spec(id).width;
  const double samples = std::floor(t.end / t.sample_interval + 1e-9) + 1.0;
  const double bytes = samples * width * 8.0;
  if (bytes > kMaxHistoryBytes) {
    std::ostringstream m;
    m << samples << " samples of " << width << " recorded values need " << bytes / 1073741824.0
      << " GiB of memory per case (limit 2 GiB); expected a larger sample interval, a shorter "
         "end time or fewer signals";
    throw InputError("time.sample_interval", m.str());
  }
}

}  // namespace rodend::study_detail
