// rodend-bench: the project's benchmark (bench/README.md).
//
//   1. rhs         cost of one right-hand-side call per scene, at states sampled from a short run
//                  (contact active for the contact scenes); ratios to rod-end-kinematic.
//   2. throughput  simulated seconds per wall second over one extension-retraction cycle
//                  (2.4 s) of rod-end-kinematic and rod-end-actuator, per accuracy preset.
//   3. cvode       CVODE (BDF, Adams) against the default preset at equal achieved error on a set
//                  of summary metrics, measured against a reference run: cost ratios.
//
// Own harness: std::chrono::steady_clock for wall time (plus the thread's CPU clock, to show what
// the machine's load did to the wall figures), medians of repeated measurements.
//
// The parts are bench/bench_rhs.cpp, bench/bench_throughput.cpp and bench/bench_cvode.cpp; what
// they share (options, clocks, scenes, presets, one measured run) is bench/bench_common.hpp.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>

#include "bench/bench_common.hpp"

#ifndef RODEND_BENCH_BUILD_TYPE
#define RODEND_BENCH_BUILD_TYPE "unknown"
#endif
#ifndef RODEND_BENCH_CXX_FLAGS
#define RODEND_BENCH_CXX_FLAGS "unknown"
#endif
#ifndef RODEND_GIT_REVISION
#define RODEND_GIT_REVISION "unknown"
#endif

namespace {

using namespace rodend::bench;

void usage(std::FILE* out) {
  std::fprintf(
      out,
      "usage: rodend-bench [--quick] [--json FILE] [--only rhs,throughput,cvode]\n"
      "  --quick        fewer repetitions and a shorter CVODE ladder (< 30 s on an idle machine)\n"
      "  --json FILE    also write every figure as JSON\n"
      "  --only LIST    run only these parts (comma-separated)\n");
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") {
      o.quick = true;
    } else if (a == "--json" && i + 1 < argc) {
      o.json_path = argv[++i];
    } else if (a == "--only" && i + 1 < argc) {
      const std::string list = argv[++i];
      o.rhs = list.find("rhs") != std::string::npos;
      o.throughput = list.find("throughput") != std::string::npos;
      o.cvode = list.find("cvode") != std::string::npos;
      if (!o.rhs && !o.throughput && !o.cvode) {
        usage(stderr);
        std::exit(2);
      }
    } else if (a == "-h" || a == "--help") {
      usage(stdout);
      std::exit(0);
    } else {
      std::fprintf(stderr, "rodend-bench: unknown argument '%s'\n", a.c_str());
      usage(stderr);
      std::exit(2);
    }
  }
  return o;
}

/// The machine and build, printed and as JSON.
json machine_header(const Options& opt) {
  char host[256] = "unknown";
  gethostname(host, sizeof host - 1);
  json machine = {{"host", host},
                  {"hardware_threads", std::thread::hardware_concurrency()},
                  {"load_average_start", load_average()},
                  {"compiler", __VERSION__},
                  {"build_type", RODEND_BENCH_BUILD_TYPE},
                  {"bench_flags", RODEND_BENCH_CXX_FLAGS},
                  {"git_revision", RODEND_GIT_REVISION},
                  {"quick", opt.quick}};
  std::printf("rodend-bench%s  (git %s, %s build, bench flags: %s)\n", opt.quick ? " --quick" : "",
              RODEND_GIT_REVISION, RODEND_BENCH_BUILD_TYPE, RODEND_BENCH_CXX_FLAGS);
  std::printf("host %s, %u hardware threads, load average %s (1, 5, 15 min) at start\n", host,
              std::thread::hardware_concurrency(), load_string().c_str());
  std::printf(
      "wall = std::chrono::steady_clock; cpu = this thread's CPU clock (wall/cpu > 1: the "
      "machine was busy)\n");
  return machine;
}

}  // namespace

int main(int argc, char** argv) {
  const Options opt = parse(argc, argv);
  json out;
  out["machine"] = machine_header(opt);
  const auto t_start = now();
  std::map<std::string, double> rhs_ns_cpu;  // part 1's cpu cost per call, per scene
  if (opt.rhs) rhs_ns_cpu = part_rhs(opt, out);
  std::vector<ThroughputRow> tp;
  if (opt.throughput) tp = part_throughput(opt, rhs_ns_cpu, out);
  if (opt.cvode) part_cvode(opt, tp, out);
  const auto t_end = now();
  out["machine"]["load_average_end"] = load_average();
  out["machine"]["total_wall_s"] = t_end.wall - t_start.wall;
  std::printf("\ntotal %.1f s wall, %.1f s cpu; load average %s at the end\n",
              t_end.wall - t_start.wall, t_end.cpu - t_start.cpu, load_string().c_str());
  if (!opt.json_path.empty()) {
    std::ofstream f(opt.json_path);
    if (!f) {
      std::fprintf(stderr, "rodend-bench: cannot write %s\n", opt.json_path.c_str());
      return 1;
    }
    f << out.dump(2) << '\n';
    std::fprintf(stderr, "rodend-bench: wrote %s\n", opt.json_path.c_str());
  }
  return 0;
}
