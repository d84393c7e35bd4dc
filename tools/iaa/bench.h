// `iaa bench WHAT`: each benchmark lives in its own bench_*.cpp and registers itself here, the same
// way subcommands do (command.h). Benchmarks report medians and ratios against a baseline measured
// in the same run; they print a table on stdout and, with --json FILE, write the same as data.
#pragma once

#include <CLI/CLI.hpp>

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

}  // namespace iaa::cli
