// Helpers of the MPI implementation (world_mpi.cpp, mpi_spread.cpp): errors as exceptions, waits
// that sleep rather than spin, and messages of any size.
#pragma once

#include <mpi.h>

#include <chrono>
#include <cstdint>
#include <string>
#include <thread>

#include "core/error.h"
#include "dist/world.h"

namespace iaa::dist {

/// Throws iaa::Error with MPI's message when an MPI call failed (MPI_ERRORS_RETURN is set on
/// MPI_COMM_WORLD, so failures come back as codes).
inline void mpi_check(int rc, const char* what) {
  if (rc == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int len = 0;
  MPI_Error_string(rc, text, &len);
  throw Error(std::string("MPI: ") + what + " failed: " + std::string(text, std::size_t(len)));
}

/// The tag of World::announce_failure()'s notices, on MPI_COMM_WORLD.
constexpr int kFailureTag = 199;

/// True when another process announced that it failed (World::announce_failure()); `rank` gets
/// which one. The notice is left in place, so that every later look sees it too.
inline bool failure_announced(int* rank) {
  int flag = 0;
  MPI_Status st;
  mpi_check(MPI_Iprobe(MPI_ANY_SOURCE, kFailureTag, MPI_COMM_WORLD, &flag, &st), "MPI_Iprobe");
  if (flag) *rank = st.MPI_SOURCE;
  return flag != 0;
}

/// Throws PeerFailed when another process announced that it failed.
inline void check_failures() {
  int rank = -1;
  if (failure_announced(&rank)) throw PeerFailed{rank};
}

/// Waits for a request to complete: a few quick tests, then tests between sleeps of 50 us, so
/// that a waiting process leaves its core to the ones that compute. With `deadline` > 0, returns
/// false when that many seconds passed first. With `watch`, throws PeerFailed as soon as another
/// process announces that it failed (the spread's waits: what they wait for may never come).
inline bool mpi_wait(MPI_Request& req, double deadline = 0, bool watch = false) {
  const auto t0 = std::chrono::steady_clock::now();
  for (int polls = 0;; ++polls) {
    int done = 0;
    mpi_check(MPI_Test(&req, &done, MPI_STATUS_IGNORE), "MPI_Test");
    if (done) return true;
    if (polls < 64) continue;
    if (watch && polls % 16 == 0) check_failures();
    std::this_thread::sleep_for(std::chrono::microseconds(50));
    if (deadline > 0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > deadline) {
      return false;
    }
  }
}

/// MPI counts are ints: large buffers go in pieces of at most 1 GiB.
constexpr std::size_t kMpiPiece = std::size_t{1} << 30;

// The bulk transfers below first agree on the size with a message whose wait sleeps (the other
// side may still be computing), then move the bytes with MPI's own blocking calls: both sides are
// there by then, and a blocking call progresses a large transfer much faster than tests spaced
// by sleeps.

/// Sends a buffer of any size to `dest`: its size first, synchronously (so that this returns to
/// the bytes only once `dest` is receiving), then the bytes.
inline void mpi_send_bytes(const std::string& buf, int dest, int tag) {
  std::uint64_t n = buf.size();
  MPI_Request req;
  mpi_check(MPI_Issend(&n, 1, MPI_UINT64_T, dest, tag, MPI_COMM_WORLD, &req), "MPI_Issend");
  mpi_wait(req, 0, true);
  for (std::size_t off = 0; off < buf.size(); off += kMpiPiece) {
    const int len = static_cast<int>(std::min(kMpiPiece, buf.size() - off));
    mpi_check(MPI_Send(buf.data() + off, len, MPI_BYTE, dest, tag, MPI_COMM_WORLD), "MPI_Send");
  }
}

/// Receives what mpi_send_bytes() sent from `source`.
inline std::string mpi_recv_bytes(int source, int tag) {
  std::uint64_t n = 0;
  MPI_Request req;
  mpi_check(MPI_Irecv(&n, 1, MPI_UINT64_T, source, tag, MPI_COMM_WORLD, &req), "MPI_Irecv");
  mpi_wait(req, 0, true);
  std::string buf(n, '\0');
  for (std::size_t off = 0; off < buf.size(); off += kMpiPiece) {
    const int len = static_cast<int>(std::min(kMpiPiece, buf.size() - off));
    mpi_check(
        MPI_Recv(buf.data() + off, len, MPI_BYTE, source, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
        "MPI_Recv");
  }
  return buf;
}

/// Broadcasts a buffer of any size from rank 0 (`buf` is replaced on the other ranks).
inline void mpi_bcast_bytes(std::string& buf) {
  std::uint64_t n = buf.size();
  MPI_Request req;
  mpi_check(MPI_Ibcast(&n, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD, &req), "MPI_Ibcast");
  mpi_wait(req, 0, true);
  buf.resize(n);
  for (std::size_t off = 0; off < buf.size(); off += kMpiPiece) {
    const int len = static_cast<int>(std::min(kMpiPiece, buf.size() - off));
    mpi_check(MPI_Bcast(buf.data() + off, len, MPI_BYTE, 0, MPI_COMM_WORLD), "MPI_Bcast");
  }
}

}  // namespace iaa::dist
