// Shared by the GoogleTest end-to-end suites: run a built command through the shell and capture
// its exit status, standard output and standard error.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace iaa::e2e {

struct Outcome {
  int status = -1;  ///< exit status, -1 when the command did not exit normally
  std::string out, err;
};

/// Runs a shell command; captures stdout and stderr (stderr through a per-process scratch file).
inline Outcome run(const std::string& cmd) {
  namespace fs = std::filesystem;
  static int n = 0;
  const fs::path err = fs::temp_directory_path() /
                       ("iaa_e2e_err_" + std::to_string(::getpid()) + "_" + std::to_string(n++));
  Outcome r;
  FILE* p = ::popen((cmd + " 2>'" + err.string() + "'").c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  std::size_t k = 0;
  while ((k = std::fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), k);
  const int st = ::pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  std::ifstream e(err);
  std::stringstream ss;
  ss << e.rdbuf();
  r.err = ss.str();
  fs::remove(err);
  return r;
}

/// A path in single quotes for the shell (built with append: GCC 12 warns falsely on "'" + s).
inline std::string quoted(const std::string& s) {
  std::string q(1, '\'');
  q.append(s).append(1, '\'');
  return q;
}

}  // namespace iaa::e2e
