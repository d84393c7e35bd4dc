// `iaa bench WHAT`: each benchmark lives in its own bench_*.cpp and registers itself here, the same
// way subcommands do (command.h). Benchmarks report medians and ratios against a baseline measured
// in the same run; they print a table on stdout and, with --json FILE, write the same as data.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace iaa::cli {

struct BenchCommand {
  std::string name;
  std::string summary;
  std::function<void(CLI::App&)> setup;
};

std::vector<BenchCommand>& bench_commands();

struct BenchRegistrar {
  explicit BenchRegistrar(BenchCommand c) { bench_commands().push_back(std::move(c)); }
};

/// The peak resident memory of one measured run, from Linux's /proc/self/status (VmHWM, the
/// high-water mark of the process's resident set). Made just before the run, it returns freed heap
/// to the system (malloc_trim) and resets the mark (writes 5 to /proc/self/clear_refs), so that
/// peak_bytes() after the run is that run's peak (it includes what the process held before the
/// run: the binary, the scenes, images kept for comparison). Where the reset is refused, the
/// peak is the process's since it started, and exact() says so.
class PeakMemory {
 public:
  PeakMemory();
  /// The high-water mark now, in bytes; 0 where /proc/self/status has none.
  std::uint64_t peak_bytes() const;
  /// The resident memory when the measurement started, in bytes.
  std::uint64_t start_bytes() const { return start_; }
  /// The mark was reset: peak_bytes() is this run's peak.
  bool exact() const { return exact_; }

 private:
  std::uint64_t start_ = 0;
  bool exact_ = false;
};

/// The line under a table with a `peak MiB` column that says what it is.
inline constexpr const char* kPeakNote =
    "peak MiB: the process's peak resident memory during a run, the largest of the runs\n"
    "(* where it could not be reset per run: the peak since the benchmark started).";

/// Bytes as MiB, for the tables and the JSON reports.
double mib(std::uint64_t bytes);

}  // namespace iaa::cli
