#include "app/analyze.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>

extern char** environ;

namespace rodend {

namespace {

namespace fs = std::filesystem;

/// Whether `python` imports `module` by itself (PYTHONPATH, its site-packages, a venv's install
/// by `pip install`): `python -c` with find_spec, its output discarded.
bool importable(const std::string& python, const std::string& module) {
  const std::string code = "import importlib.util as u, sys\ntry:\n  sys.exit(0 if u.find_spec('" +
                           module + "') else 1)\nexcept Exception:\n  sys.exit(1)\n";
  posix_spawn_file_actions_t io;
  posix_spawn_file_actions_init(&io);
  posix_spawn_file_actions_addopen(&io, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&io, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  std::string p = python, flag = "-c", c = code;
  char* argv[] = {p.data(), flag.data(), c.data(), nullptr};
  pid_t pid = 0;
  const int rc = ::posix_spawn(&pid, python.c_str(), &io, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&io);
  if (rc != 0) return false;
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

/// The folder holding the package rodend/ when `python` cannot import it by itself: beside the
/// install prefix of this executable (PREFIX/<datadir>/rodend/python, `cmake --install`), else
/// the source tree named by the file the configure step writes beside the executable of a build
/// tree. Empty when neither has it; `tried` lists where it looked.
fs::path package_folder(const fs::path& exe_dir, std::string& tried) {
  const auto has_package = [](const fs::path& d) {
    return fs::exists(d / "rodend" / "__init__.py");
  };
  fs::path installed = RODEND_INSTALL_PYTHON_DIR;
  if (installed.is_relative()) installed = exe_dir.parent_path() / installed;
  tried += ", " + installed.string();
  if (has_package(installed)) return installed;
  const fs::path pointer = exe_dir / "rodend-python-path";
  tried += ", " + pointer.string();
  std::ifstream in(pointer);
  std::string source;
  if (in && std::getline(in, source) && has_package(source)) {
    tried += " (" + source + ")";
    return source;
  }
  return {};
}

}  // namespace

int exec_python_module(const std::string& module, const std::vector<std::string>& args) {
  const char* env_python = std::getenv("RODEND_PYTHON");
  const std::string python = env_python && *env_python ? env_python : "/usr/bin/python3";
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (!ec && !std::getenv("RODEND_BUILD_DIR"))
    ::setenv("RODEND_BUILD_DIR", self.parent_path().c_str(), 0);
  // a Python that does not run is said below, by the exec that fails
  if (::access(python.c_str(), X_OK) == 0 && !importable(python, module)) {
    std::string tried = "importable by " + python;
    const fs::path folder = ec ? fs::path() : package_folder(self.parent_path(), tried);
    if (folder.empty()) {
      std::cerr << "rodend: error: cannot find the Python package rodend for " << module
                << "; looked for it " << tried
                << " (install it with `pip install .` from the source tree into that Python's "
                   "environment, or set PYTHONPATH to the source tree's python/ folder)\n";
      return 2;
    }
    std::string path = folder.string();
    if (const char* old = std::getenv("PYTHONPATH"); old && *old) path += std::string(":") + old;
    ::setenv("PYTHONPATH", path.c_str(), 1);
  }
  std::vector<std::string> argv_s{python, "-m", module};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);
  ::execv(python.c_str(), argv.data());
  std::cerr << "rodend: error: cannot run " << python << " for " << module << ": "
            << std::strerror(errno)
            << " (set RODEND_PYTHON to a Python 3 with numpy, h5py, matplotlib and openturns)\n";
  return 2;
}

int exec_analyze(const std::vector<std::string>& args) {
  return exec_python_module("rodend.analyze", args);
}

int exec_calibrate(const std::vector<std::string>& args) {
  return exec_python_module("rodend.calibrate", args);
}

}  // namespace rodend
