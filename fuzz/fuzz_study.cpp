// libFuzzer target for the study loader: the fuzz input is the text of a study file, handed to
// rodend::parse_study_text (everything load_study does after reading the file: NUL bytes, JSON
// syntax, duplicate keys, then parse_study). It must either return a study or throw InputError.
// Properties checked:
// - a refused study names the file, and a key path unless the fault is the document's own
//   (syntax, NUL byte, number out of range, not an object, nesting);
// - an accepted study is consistent (one 16-digit id per case, cases in grid order) and round
//   trips: the study.json a run writes (the parsed source, dumped) loads again to the same ids.
// Anything else (another exception, a crash, a leak, an AddressSanitizer or
// UndefinedBehaviorSanitizer report, a timeout) is a bug.
//
// Built only with clang and -DRODEND_FUZZ=ON (docs/testing.md):
//   CXX=clang++-14 CC=clang-14 cmake -S . -B build-fuzz -DRODEND_FUZZ=ON
//   -DCMAKE_BUILD_TYPE=RelWithDebInfo cmake --build build-fuzz --target fuzz_study -j2
//   build-fuzz/fuzz/fuzz_study -max_total_time=600 -dict=fuzz/study.dict fuzz/corpus-work
//   fuzz/corpus
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "core/errors.hpp"
#include "sweep/study.hpp"

namespace {

bool document_level(const rodend::InputError& e) {
  const std::string& p = e.problem();
  for (const char* prefix : {"JSON syntax error", "number out of range", "a NUL byte",
                             "a study must be a JSON object", "the document is nested"})
    if (p.rfind(prefix, 0) == 0) return true;
  return false;
}

[[noreturn]] void fail(const char* what, const std::string& detail) {
  std::fprintf(stderr, "%s: %s\n", what, detail.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const rodend::Study s = rodend::parse_study_text(text, "fuzz.json", "fuzz-results");
    for (std::size_t i = 0; i < s.cases.size(); ++i)
      if (s.cases[i].index != static_cast<long>(i) || s.cases[i].id.size() != 16)
        fail("inconsistent case", s.cases[i].id);
    // round trip through the study.json a run writes
    const rodend::Study again =
        rodend::parse_study_text(s.source.dump(2) + "\n", "fuzz.json", "fuzz-results");
    if (again.cases.size() != s.cases.size()) fail("round trip", "case count differs");
    for (std::size_t i = 0; i < s.cases.size(); ++i)
      if (again.cases[i].id != s.cases[i].id) fail("round trip", "case id differs");
  } catch (const rodend::InputError& e) {
    if (std::string_view(e.what()).find("fuzz.json") == std::string_view::npos)
      fail("InputError without the file name", e.what());
    if (e.key_path().empty() && !document_level(e)) fail("InputError without a key path", e.what());
  }
  return 0;
}
