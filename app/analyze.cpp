#include "app/analyze.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>

namespace rodend {

int exec_python_module(const std::string& module, const std::vector<std::string>& args) {
  namespace fs = std::filesystem;
  const char* env_python = std::getenv("RODEND_PYTHON");
  const std::string python = env_python && *env_python ? env_python : "/usr/bin/python3";
  std::string path = RODEND_PYTHON_SOURCE_DIR;
  if (const char* old = std::getenv("PYTHONPATH"); old && *old) path += std::string(":") + old;
  ::setenv("PYTHONPATH", path.c_str(), 1);
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (!ec && !std::getenv("RODEND_BUILD_DIR"))
    ::setenv("RODEND_BUILD_DIR", self.parent_path().c_str(), 0);
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
