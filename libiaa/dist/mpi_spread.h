// The MPI implementation of core/spread.h: rank 0 hands out the items of a loop on request, a few
// at a time while many are left and one at a time at the end (guided self-scheduling), because
// their costs vary by 100x (a root block of background costs one evaluation, one
// on a silhouette thousands); every rank computes its items with its own threads, and at the end
// the results are gathered on rank 0 and broadcast, so that every rank holds the whole result.
//
// On rank 0 a service thread answers the other ranks' requests while rank 0's own threads work;
// the other ranks ask for their next item as soon as they start one, so that the round trip is
// hidden behind the work.
// Every wait polls with short sleeps rather than spinning in MPI, so that a rank waiting for work
// or for the others does not take a core from ranks that compute (on a shared or oversubscribed
// node that matters). Every wait also watches for another process's announcement that it failed
// (World::announce_failure()) and then throws PeerFailed, so that one process's error ends the
// run at once rather than leave the others waiting for its share.
#pragma once

#include <mpi.h>

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "core/spread.h"
#include "dist/world.h"

namespace iaa::dist {

class MpiSpread final : public Spread {
 public:
  /// A spread over the processes of `world` (which must be active).
  explicit MpiSpread(World& world);
  ~MpiSpread() override;

  int size() const override { return world_.size(); }
  int rank() const override { return world_.rank(); }
  void begin(std::uint64_t items, const ProgressPhase* phase) override;
  std::int64_t next() override;
  void fail() override { failed_ = true; }
  SpreadBalance finish(std::vector<std::string>& results,
                       std::vector<std::uint64_t>& work) override;

 private:
  void serve();  // rank 0's service thread: answers requests until every rank had its last reply
  std::int64_t take(int rank, std::uint64_t* count);  // rank 0: items for another rank
  void request();  // rank > 0: asks rank 0 for an item, reporting the items finished since

  World& world_;
  std::uint64_t items_ = 0;
  const ProgressPhase* phase_ = nullptr;
  std::mutex mutex_;  // the next item (rank 0) or the request channel (other ranks)
  std::uint64_t next_item_ = 0;
  std::vector<int> owner_;                    // rank 0: which rank took each item
  bool exhausted_ = false;                    // this rank was told there is nothing left
  std::int64_t ahead_lo_ = 0, ahead_hi_ = 0;  // rank > 0: items received, not yet started
  bool pending_ = false;                      // rank > 0: a request is on its way (pending_req_)
  MPI_Request pending_req_{};                 // its reply, into reply_
  std::int64_t reply_[2] = {0, 0};            // first item, count
  std::int64_t finished_ = 0;                 // rank > 0: items finished since the last request
  std::uint64_t remote_done_ = 0;             // rank 0: items the other ranks reported finished
  double start_ = 0;                          // MPI_Wtime() at begin()
  double last_done_ = 0;                      // seconds from begin() to this rank's last item's end
  std::uint64_t loop_ = 0;                    // this loop's number (see next())
  std::thread server_;
  std::atomic<bool> failed_{false};   // this process failed in the loop (fail())
  std::atomic<bool> stop_{false};     // rank 0: the service thread must end (the loop failed)
  std::atomic<int> peer_failed_{-1};  // rank 0: a process that announced a failure, seen by serve()
  // rank 0: the service thread stopped on an error (an MPI call that failed); its message, written
  // before the flag is set. Rank 0's workers and finish() throw it: an exception must not leave the
  // thread, which would end the process without a message.
  std::atomic<bool> server_failed_{false};
  std::string server_error_;
};

}  // namespace iaa::dist
