// rodend from C++: read a study file with rodend::load_study, list its cases as
// `rodend run --dry-run` does, run the first one in memory with rodend::run_case and print two
// of its metrics. Built against an installed rodend (find_package(rodend); docs/python.md "C++:
// the CMake package"); the test cli.package_consumer builds and runs it on
// studies/gravity-drop.json.
//
//   load_study STUDY.json
#include <cstdio>
#include <exception>
#include <string>

#include <rodend/sweep/runner.hpp>
#include <rodend/sweep/study.hpp>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s STUDY.json\n", argv[0]);
    return 2;
  }
  try {
    // reads the file, expands its grid or design and checks every case; nothing is written
    const rodend::Study study = rodend::load_study(argv[1]);
    std::printf("study %s: scene %s, %zu cases, results in %s\n", study.name.c_str(),
                study.scene.c_str(), study.cases.size(), study.output_dir.c_str());
    for (std::size_t i = 0; i < study.cases.size(); ++i) {
      const rodend::CaseSpec c = study.cases[i];  // resolved on demand
      std::printf("  case %s %s\n", c.id.c_str(), c.coordinates.dump().c_str());
    }
    rodend::History history;  // the recorded signals, in memory
    const rodend::CaseRecord r = rodend::run_case(study.cases[0], history);
    const auto metric = [&](rodend::MetricId m) { return r.metrics[static_cast<std::size_t>(m)]; };
    std::printf(
        "first case: %s, %lld samples, first impact speed %.6g m/s, "
        "max contact force %.6g N\n",
        std::string(rodend::to_string(r.status)).c_str(), history.samples,
        metric(rodend::MetricId::first_impact_speed), metric(rodend::MetricId::max_contact_force));
    return r.status == rodend::RunStatus::ok ? 0 : 1;
  } catch (const rodend::InputError& e) {  // a bad study: the file, the key path, what is expected
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
}
