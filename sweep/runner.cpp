#include "sweep/runner.hpp"

#include <omp.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <iostream>
#include <mutex>

#include "core/scene.hpp"

namespace rodend {
namespace fs = std::filesystem;

namespace {

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

/// Collects the sampled histories of the recorded signals and the metrics of every step.
class CaseObserver final : public RunObserver {
 public:
  CaseObserver(const Scene& scene, const CaseSpec& spec, History& h)
      : history_(h), metrics_(scene, spec.metrics) {
    h.signals = spec.signals;
    h.values.assign(spec.signals.size(), {});
    h.samples = 0;
    const auto n = static_cast<std::size_t>(
        std::floor(spec.time.end / spec.time.sample_interval + 1e-9) + 1);
    for (std::size_t i = 0; i < spec.signals.size(); ++i)
      h.values[i].reserve(n * static_cast<std::size_t>(signal_spec(spec.signals[i]).width));
  }
  void on_sample(const SignalFrame& f) override {
    for (std::size_t i = 0; i < history_.signals.size(); ++i) {
      const SignalId id = history_.signals[i];
      const double* v = f.data(id);
      history_.values[i].insert(history_.values[i].end(), v, v + signal_spec(id).width);
    }
    ++history_.samples;
  }
  void on_step(const SignalFrame& f) override { metrics_.on_step(f); }
  bool wants_steps() const override { return true; }
  MetricValues finish(const RunStats& s) const { return metrics_.finish(s); }

 private:
  History& history_;
  MetricsAccumulator metrics_;
};

std::string format_duration(double s) {
  char buf[32];
  if (s < 60)
    std::snprintf(buf, sizeof buf, "%.0fs", s);
  else if (s < 3600)
    std::snprintf(buf, sizeof buf, "%dm%02ds", static_cast<int>(s / 60), static_cast<int>(s) % 60);
  else
    std::snprintf(buf, sizeof buf, "%dh%02dm", static_cast<int>(s / 3600),
                  static_cast<int>(s / 60) % 60);
  return buf;
}

/// Progress on stderr: one updating line on a terminal, periodic plain lines otherwise.
class Progress {
 public:
  Progress(bool enabled, long total, long already)
      : enabled_(enabled), tty_(isatty(fileno(stderr)) != 0), total_(total), done_(already),
        start_(std::chrono::steady_clock::now()), already_(already) {
    if (enabled_ && already > 0)
      std::fprintf(stderr, "rodend: %ld of %ld cases already complete, %ld to run\n", already,
                   total, total - already);
  }
  void case_done(bool failed) {
    if (!enabled_) return;
    std::lock_guard lock(mutex_);
    ++done_;
    if (failed) ++failed_;
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const long ran = done_ - already_;
    const double eta = ran > 0 ? elapsed / static_cast<double>(ran) * static_cast<double>(total_ - done_) : 0.0;
    if (tty_) {
      std::fprintf(stderr, "\r[%ld/%ld] %ld failed, elapsed %s, ETA %s   ", done_, total_, failed_,
                   format_duration(elapsed).c_str(), format_duration(eta).c_str());
      if (done_ == total_) std::fprintf(stderr, "\n");
    } else if (done_ == total_ || elapsed - last_print_ >= 10.0) {
      last_print_ = elapsed;
      std::fprintf(stderr, "rodend: %ld/%ld cases done, %ld failed, elapsed %s, ETA %s\n", done_,
                   total_, failed_, format_duration(elapsed).c_str(), format_duration(eta).c_str());
    }
    std::fflush(stderr);
  }

 private:
  bool enabled_, tty_;
  long total_, done_, failed_ = 0;
  std::chrono::steady_clock::time_point start_;
  long already_;
  double last_print_ = 0.0;
  std::mutex mutex_;
};

/// Writes `text` to `path` via a temporary file and a rename.
void write_text_atomically(const fs::path& path, const std::string& text) {
  // built with += : GCC 12 warns falsely (-Wrestrict) on "." + std::string temporaries
  std::string name = ".";
  name += path.filename().string();
  name += ".tmp.";
  name += std::to_string(::getpid());
  const fs::path tmp = path.parent_path() / name;
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot write " + tmp.string());
    out << text;
    if (!out.flush()) throw std::runtime_error("cannot write " + tmp.string());
  }
  fs::rename(tmp, path);
}

}  // namespace

bool in_shard(const CaseSpec& c, const RunOptions& o) {
  return o.shard_count <= 1 || (c.index % o.shard_count) + 1 == o.shard_index;
}

CaseRecord run_case(const CaseSpec& spec, History& history) {
  CaseRecord rec;
  rec.id = spec.id;
  rec.index = spec.index;
  rec.coordinates = spec.coordinates;
  rec.started_utc = utc_now();
  const auto t0 = std::chrono::steady_clock::now();
  const auto scene = make_scene(spec.scene, spec.parameters);
  CaseObserver obs(*scene, spec, history);
  RunResult r;
  try {
    r = simulate(*scene, spec.integrator, spec.time, obs, spec.health);
  } catch (const std::exception& e) {
    // anything else the physics throws is this case's failure, not the study's
    r.status = RunStatus::non_finite_state;
    r.message = std::string("internal error: ") + e.what();
  }
  rec.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  rec.finished_utc = utc_now();
  rec.status = std::string(to_string(r.status));
  rec.message = r.message;
  rec.t_reached = r.stats.t_reached;
  rec.steps_accepted = r.stats.steps_accepted;
  rec.steps_rejected = r.stats.steps_rejected;
  rec.rhs_calls = r.stats.rhs_calls;
  rec.metrics = obs.finish(r.stats);
  return rec;
}

int run_study(const Study& study, const RunOptions& opt) {
  const fs::path dir = study.output_dir;
  const fs::path cases_dir = dir / "cases";
  std::error_code ec;
  fs::create_directories(cases_dir, ec);
  if (ec)
    throw InputError("output", "cannot create the results directory " + cases_dir.string() +
                                   ": " + ec.message(),
                     study.file.string());
  if (::access(cases_dir.c_str(), W_OK) != 0)
    throw InputError("output", "the results directory " + cases_dir.string() + " is not writable",
                     study.file.string());
  const Json prov = provenance(study);
  write_text_atomically(dir / "study.json", study.source.dump(2) + "\n");

  // what is complete already (resume): a case file under its final name is complete
  std::vector<CaseRecord> records(study.cases.size());
  std::vector<char> have(study.cases.size(), 0);  // not vector<bool>: written from threads
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < study.cases.size(); ++i) {
    const CaseSpec& c = study.cases[i];
    if (!in_shard(c, opt)) continue;
    if (auto rec = read_case_record(cases_dir / (c.id + ".h5"))) {
      if (rec->status == "ok" || !opt.rerun_failed) {
        records[i] = *rec;
        have[i] = 1;
        continue;
      }
    }
    todo.push_back(i);
  }
  const long in_scope = static_cast<long>(
      std::count_if(study.cases.begin(), study.cases.end(), [&](const CaseSpec& c) { return in_shard(c, opt); }));
  Progress progress(opt.progress, in_scope, in_scope - static_cast<long>(todo.size()));

  std::mutex error_mutex;
  std::string first_error;
  const long n_todo = static_cast<long>(todo.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(std::max(opt.threads, 1))
  for (long k = 0; k < n_todo; ++k) {
    const std::size_t i = todo[static_cast<std::size_t>(k)];
    const CaseSpec& spec = study.cases[i];
    try {
      History history;
      CaseRecord rec = run_case(spec, history);
      write_case_file(cases_dir / (spec.id + ".h5"), spec, rec, history, prov);
      records[i] = std::move(rec);
      have[i] = 1;
      progress.case_done(records[i].status != "ok");
    } catch (const std::exception& e) {
      std::lock_guard lock(error_mutex);
      if (first_error.empty()) first_error = "case " + spec.id + ": " + e.what();
      progress.case_done(true);
    }
  }
  if (!first_error.empty()) throw std::runtime_error(first_error);

  std::vector<CaseRecord> rows;
  for (std::size_t i = 0; i < study.cases.size(); ++i)
    if (have[i]) rows.push_back(records[i]);
  // a shard writes its own summary; `rodend merge` assembles the study's
  const fs::path summary_dir =
      opt.shard_count > 1 ? dir / ("shard-" + std::to_string(opt.shard_index) + "-of-" +
                                   std::to_string(opt.shard_count))
                          : dir;
  fs::create_directories(summary_dir);
  write_summary(summary_dir, study, rows, prov);
  const bool any_failed =
      std::any_of(rows.begin(), rows.end(), [](const CaseRecord& r) { return r.status != "ok"; });
  return any_failed ? 1 : 0;
}

}  // namespace rodend
