// Simulated processes for the tests of the loops shared through core/spread.h, without MPI: K
// threads of a test, each running the library with its own Spread over a shared board that serves
// any number of loops in order (render and enclose have one, the certified mesher one per
// refinement and per extraction), as MpiSpread's processes do.
#pragma once

#include <gtest/gtest.h>

#include <condition_variable>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/error.h"
#include "core/exec.h"
#include "core/spread.h"

namespace iaa::test {

/// One loop as the simulated processes share it: the next item, and the results once all came.
struct Loop {
  bool started = false;
  std::uint64_t items = 0, next = 0;
  std::vector<int> owner;
  std::vector<std::string> results;
  std::vector<std::uint64_t> work;
  int arrived = 0;
};

struct Board {
  explicit Board(int k) : processes(k) {}
  int processes;
  std::mutex m;
  std::condition_variable cv;
  std::map<int, Loop> loops;  ///< by loop number (every process runs the same loops in order)
};

class BoardSpread final : public Spread {
 public:
  BoardSpread(Board& b, int rank) : b_(b), rank_(rank) {}
  int size() const override { return b_.processes; }
  int rank() const override { return rank_; }
  void begin(std::uint64_t items, const ProgressPhase*) override {
    std::lock_guard<std::mutex> lock(b_.m);
    Loop& l = b_.loops[++loop_];
    if (!l.started) {
      l.started = true;
      l.items = items;
      l.owner.assign(items, -1);
      l.results.assign(items, {});
      l.work.assign(items, 0);
    }
    EXPECT_EQ(l.items, items);
  }
  std::int64_t next() override {
    std::lock_guard<std::mutex> lock(b_.m);
    Loop& l = b_.loops[loop_];
    if (l.next >= l.items) return -1;
    l.owner[l.next] = rank_;
    return static_cast<std::int64_t>(l.next++);
  }
  SpreadBalance finish(std::vector<std::string>& results,
                       std::vector<std::uint64_t>& work) override {
    std::unique_lock<std::mutex> lock(b_.m);
    Loop& l = b_.loops[loop_];
    for (std::uint64_t i = 0; i < l.items; ++i) {
      if (l.owner[i] != rank_) continue;
      l.results[i] = results[i];
      l.work[i] = work[i];
    }
    ++l.arrived;
    b_.cv.notify_all();
    b_.cv.wait(lock, [&] { return l.arrived == b_.processes; });
    results = l.results;
    work = l.work;
    SpreadBalance bal;
    bal.ranks.resize(std::size_t(b_.processes));
    for (std::uint64_t i = 0; i < l.items; ++i) {
      RankLoad& r = bal.ranks[std::size_t(l.owner[i])];
      ++r.items;
      r.work += l.work[i];
    }
    return bal;
  }

 private:
  Board& b_;
  int rank_;
  int loop_ = -1;
};

/// Runs f(exec) as K simulated processes (one or two threads each), returning each one's result.
template <class F>
auto run_spread(int k, F f) {
  Board board(k);
  std::vector<decltype(f(Exec{}))> out(static_cast<std::size_t>(k));
  std::vector<std::thread> procs;
  for (int r = 0; r < k; ++r) {
    procs.emplace_back([&, r] {
      BoardSpread spread(board, r);
      Exec exec;
      exec.threads = 1 + r % 2;
      exec.spread = &spread;
      out[std::size_t(r)] = f(exec);
    });
  }
  for (auto& p : procs) p.join();
  return out;
}

/// Runs f(exec) as K simulated processes and counts those in which it threw a SettingError (the
/// box limits' error, which every process must throw when one process passes the limit).
template <class F>
int processes_failing_with_setting_error(int k, F f) {
  const auto failed = run_spread(k, [&](const Exec& e) {
    try {
      f(e);
    } catch (const SettingError&) {
      return 1;  // an int: the processes write their results at once (no vector<bool>)
    }
    return 0;
  });
  int n = 0;
  for (int x : failed) n += x;
  return n;
}

}  // namespace iaa::test
