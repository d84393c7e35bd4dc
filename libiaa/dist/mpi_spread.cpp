// dist/mpi_spread.h.
#include "dist/mpi_spread.h"

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <exception>

#include "core/error.h"
#include "core/exec.h"
#include "dist/mpi_util.h"

namespace iaa::dist {

namespace {

constexpr int kRequestTag = 101;  // rank > 0 to rank 0: "one more item, please" (+ items done)
constexpr int kReplyTag = 102;    // rank 0 to rank > 0: first item and count (0: none left)
constexpr int kResultsTag = 103;  // rank > 0 to rank 0: its items' results at the end of a loop

/// Which loop a thread last asked in, so that its next request can say it finished an item. Loop
/// numbers are unique in the process, so one per thread is enough.
std::atomic<std::uint64_t> g_loops{0};
thread_local std::uint64_t t_loop = 0;

}  // namespace

MpiSpread::MpiSpread(World& world) : world_(world) {
  IAA_CHECK(world.active());
}

MpiSpread::~MpiSpread() {
  // After a failure: the service thread stops answering, and a request still on its way is
  // withdrawn, so that nothing of this loop is left pending in MPI.
  stop_ = true;
  if (server_.joinable()) server_.join();
  if (pending_) {
    MPI_Cancel(&pending_req_);
    MPI_Wait(&pending_req_, MPI_STATUS_IGNORE);
  }
}

void MpiSpread::begin(std::uint64_t items, const ProgressPhase* phase) {
  IAA_CHECK(!server_.joinable());
  items_ = items;
  phase_ = phase;
  next_item_ = 0;
  exhausted_ = false;
  ahead_lo_ = ahead_hi_ = 0;
  pending_ = false;
  finished_ = 0;
  remote_done_ = 0;
  loop_ = ++g_loops;
  failed_ = false;
  stop_ = false;
  peer_failed_ = -1;
  owner_.assign(world_.rank() == 0 ? items : 0, -1);
  start_ = MPI_Wtime();
  last_done_ = 0;
  server_failed_ = false;
  server_error_.clear();
  if (world_.rank() == 0 && world_.size() > 1) {
    server_ = std::thread([this] {
      try {
        serve();
      } catch (const std::exception& e) {
        server_error_ = e.what();
        server_failed_ = true;
      } catch (...) {
        server_error_ = "MPI service thread: unknown error";
        server_failed_ = true;
      }
    });
  }
}

std::int64_t MpiSpread::take(int rank, std::uint64_t* count) {
  const std::uint64_t left = items_ - next_item_;
  // Guided: a quarter of this rank's share of what is left, at least one. Few requests while
  // much is left, single items at the end, where the balance is made.
  const std::uint64_t n =
      std::min(left, std::max<std::uint64_t>(1, left / (4 * std::uint64_t(world_.size()))));
  *count = n;
  if (n == 0) return -1;
  for (std::uint64_t k = 0; k < n; ++k) owner_[next_item_ + k] = rank;
  const auto first = static_cast<std::int64_t>(next_item_);
  next_item_ += n;
  return first;
}

void MpiSpread::request() {
  std::int64_t done = finished_;
  finished_ = 0;
  mpi_check(MPI_Send(&done, 1, MPI_INT64_T, 0, kRequestTag, MPI_COMM_WORLD), "MPI_Send");
  mpi_check(MPI_Irecv(reply_, 2, MPI_INT64_T, 0, kReplyTag, MPI_COMM_WORLD, &pending_req_),
            "MPI_Irecv");
  pending_ = true;
}

std::int64_t MpiSpread::next() {
  // A thread's call after its first in this loop means it finished an item.
  const bool finished_one = t_loop == loop_;
  t_loop = loop_;
  if (failed_) return -1;
  std::lock_guard<std::mutex> lock(mutex_);
  std::int64_t item = -1;
  if (world_.rank() == 0) {
    if (const int r = peer_failed_; r >= 0) throw PeerFailed{r};
    if (server_failed_) throw Error(server_error_);
    // Rank 0's own threads take one item at a time: no messages to save.
    if (next_item_ < items_) {
      owner_[next_item_] = 0;
      item = static_cast<std::int64_t>(next_item_++);
    }
  } else {
    if (finished_one) ++finished_;
    if (ahead_lo_ == ahead_hi_ && !exhausted_) {
      if (!pending_) request();
      mpi_wait(pending_req_, 0, true);
      pending_ = false;
      if (reply_[1] == 0) {
        exhausted_ = true;
      } else {
        ahead_lo_ = reply_[0];
        ahead_hi_ = reply_[0] + reply_[1];
      }
    }
    if (ahead_lo_ < ahead_hi_) item = ahead_lo_++;
    // Ask for more as the last item at hand starts, so that the answer arrives while it is
    // computed: the round trip to rank 0's service thread is then hidden behind the work.
    if (item >= 0 && ahead_lo_ == ahead_hi_ && !pending_) request();
  }
  if (item < 0) last_done_ = std::max(last_done_, MPI_Wtime() - start_);
  return item;
}

void MpiSpread::serve() {
  int waiting = world_.size() - 1;  // ranks that have not yet been told the loop is over
  // The thread shares rank 0's cores with its workers: between requests it sleeps, 20 us after a
  // request and twice as long after each empty poll, up to 1 ms. Polling every 20 us throughout
  // took so much of rank 0's core that its worker did about half the evaluations of rank 1's in
  // the same time (-np 2 --threads 1 on 2 cores). The others ask ahead, so the longer wait hides
  // behind their work.
  auto pause = std::chrono::microseconds(20);
  while (waiting > 0 && !stop_) {
    int flag = 0;
    MPI_Status st;
    mpi_check(MPI_Iprobe(MPI_ANY_SOURCE, kRequestTag, MPI_COMM_WORLD, &flag, &st), "MPI_Iprobe");
    if (!flag) {
      // Another process failed: its requests will not come. Rank 0's workers and finish() see
      // peer_failed_ and throw.
      if (int r = -1; failure_announced(&r)) {
        peer_failed_ = r;
        return;
      }
      std::this_thread::sleep_for(pause);
      pause = std::min(2 * pause, std::chrono::microseconds(1000));
      continue;
    }
    pause = std::chrono::microseconds(20);
    std::int64_t done = 0;
    mpi_check(MPI_Recv(&done, 1, MPI_INT64_T, st.MPI_SOURCE, kRequestTag, MPI_COMM_WORLD,
                       MPI_STATUS_IGNORE),
              "MPI_Recv");
    if (done > 0 && phase_) phase_->advance(std::uint64_t(done));
    remote_done_ += std::uint64_t(std::max<std::int64_t>(done, 0));
    std::int64_t reply[2];  // the first item and the number of items (0: none left)
    {
      std::lock_guard<std::mutex> lock(mutex_);
      std::uint64_t count = 0;
      reply[0] = take(st.MPI_SOURCE, &count);
      reply[1] = static_cast<std::int64_t>(count);
    }
    mpi_check(MPI_Send(reply, 2, MPI_INT64_T, st.MPI_SOURCE, kReplyTag, MPI_COMM_WORLD),
              "MPI_Send");
    if (reply[1] == 0) --waiting;
  }
}

SpreadBalance MpiSpread::finish(std::vector<std::string>& results,
                                std::vector<std::uint64_t>& work) {
  IAA_CHECK(results.size() == items_ && work.size() == items_);
  const int size = world_.size();
  std::string all;  // rank 0 to everyone: the balance, then every item's work and result
  if (world_.rank() != 0) {
    // This rank's items (those with a result or some work; an item may have an empty result).
    std::string mine;
    put_bytes(mine, last_done_);
    for (std::uint64_t i = 0; i < items_; ++i) {
      if (results[i].empty() && work[i] == 0) continue;
      put_bytes(mine, i);
      put_bytes(mine, work[i]);
      put_bytes(mine, std::uint64_t(results[i].size()));
      mine += results[i];
    }
    mpi_send_bytes(mine, 0, kResultsTag);
  } else {
    if (server_.joinable()) server_.join();
    if (const int r = peer_failed_; r >= 0) throw PeerFailed{r};
    if (server_failed_) throw Error(server_error_);
    std::vector<double> busy(std::size_t(size), 0);
    busy[0] = last_done_;
    for (int r = 1; r < size; ++r) {
      const std::string in = mpi_recv_bytes(r, kResultsTag);
      std::size_t pos = 0;
      busy[std::size_t(r)] = take_bytes<double>(in, pos);
      while (pos < in.size()) {
        const auto i = take_bytes<std::uint64_t>(in, pos);
        IAA_CHECK(i < items_ && owner_[i] == r);
        work[i] = take_bytes<std::uint64_t>(in, pos);
        const auto n = take_bytes<std::uint64_t>(in, pos);
        results[i].assign(in, pos, n);
        pos += n;
      }
    }
    // The other ranks report the items they finished with their requests; the last ones are
    // known only now.
    std::uint64_t remote = 0;
    for (int o : owner_) remote += o != 0;
    if (phase_ && remote > remote_done_) phase_->advance(remote - remote_done_);
    SpreadBalance b;
    b.ranks.resize(std::size_t(size));
    double slowest = 0;
    for (int r = 0; r < size; ++r) slowest = std::max(slowest, busy[std::size_t(r)]);
    for (int r = 0; r < size; ++r) {
      b.ranks[std::size_t(r)].busy = busy[std::size_t(r)];
      b.ranks[std::size_t(r)].idle = slowest - busy[std::size_t(r)];
    }
    for (std::uint64_t i = 0; i < items_; ++i) {
      IAA_CHECK(owner_[i] >= 0);
      RankLoad& l = b.ranks[std::size_t(owner_[i])];
      ++l.items;
      l.work += work[i];
    }
    for (const RankLoad& l : b.ranks) put_bytes(all, l);
    for (std::uint64_t i = 0; i < items_; ++i) {
      put_bytes(all, work[i]);
      put_bytes(all, std::uint64_t(results[i].size()));
      all += results[i];
    }
  }
  mpi_bcast_bytes(all);
  SpreadBalance b;
  std::size_t pos = 0;
  b.ranks.resize(std::size_t(size));
  for (RankLoad& l : b.ranks) l = take_bytes<RankLoad>(all, pos);
  if (world_.rank() != 0) {
    for (std::uint64_t i = 0; i < items_; ++i) {
      work[i] = take_bytes<std::uint64_t>(all, pos);
      const auto n = take_bytes<std::uint64_t>(all, pos);
      results[i].assign(all, pos, n);
      pos += n;
    }
  }
  return b;
}

}  // namespace iaa::dist
