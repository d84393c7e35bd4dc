// dist/world.h in a build without MPI (IAA_WITH_MPI=OFF): there is never more than one process,
// and being started by mpirun is an error rather than N copies of one run writing the same files.
#include <cstdlib>

#include "core/error.h"
#include "dist/world.h"
#include "dist/world_env.h"

namespace iaa::dist {

bool built_with_mpi() {
  return false;
}

World::World() {
  if (launched_by_mpirun()) {
    throw Error(
        "started by mpirun, but this iaa was built without MPI (IAA_WITH_MPI=OFF); install "
        "libopenmpi-dev and rebuild, or run it without mpirun");
  }
}

World::~World() = default;

World* World::current() {
  return nullptr;
}

World::Outcome World::agree(bool ok, double) {
  return {ok, ok};
}

World::Outcome World::agree(bool ok, bool own_error, double) {
  return {ok, !own_error, false, true};
}

void World::agree_input() {}

void World::agree_done() {}

void World::announce_failure() {}

std::unique_ptr<Spread> World::spread() {
  return nullptr;
}

void World::abort(int code) {
  std::exit(code);
}

}  // namespace iaa::dist
