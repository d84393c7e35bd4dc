// The peak resident memory of a measured run (bench.h, PeakMemory): Linux's VmHWM, reset per run.
#include <malloc.h>

#include <fstream>
#include <string>

#include "iaa/bench.h"

namespace iaa::cli {
namespace {

/// A "Name:   1234 kB" line of /proc/self/status, in bytes; 0 when it is not there.
std::uint64_t status_bytes(const std::string& name) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(name + ":", 0) == 0) return std::stoull(line.substr(name.size() + 1)) * 1024;
  }
  return 0;
}

}  // namespace

PeakMemory::PeakMemory() {
  // Freed blocks glibc keeps would count as resident from the start: give them back first.
  malloc_trim(0);
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5" << std::flush;  // "5" resets the peak resident set size to the current one
  exact_ = clear.good();
  start_ = status_bytes("VmRSS");
}

std::uint64_t PeakMemory::peak_bytes() const {
  return status_bytes("VmHWM");
}

double mib(std::uint64_t bytes) {
  return static_cast<double>(bytes) / (1024.0 * 1024.0);
}

}  // namespace iaa::cli
