// The `iaa` command: builds the CLI from the registered subcommands, runs the chosen one, and
// turns every user-input error into one line on stderr and a non-zero exit code. Under mpirun
// (docs/distributed.md) every process runs the command; the processes agree on its outcome so
// that all of them exit non-zero when one failed, and the error is printed once.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string_view>

#include "core/error.h"
#include "dist/world.h"
#include "iaa/command.h"

namespace iaa::cli {

std::vector<Command>& commands() {
  static std::vector<Command> all;
  return all;
}

}  // namespace iaa::cli

namespace {

using namespace iaa::cli;

/// The registered command named by the first argument that is not an option, or null.
const Command* named_command(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    if (a.starts_with("-")) continue;
    for (const Command& c : commands()) {
      if (c.name == a) return &c;
    }
    return nullptr;
  }
  return nullptr;
}

/// Prints an error, with the rank of the process that met it when it is not the lead, or when
/// the lead alone met it (`alone`: in the middle of the run, not bad input that all would see).
void print_error(const std::string& cmd, const std::string& what, const iaa::dist::World& w,
                 bool alone = false) {
  if (w.size() > 1 && (!w.lead() || alone)) {
    std::fprintf(stderr, "%s: error (MPI rank %d): %s\n", cmd.c_str(), w.rank(), what.c_str());
  } else {
    std::fprintf(stderr, "%s: error: %s\n", cmd.c_str(), what.c_str());
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::unique_ptr<iaa::dist::World> world;
  try {
    world = std::make_unique<iaa::dist::World>();
  } catch (const iaa::Error& e) {
    if (iaa::dist::launcher_rank() == 0) std::fprintf(stderr, "iaa: error: %s\n", e.what());
    return 1;
  }
  CLI::App app{
      "iaa: guaranteed ray tracing, enclosure, meshing and inspection of implicit "
      "surfaces f(x,y,z) = 0 with interval arithmetic"};
  app.require_subcommand(1);
  app.footer(
      "Examples:\n"
      "  iaa eval 'x^2 + y^2 + z^2 - 1' --box -1:1,0:1,0.5:0.6\n"
      "  iaa render data/scenes/teardrop.toml -o teardrop.png\n"
      "  iaa inspect data/scenes/teardrop.toml --pixel 256,250\n"
      "  mpirun -np 4 iaa render data/scenes/chubs.toml -o chubs.png --threads 1\n"
      "Run 'iaa COMMAND --help' for the options of one command.");
  auto& cmds = commands();
  std::sort(cmds.begin(), cmds.end(),
            [](const Command& a, const Command& b) { return a.order < b.order; });
  for (const Command& c : cmds) {
    CLI::App* sub = app.add_subcommand(c.name, c.summary);
    c.setup(*sub);
  }

  std::string cmd = "iaa", error;
  bool stopped = false;
  if (const Command* c = named_command(argc, argv)) cmd = "iaa " + c->name;
  if (world->size() > 1) {
    // Every process decides the same from the same arguments: no agreement is needed.
    const Command* c = named_command(argc, argv);
    if (c && !c->mpi) {
      if (world->lead()) {
        std::fprintf(stderr,
                     "%s: error: this command does not run under mpirun with more than one "
                     "process (render, enclose and mesh do); run it without mpirun\n",
                     cmd.c_str());
      }
      return 1;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Help and usage errors: the same on every process, printed by the lead.
    if (!world->lead()) return e.get_exit_code();
    return app.exit(e);
  } catch (const iaa::dist::Stopped&) {
    return 1;  // another process failed and said so at an agreement, which this one took part in
  } catch (const iaa::dist::PeerFailed&) {
    stopped = true;  // another process failed in the middle of the run: it reports why
  } catch (const iaa::Error& e) {
    error = e.what();
  } catch (const std::bad_alloc&) {
    error = "out of memory";
  } catch (const std::filesystem::filesystem_error& e) {
    error = e.what();  // moving the .pvtu pieces into place (cmd_enclose.cpp)
  }
  if (!world->active()) {
    if (error.empty()) return 0;
    print_error(cmd, error, *world);
    return 1;
  }
  // Under mpirun: agree on the outcome. A process that failed before the command's own agreement
  // joins that one; otherwise this is the final one (or the one before the outputs are written,
  // World::agree_done(), where the others are). A process that failed after the input checks first
  // tells the others, whose loops then stop at once (PeerFailed) and join this agreement; it
  // waits at most 10 s for them (one may be stuck or gone), then ends the whole run.
  const bool ok = error.empty() && !stopped;
  if (!error.empty()) world->announce_failure();
  const iaa::dist::World::Outcome out = world->agree(ok, !error.empty(), ok ? 0.0 : 10.0);
  if (out.timed_out) {
    if (!error.empty()) {
      print_error(cmd, error + " (the other processes did not answer: ending the run)", *world);
    }
    world->abort(1);
  }
  if (!error.empty() && (world->lead() || out.lead_ok)) {
    print_error(cmd, error, *world, world->lead() && out.others_ok);
  }
  return out.all_ok ? 0 : 1;
}
