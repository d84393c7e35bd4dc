// Whole-file reads and atomic writes (files.h). Application layer: used by tools/ and viz/, never
// by the library modules.
#include "app/files.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace iaa::app {

namespace fs = std::filesystem;

std::string read_file(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw Error("cannot read '" + path + "': it is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read '" + path + "': " + std::strerror(errno));
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

namespace {

/// The directory a file at `path` is created in.
fs::path directory_of(const fs::path& target) {
  return target.has_parent_path() ? target.parent_path() : fs::path(".");
}

}  // namespace

void check_writable(const std::string& path, const std::string& prefix) {
  const fs::path dir = directory_of(path);
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    throw Error(prefix + "cannot write '" + path + "': directory '" + dir.string() +
                "' does not exist");
  }
  if (::access(dir.c_str(), W_OK) != 0) {
    throw Error(prefix + "cannot write '" + path + "': directory '" + dir.string() +
                "' is not writable");
  }
}

void write_atomically(const std::string& path,
                      const std::function<void(const std::string&)>& write) {
  if (path.empty()) throw Error("empty output path");
  check_writable(path);
  const fs::path target(path);
  const fs::path dir = directory_of(target);
  std::error_code ec;
  if (fs::is_directory(target, ec)) throw Error("cannot write '" + path + "': it is a directory");
  // Keep the extension last: some writers (VTK, OpenMesh) choose the format from it.
  // Built with append rather than "." + ...: GCC 12 warns falsely (-Wrestrict, PR 105651).
  std::string name(1, '.');
  name.append(target.stem().string()).append(".tmp").append(std::to_string(::getpid()));
  name.append(target.extension().string());
  const std::string tmp = (dir / name).string();
  try {
    write(tmp);
    if (!fs::exists(tmp, ec)) throw Error("writing '" + path + "' produced no file");
    fs::rename(tmp, target, ec);
    if (ec) throw Error("cannot write '" + path + "': " + ec.message());
  } catch (...) {
    fs::remove(tmp, ec);
    throw;
  }
}

void write_text_atomically(const std::string& path, const std::string& contents) {
  write_atomically(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out << contents;
    out.close();
    if (!out) throw Error("cannot write '" + path + "': " + std::strerror(errno));
  });
}

std::string extension_of(const std::string& path) {
  std::string e = fs::path(path).extension().string();
  if (!e.empty()) e.erase(0, 1);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

}  // namespace iaa::app
