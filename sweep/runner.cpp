#include "sweep/runner.hpp"

#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <iostream>
#include <mutex>
#include <ostream>

#include "core/scene.hpp"
#include "sweep/case_observer.hpp"

namespace rodend {
namespace fs = std::filesystem;

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

namespace {

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

/// Writes `text` to `path` via a temporary file and a rename.
void write_text_atomically(const fs::path& path, const std::string& text) {
  // built with += : GCC 12 warns falsely (-Wrestrict) on "." + std::string temporaries
  std::string name = ".";
  name += path.filename().string();
  name += ".tmp.";
  // host and pid: shards on different nodes may write the same study.json at once
  char host[256] = {};
  if (::gethostname(host, sizeof host - 1) == 0) {
    name += host;
    name += ".";
  }
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

Progress::Progress(bool enabled, long total, long already)
    : enabled_(enabled),
      tty_(isatty(fileno(stderr)) != 0),
      total_(total),
      done_(already),
      start_(std::chrono::steady_clock::now()),
      already_(already) {
  if (enabled_ && already > 0)
    std::fprintf(stderr, "rodend: %ld of %ld cases already complete, %ld to run\n", already, total,
                 total - already);
}

void Progress::case_done(bool failed) {
  if (!enabled_) return;
  std::lock_guard lock(mutex_);
  ++done_;
  if (failed) ++failed_;
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const long ran = done_ - already_;
  const double eta =
      ran > 0 ? elapsed / static_cast<double>(ran) * static_cast<double>(total_ - done_) : 0.0;
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

bool in_shard(const CaseSpec& c, const RunOptions& o) {
  return o.shard_count <= 1 || (c.index % o.shard_count) + 1 == o.shard_index;
}

CaseRecord run_case(const CaseSpec& spec, History& history) {
  if (spec.wear_evolution.enabled) return run_wear_evolution(spec, history);
  CaseRecord rec;
  rec.id = spec.id;
  rec.index = spec.index;
  rec.scene = spec.scene;
  rec.coordinates = spec.coordinates;
  rec.started_utc = utc_now();
  const auto t0 = std::chrono::steady_clock::now();
  const auto scene = make_scene(spec.scene, spec.parameters);
  CaseObserver obs(*scene, spec, &history);
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
  obs.record_wear(rec.metrics, history);
  return rec;
}

RunPlan plan_run(const Study& study, const RunOptions& opt) {
  RunPlan plan;
  plan.dir = study.output_dir;
  plan.cases_dir = plan.dir / "cases";
  std::error_code ec;
  fs::create_directories(plan.cases_dir, ec);
  if (ec)
    throw InputError(
        "output",
        "cannot create the results directory " + plan.cases_dir.string() + ": " + ec.message(),
        study.file.string());
  // both directories take files (cases; study.json and the summary): checked before anything
  // runs, so a read-only results folder fails at once, not after the cases
  for (const fs::path& d : {plan.cases_dir, plan.dir})
    if (::access(d.c_str(), W_OK) != 0)
      throw InputError(
          "output",
          "the results directory " + d.string() + " is not writable (" + std::strerror(errno) + ")",
          study.file.string());
  plan.provenance = provenance(study);
  // a shard writes its own summary; `rodend merge` assembles the study's
  plan.summary_dir = opt.shard_count > 1 ? plan.dir / ("shard-" + std::to_string(opt.shard_index) +
                                                       "-of-" + std::to_string(opt.shard_count))
                                         : plan.dir;

  // what is complete already (resume): a case file under its final name is complete. One that
  // cannot be read (truncated, corrupt, locked, another case's or another schema's) is never
  // overwritten: it is reported and nothing runs.
  plan.records.assign(study.cases.size(), CaseRecord{});
  plan.have.assign(study.cases.size(), 0);
  std::vector<std::string> unreadable;
  for (std::size_t i = 0; i < study.cases.size(); ++i) {
    const CaseSpec& c = study.cases[i];
    if (!in_shard(c, opt)) continue;
    ++plan.in_scope;
    const fs::path path = plan.cases_dir / (c.id + ".h5");
    std::optional<CaseRecord> rec;
    try {
      rec = read_case_record_strict(path);
      if (rec && rec->id != c.id)
        throw std::runtime_error(path.string() + " holds case " + rec->id + ", not " + c.id);
    } catch (const std::exception& e) {
      unreadable.push_back(e.what());
      continue;
    }
    if (rec && (rec->status == "ok" || !opt.rerun_failed)) {
      plan.records[i] = *rec;
      plan.have[i] = 1;
      continue;
    }
    plan.todo.push_back(i);
  }
  if (!unreadable.empty()) {
    std::string m = std::to_string(unreadable.size()) +
                    " case file(s) exist but cannot be read; rodend does not overwrite them. "
                    "Move them away (or delete them) to rerun those cases:";
    for (const std::string& u : unreadable) m += "\n  " + u;
    throw std::runtime_error(m);
  }
  write_text_atomically(plan.dir / "study.json", study.source.dump(2) + "\n");
  return plan;
}

CaseRecord run_and_write_case(const Study& study, const RunPlan& plan, std::size_t i) {
  const CaseSpec& spec = study.cases[i];
  History history;
  CaseRecord rec = run_case(spec, history);
  write_case_file(plan.cases_dir / (spec.id + ".h5"), spec, rec, history, plan.provenance);
  return rec;
}

int write_run_summary(const Study& study, const RunPlan& plan,
                      const std::vector<CaseRecord>& rows) {
  fs::create_directories(plan.summary_dir);
  write_summary(plan.summary_dir, study, rows, plan.provenance);
  const bool any_failed =
      std::any_of(rows.begin(), rows.end(), [](const CaseRecord& r) { return r.status != "ok"; });
  return any_failed ? 1 : 0;
}

int run_study(const Study& study, const RunOptions& opt) {
  RunPlan plan = plan_run(study, opt);
  Progress progress(opt.progress, plan.in_scope,
                    plan.in_scope - static_cast<long>(plan.todo.size()));

  std::mutex error_mutex;
  std::string first_error;
  const long n_todo = static_cast<long>(plan.todo.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(std::max(opt.threads, 1))
  for (long k = 0; k < n_todo; ++k) {
    const std::size_t i = plan.todo[static_cast<std::size_t>(k)];
    try {
      plan.records[i] = run_and_write_case(study, plan, i);
      plan.have[i] = 1;  // vector<char>: distinct elements written from threads
      progress.case_done(plan.records[i].status != "ok");
    } catch (const std::exception& e) {
      std::lock_guard lock(error_mutex);
      if (first_error.empty()) first_error = "case " + study.cases[i].id + ": " + e.what();
      progress.case_done(true);
    }
  }
  if (!first_error.empty()) throw std::runtime_error(first_error);

  std::vector<CaseRecord> rows;
  for (std::size_t i = 0; i < study.cases.size(); ++i)
    if (plan.have[i]) rows.push_back(plan.records[i]);
  return write_run_summary(study, plan, rows);
}

int merge_study(const Study& study, std::ostream& report) {
  const fs::path dir = study.output_dir;
  const fs::path cases_dir = dir / "cases";
  std::vector<CaseRecord> rows;
  rows.reserve(study.cases.size());
  std::vector<const CaseSpec*> missing;
  // the shard count, when the shard summaries present agree on one (to name missing shards)
  int shards = 0;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    int k = 0, n = 0;
    char tail = 0;
    const std::string name = e.path().filename().string();
    if (std::sscanf(name.c_str(), "shard-%d-of-%d%c", &k, &n, &tail) == 2 && n > 0)
      shards = (shards == 0 || shards == n) ? n : -1;
  }
  if (shards < 0) shards = 0;
  for (const CaseSpec& c : study.cases) {
    if (auto rec = read_case_record(cases_dir / (c.id + ".h5")))
      rows.push_back(std::move(*rec));
    else
      missing.push_back(&c);
  }
  if (!missing.empty()) {
    report << "rodend: " << missing.size() << " of " << study.cases.size()
           << " cases have no complete file in " << cases_dir.string()
           << "; no summary written. Missing (case index, case id"
           << (shards > 0 ? ", shard K/N" : "") << "):\n";
    for (const CaseSpec* c : missing) {
      report << "  " << c->index << "\t" << c->id;
      if (shards > 0) report << "\t" << (c->index % shards) + 1 << "/" << shards;
      report << "\n";
    }
    return 1;
  }
  write_summary(dir, study, rows, provenance(study));
  const auto failed =
      std::count_if(rows.begin(), rows.end(), [](const CaseRecord& r) { return r.status != "ok"; });
  report << "rodend: merged " << rows.size() << " cases (" << failed << " failed) into "
         << (dir / "summary.h5").string() << " and summary.csv\n";
  return 0;
}

}  // namespace rodend
