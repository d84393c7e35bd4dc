// The `iaa` command: builds the CLI from the registered subcommands, runs the chosen one, and
// turns every user-input error into one line on stderr and a non-zero exit code.
#include <algorithm>
#include <cstdio>
#include <sstream>

#include "core/error.h"
#include "iaa/command.h"

namespace iaa::cli {

std::vector<Command>& commands() {
  static std::vector<Command> all;
  return all;
}

}  // namespace iaa::cli

int main(int argc, char** argv) {
  using namespace iaa::cli;
  CLI::App app{
      "iaa: guaranteed ray tracing, enclosure, meshing and inspection of implicit "
      "surfaces f(x,y,z) = 0 with interval arithmetic"};
  app.require_subcommand(1);
  app.footer(
      "Examples:\n"
      "  iaa eval 'x^2 + y^2 + z^2 - 1' --box -1:1,0:1,0.5:0.6\n"
      "  iaa render data/scenes/teardrop.toml -o teardrop.png\n"
      "  iaa inspect data/scenes/teardrop.toml --pixel 256,250\n"
      "Run 'iaa COMMAND --help' for the options of one command.");
  auto& cmds = commands();
  std::sort(cmds.begin(), cmds.end(),
            [](const Command& a, const Command& b) { return a.order < b.order; });
  for (const Command& c : cmds) {
    CLI::App* sub = app.add_subcommand(c.name, c.summary);
    c.setup(*sub);
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const iaa::Error& e) {
    const std::string cmd =
        app.get_subcommands().empty() ? "iaa" : "iaa " + app.get_subcommands()[0]->get_name();
    std::fprintf(stderr, "%s: error: %s\n", cmd.c_str(), e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "iaa: error: out of memory\n");
    return 1;
  }
  return 0;
}
