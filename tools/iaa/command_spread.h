// The spread with which `iaa render`, `iaa enclose` and `iaa mesh` share their loops under mpirun
// (dist::World::spread(), docs/distributed.md), and a failure on purpose for the tests.
#pragma once

#include <memory>

#include "core/spread.h"
#include "dist/world.h"

namespace iaa::cli {

/// The world's spread, or null outside mpirun. FOR TESTS ONLY: when the environment holds
/// IAA_TEST_FAIL_RANK=K, process K of the run throws an error at its second request for an item
/// (it has computed one item of the first loop), so that tests/e2e/mpi_cli.sh can check what one
/// process failing in the middle of the run does to the others. The library knows nothing of it.
std::unique_ptr<Spread> command_spread(dist::World* world);

}  // namespace iaa::cli
