// The processes of a run under `mpirun` (docs/distributed.md). World starts MPI when the program
// was launched by mpirun (and only then: run alone, iaa does not touch MPI and behaves as it always
// did) and finishes it on destruction. Commands that share their work call agree() once after
// their input is checked, so that bad input on any process stops every process cleanly; main()
// calls finish() with the command's outcome, so that every process exits with the same status and
// an error is printed once. Only this module includes <mpi.h> (tools/check_layers.cmake).
#pragma once

#include <memory>
#include <string>

#include "core/spread.h"
#include "dist/world_env.h"

namespace iaa::dist {

/// Thrown by agree_input() and agree_done() on a process that was fine when another was not:
/// that process's error has been reported there, this one only exits non-zero (it has taken part
/// in the agreement already).
struct Stopped {};

/// Thrown by a spread's loop (MpiSpread) on a process that learned, while it waited for work or
/// results, that process `rank` failed in the middle of the run (announce_failure()): this one
/// stops at once and joins the final agreement, where the failed one reports its error.
struct PeerFailed {
  int rank = -1;
};

/// True when this build has MPI (the CMake option IAA_WITH_MPI).
bool built_with_mpi();

class World {
 public:
  /// Starts MPI when launched by mpirun, else is a world of one process that does nothing.
  /// Throws iaa::Error when launched by mpirun in a build without MPI, or when MPI lacks the
  /// thread support the spread needs.
  World();
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  /// The world of the running program, or null when there is none (not under mpirun).
  static World* current();

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool active() const { return active_; }
  bool lead() const { return rank_ == 0; }

  /// Outcome of an agreement: whether every process was fine, and whether the lead was free of
  /// an error of its own (it may have stopped for another's, PeerFailed).
  struct Outcome {
    bool all_ok = true;
    bool lead_ok = true;
    bool timed_out = false;  ///< the deadline passed first (the others are stuck or gone)
    bool others_ok = true;   ///< no process but the lead met an error of its own
  };
  /// Collective: every process says whether it is fine, and whether it met an error of its own
  /// (`own_error`; by default, not being fine). Waits without spinning, or at most `deadline`
  /// seconds when positive. Agreements have a communicator of their own, so that a loop of a
  /// spread that a failure left unfinished does not meet them.
  Outcome agree(bool ok, double deadline = 0);
  Outcome agree(bool ok, bool own_error, double deadline);
  /// The command's agreement after its input checks: returns when every process is fine, throws
  /// Stopped otherwise. Does nothing in a world of one process.
  void agree_input();
  /// The command's agreement after its work, before the lead writes anything: returns when every
  /// process is fine, throws Stopped otherwise (a process failed after the last loop it shared,
  /// and no file must be written). Does nothing in a world of one process.
  void agree_done();
  /// Tells every other process, without waiting, that this one failed in the middle of the run
  /// (after agree_input()): their spreads stop the loop they are in or the next one they start
  /// (PeerFailed) instead of waiting for this process's share. Call it before the final agree().
  void announce_failure();
  /// True once agree() has been called (the command passed its input checks everywhere).
  bool agreed() const { return agreed_; }

  /// A spread of loops over the processes (core/spread.h), or null for a world of one process.
  std::unique_ptr<Spread> spread();

  /// Ends every process at once (MPI_Abort) after an error that the others cannot learn of.
  [[noreturn]] void abort(int code);

 private:
  bool active_ = false;
  bool agreed_ = false;
  int rank_ = 0;
  int size_ = 1;
};

}  // namespace iaa::dist
