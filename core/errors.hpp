// Errors in user input: they name the file, the key path and what was expected.
#pragma once

#include <stdexcept>
#include <string>

namespace rodend {

/// Bad input. `key_path` is a dotted path into the input (e.g. "parameters.contact.clearance");
/// `file` is filled in by whoever knows which file the value came from.
class InputError : public std::runtime_error {
 public:
  InputError(std::string key_path, std::string problem, std::string file = {})
      : std::runtime_error(compose(file, key_path, problem)),
        file_(std::move(file)),
        key_path_(std::move(key_path)),
        problem_(std::move(problem)) {}

  const std::string& file() const { return file_; }
  const std::string& key_path() const { return key_path_; }
  const std::string& problem() const { return problem_; }

  /// The same error, located in `file` and with `prefix.` before its key path.
  InputError located(const std::string& file, const std::string& prefix = {}) const {
    std::string path = prefix.empty()      ? key_path_
                       : key_path_.empty() ? prefix
                                           : prefix + "." + key_path_;
    return InputError(path, problem_, file.empty() ? file_ : file);
  }

 private:
  static std::string compose(const std::string& file, const std::string& key,
                             const std::string& problem) {
    std::string s;
    if (!file.empty()) s += file + ": ";
    if (!key.empty()) s += key + ": ";
    return s + problem;
  }
  std::string file_, key_path_, problem_;
};

}  // namespace rodend
