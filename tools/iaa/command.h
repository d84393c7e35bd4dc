// Subcommand registry of the `iaa` tool. Each subcommand lives in its own cmd_*.cpp and registers
// itself with a static `CommandRegistrar`; main() builds the CLI from the registry. A subcommand's
// setup function adds its options to its CLI11 sub-app and sets the callback that runs it. The
// callback throws iaa::Error for bad input; main turns that into a message and exit code 1 (under
// mpirun, on every process, with the message printed once: dist/world.h).
#pragma once

#include <CLI/CLI.hpp>

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "core/vec.h"
#include "expr/parser.h"

namespace iaa::cli {

struct Command {
  std::string name;
  std::string summary;
  int order;  ///< position in `iaa --help`
  std::function<void(CLI::App&)> setup;
  /// Runs under `mpirun -np N` with N > 1, sharing its work (docs/distributed.md). Such a command
  /// calls dist::World::agree_input() once after checking its input, and writes its files on the
  /// lead process only.
  bool mpi = false;
};

std::vector<Command>& commands();

struct CommandRegistrar {
  explicit CommandRegistrar(Command c) { commands().push_back(std::move(c)); }
};

/// Parses one finite number (subnormals included); throws iaa::Error naming `what` on failure.
double parse_double(const std::string& text, const std::string& what);

/// Parses a box "X0:X1,Y0:Y1,Z0:Z1" of finite numbers with LO <= HI on every axis; throws
/// iaa::Error naming `what` and the axis on failure.
Box3 parse_box(const std::string& text, const std::string& what);

/// Parses "a,b,c" into three doubles; throws iaa::Error naming `what` on failure.
std::array<double, 3> parse_triple(const std::string& text, const std::string& what);

/// Parses "a,b" into two integers; throws iaa::Error naming `what` on failure.
std::array<int, 2> parse_int_pair(const std::string& text, const std::string& what);

/// Parses the `--param NAME=VALUE` items of an expression given on the command line; throws
/// iaa::Error naming --param and the item on failure.
Params parse_params(const std::vector<std::string>& items);

/// Adds the positional SCENE argument and the repeatable `--set KEY=VALUE` option to a command;
/// app::load_scene(path, overrides) loads what they name.
void add_scene_options(CLI::App& app, std::string* path, std::vector<std::string>* overrides);

}  // namespace iaa::cli
