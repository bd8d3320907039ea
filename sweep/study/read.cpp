// Reading a study file: its text (a regular file of at most 16 MiB), its JSON (no NUL byte,
// no key twice in one object, numbers a double holds; errors at their line and column), then
// the --set overrides (overrides.cpp) and parse_study.
#include <algorithm>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "sweep/study.hpp"

namespace rodend {
namespace fs = std::filesystem;

namespace {

/// Largest study file read (a study is a few kilobytes; a grid of 1e5 explicit values is about
/// 2 MB): anything larger is refused before it is read.
constexpr std::uintmax_t kMaxStudyBytes = 16u << 20;

/// Reads a study file: a regular file of at most kMaxStudyBytes, with no NUL byte.
std::string read_study_text(const fs::path& file) {
  const std::string name = file.string();
  std::error_code ec;
  const fs::file_status st = fs::status(file, ec);
  if (ec && ec != std::errc::no_such_file_or_directory)  // a loop of links, no permission, ...
    throw InputError("", "cannot open the study file: " + ec.message(), name);
  if (ec || !fs::exists(st)) throw InputError("", "cannot open the study file: no such file", name);
  if (fs::is_directory(st))
    throw InputError("", "is a directory; expected a study file (JSON)", name);
  if (!fs::is_regular_file(st))
    throw InputError("",
                     "is not a regular file (a device, FIFO or socket); expected a study "
                     "file (JSON)",
                     name);
  const std::uintmax_t size = fs::file_size(file, ec);
  auto too_large = [&] {
    return InputError("",
                      "is larger than 16 MiB, the limit of a study file; expected a study of "
                      "a few kilobytes (a grid is written as linspace/logspace axes)",
                      name);
  };
  if (!ec && size > kMaxStudyBytes) throw too_large();
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError("", "cannot open the study file", name);
  // in pieces of the size the file had (not into one zero-filled buffer of the limit: that
  // touched 16 MiB of memory in every run, most of a small sweep's peak RSS)
  const std::size_t piece = std::clamp<std::size_t>(ec ? 0 : size + 1, 4096, kMaxStudyBytes + 1);
  std::string text;
  while (in && text.size() <= kMaxStudyBytes) {
    const std::size_t have = text.size();
    text.resize(have + std::min(piece, kMaxStudyBytes + 1 - have));
    in.read(text.data() + have, static_cast<std::streamsize>(text.size() - have));
    text.resize(have + static_cast<std::size_t>(in.gcount()));
  }
  if (text.size() > kMaxStudyBytes) throw too_large();  // it grew while being read
  return text;
}

/// Key path of the value being parsed, from the parser's nesting (for duplicate-key messages).
struct KeyTracker {
  struct Level {
    bool array = false;
    std::size_t index = 0;          // next element of an array
    std::vector<std::string> keys;  // keys seen in an object
  };
  std::vector<Level> stack;
  std::string duplicate;  // key path of the first duplicate key, empty if none

  std::string path(const std::string& last) const {
    std::string p;
    for (std::size_t i = 0; i + 1 < stack.size(); ++i) {
      const Level& l = stack[i];
      if (l.array)
        p += "[" + std::to_string(l.index) + "]";
      else
        p += (p.empty() ? "" : ".") + l.keys.back();
    }
    return p.empty() ? last : p + "." + last;
  }
  void element_done() {
    if (!stack.empty() && stack.back().array) ++stack.back().index;
  }
};

std::pair<std::size_t, std::size_t> line_column(const std::string& text, std::size_t byte) {
  std::size_t line = 1, col = 1;
  for (std::size_t i = 0; i < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return {line, col};
}

/// Parses JSON text, refusing a key that appears twice in one object: nlohmann keeps the last
/// one, which would silently drop a value the user wrote.
Json parse_unique_keys(const std::string& text, const fs::path& file) {
  KeyTracker keys;
  auto callback = [&keys](int, Json::parse_event_t event, Json& parsed) {
    using E = Json::parse_event_t;
    switch (event) {
      case E::object_start:
      case E::array_start:
        keys.stack.push_back({event == E::array_start, 0, {}});
        break;
      case E::object_end:
      case E::array_end:
        keys.stack.pop_back();
        keys.element_done();
        break;
      case E::key: {
        auto& seen = keys.stack.back().keys;
        const std::string k = parsed.get<std::string>();
        if (keys.duplicate.empty() && std::find(seen.begin(), seen.end(), k) != seen.end())
          keys.duplicate = keys.path(k);
        seen.push_back(k);
        break;
      }
      case E::value:
        keys.element_done();
        break;
    }
    return true;
  };
  Json doc = Json::parse(text, callback);
  if (!keys.duplicate.empty())
    throw InputError(keys.duplicate,
                     "the same key appears twice in one object; expected each key once (the "
                     "later value would silently replace the earlier)",
                     file.string());
  return doc;
}

/// The study's JSON document; a NUL byte, a syntax error or a number out of range is an
/// InputError naming the file and the line and column.
Json parse_study_json(const std::string& text, const fs::path& file) {
  if (text.find('\0') != std::string::npos) {
    const auto [line, col] = line_column(text, text.find('\0'));
    throw InputError("",
                     "a NUL byte at line " + std::to_string(line) + ", column " +
                         std::to_string(col) + "; expected JSON text (UTF-8) with no NUL byte",
                     file.string());
  }
  try {
    return parse_unique_keys(text, file);
  } catch (const Json::out_of_range& e) {
    // a number JSON can write but a double cannot hold (1e400)
    std::string what = e.what();
    const auto colon = what.find("] ");
    throw InputError(
        "",
        "number out of range: " + (colon == std::string::npos ? what : what.substr(colon + 2)) +
            " (expected a finite number)",
        file.string());
  } catch (const Json::parse_error& e) {
    const auto [line, col] = line_column(text, e.byte > 0 ? e.byte - 1 : 0);
    std::string what = e.what();
    // nlohmann's message starts with "[json.exception.parse_error.101] parse error at ..."
    const auto colon = what.find(": ");
    const std::string detail = colon == std::string::npos ? what : what.substr(colon + 2);
    throw InputError("",
                     "JSON syntax error at line " + std::to_string(line) + ", column " +
                         std::to_string(col) + ": " + detail,
                     file.string());
  }
}

}  // namespace

Study load_study(const fs::path& file, const fs::path& results_root,
                 const std::vector<std::string>& overrides) {
  return parse_study_text(read_study_text(file), file, results_root, overrides);
}

Study parse_study_text(const std::string& text, const fs::path& file, const fs::path& results_root,
                       const std::vector<std::string>& overrides) {
  Json doc = parse_study_json(text, file);
  if (overrides.empty()) return parse_study(doc, file, results_root);
  Study study =
      parse_study(apply_overrides(std::move(doc), overrides, file), file, results_root, overrides);
  study.overrides = overrides;
  return study;
}

}  // namespace rodend
