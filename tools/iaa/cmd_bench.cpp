// `iaa bench`: the umbrella for the registered benchmarks (bench.h).
#include <algorithm>

#include "iaa/bench.h"
#include "iaa/command.h"

namespace iaa::cli {

std::vector<BenchCommand>& bench_commands() {
  static std::vector<BenchCommand> all;
  return all;
}

namespace {

void setup(CLI::App& app) {
  app.require_subcommand(1);
  auto& all = bench_commands();
  std::sort(all.begin(), all.end(),
            [](const BenchCommand& a, const BenchCommand& b) { return a.name < b.name; });
  for (const BenchCommand& b : all) b.setup(*app.add_subcommand(b.name, b.summary));
  app.footer(
      "Examples:\n"
      "  iaa bench tape\n"
      "  iaa bench tape --json tape.json");
}

CommandRegistrar reg{
    {"bench", "measure speed (medians, ratios against a baseline of the same run)", 90, setup}};

}  // namespace
}  // namespace iaa::cli
