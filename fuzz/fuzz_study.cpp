// libFuzzer target for the study loader: the fuzz input is parsed as JSON and handed to
// rodend::parse_study, which must either return a study or throw InputError (bad input) or a
// nlohmann exception (the parser's own). Anything else (another exception, a crash, a leak, an
// AddressSanitizer or UndefinedBehaviorSanitizer report, a timeout) is a bug.
//
// Built only with clang and -DRODEND_FUZZ=ON (README "Fuzzing"):
//   CXX=clang++-14 CC=clang-14 cmake -S . -B build-fuzz -DRODEND_FUZZ=ON
//   -DCMAKE_BUILD_TYPE=RelWithDebInfo cmake --build build-fuzz --target fuzz_study -j2
//   build-fuzz/fuzz/fuzz_study -max_total_time=600 -dict=fuzz/study.dict fuzz/corpus-work
//   fuzz/corpus
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "core/errors.hpp"
#include "sweep/study.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  rodend::Json doc;
  try {
    doc = rodend::Json::parse(text);
  } catch (const rodend::Json::exception&) {
    return 0;  // not JSON: the loader's own syntax-error path, tested elsewhere
  }
  try {
    const rodend::Study s = rodend::parse_study(doc, "fuzz.json", "fuzz-results");
    // a loaded study is consistent: one id per case, cases in grid order
    for (std::size_t i = 0; i < s.cases.size(); ++i)
      if (s.cases[i].index != static_cast<long>(i) || s.cases[i].id.size() != 16) std::abort();
  } catch (const rodend::InputError& e) {
    if (std::string_view(e.what()).find("fuzz.json") == std::string_view::npos) {
      std::fprintf(stderr, "InputError without the file name: %s\n", e.what());
      std::abort();
    }
  } catch (const rodend::Json::exception&) {
    // nlohmann's type errors on values the loader reads: allowed by the brief, but rare
  }
  return 0;
}
