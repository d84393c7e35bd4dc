// dist/world.h over MPI.
#include <mpi.h>

#include <cstdio>

#include "dist/mpi_spread.h"
#include "dist/mpi_util.h"
#include "dist/world.h"

namespace iaa::dist {

namespace {
World* g_world = nullptr;
/// The agreements' communicator (a duplicate of MPI_COMM_WORLD): a collective of a spread's loop
/// that a failure left pending on MPI_COMM_WORLD cannot be matched with an agreement.
MPI_Comm g_agree = MPI_COMM_NULL;
/// What announce_failure() sends; it must outlive the sends, which are never waited for.
const int g_failure_notice = 1;
}  // namespace

bool built_with_mpi() {
  return true;
}

World::World() {
  if (!launched_by_mpirun()) return;
  // Serialized: the spread calls MPI from one thread at a time (rank 0's service thread while its
  // workers compute, a worker thread of another rank under a mutex).
  int provided = 0;
  mpi_check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided), "MPI_Init_thread");
  active_ = true;
  g_world = this;
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  mpi_check(MPI_Comm_dup(MPI_COMM_WORLD, &g_agree), "MPI_Comm_dup");
  MPI_Comm_set_errhandler(g_agree, MPI_ERRORS_RETURN);
  if (provided < MPI_THREAD_SERIALIZED) {
    throw Error("MPI: this MPI library does not support threads (MPI_THREAD_SERIALIZED)");
  }
}

World::~World() {
  if (!active_) return;
  g_world = nullptr;
  if (g_agree != MPI_COMM_NULL) MPI_Comm_free(&g_agree);
  MPI_Finalize();
}

World* World::current() {
  return g_world;
}

World::Outcome World::agree(bool ok, double deadline) {
  return agree(ok, !ok, deadline);
}

World::Outcome World::agree(bool ok, bool own_error, double deadline) {
  agreed_ = true;
  if (!active_) return {ok, !own_error, false, true};
  // Bit 0: some process failed; bit 1: the lead met an error of its own; bit 2: another did.
  int mine = (ok ? 0 : 1) | (own_error ? (rank_ == 0 ? 2 : 4) : 0);
  int all = 0;
  MPI_Request req;
  mpi_check(MPI_Iallreduce(&mine, &all, 1, MPI_INT, MPI_BOR, g_agree, &req), "MPI_Iallreduce");
  if (!mpi_wait(req, deadline)) return {false, false, true};
  return {(all & 1) == 0, (all & 2) == 0, false, (all & 4) == 0};
}

void World::agree_input() {
  if (!active_) return;
  if (!agree(true).all_ok) throw Stopped{};
}

void World::agree_done() {
  if (!active_) return;
  if (!agree(true).all_ok) throw Stopped{};
}

void World::announce_failure() {
  if (!active_ || !agreed_) return;
  for (int r = 0; r < size_; ++r) {
    if (r == rank_) continue;
    MPI_Request req;
    // Small: sent eagerly, so freeing the request does not lose it; MPI_Finalize flushes it.
    if (MPI_Isend(&g_failure_notice, 1, MPI_INT, r, kFailureTag, MPI_COMM_WORLD, &req) ==
        MPI_SUCCESS) {
      MPI_Request_free(&req);
    }
  }
}

std::unique_ptr<Spread> World::spread() {
  if (!active_) return nullptr;
  return std::make_unique<MpiSpread>(*this);
}

void World::abort(int code) {
  std::fflush(stdout);
  std::fflush(stderr);
  MPI_Abort(MPI_COMM_WORLD, code);
  std::_Exit(code);  // not reached: MPI_Abort ends the process
}

}  // namespace iaa::dist
