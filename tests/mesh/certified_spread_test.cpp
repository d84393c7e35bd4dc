// The certified mesher's loops shared through core/spread.h, without MPI: K simulated processes
// are K threads of this test, each running mesh_certified() with its own Spread over a shared
// board that serves any number of loops (the mesher has one per refinement and per extraction).
// Every process must end with exactly the one-process mesh and statistics, and the box limit must
// fail on every process.
#include <gtest/gtest.h>

#include <condition_variable>
#include <map>
#include <mutex>
#include <thread>

#include "core/error.h"
#include "core/exec.h"
#include "core/spread.h"
#include "mesh/certified_mesher.h"
#include "test_scenes.h"

namespace iaa {
namespace {

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

// Without the proof cache every count is exact whatever the layout of threads and processes; with
// it (below) the hits depend on which thread meets which cell, and the cache only saves work.
TEST(CertifiedSpread, MeshEqualsOneProcessOnEveryProcess) {
  const Scene scene = test::bundled_scene("chubs");
  CertifiedMeshSettings s;
  s.bounds = scene.bounds;
  s.min_depth = 5;
  s.max_depth = 8;
  s.proof_cache = false;
  Exec one;
  one.threads = 2;
  const CertifiedMesh ref = mesh_certified(*scene.tape, s, one);
  EXPECT_TRUE(ref.balance.ranks.empty());
  ASSERT_GT(ref.soup.triangles.size(), 1000u);
  const auto meshes =
      run_spread(3, [&](const Exec& e) { return mesh_certified(*scene.tape, s, e); });
  for (const CertifiedMesh& m : meshes) {
    EXPECT_EQ(m.soup.vertices, ref.soup.vertices);
    EXPECT_EQ(m.soup.triangles, ref.soup.triangles);
    EXPECT_EQ(m.stats.leaves, ref.stats.leaves);
    EXPECT_EQ(m.stats.certified_leaves, ref.stats.certified_leaves);
    EXPECT_EQ(m.stats.uncertified_leaves, ref.stats.uncertified_leaves);
    EXPECT_EQ(m.stats.rounds, ref.stats.rounds);
    EXPECT_EQ(m.stats.mesh_to_surface, ref.stats.mesh_to_surface);
    EXPECT_EQ(m.uncertified.size(), ref.uncertified.size());
    EXPECT_EQ(m.stats.interval_evaluations, ref.stats.interval_evaluations);
    ASSERT_EQ(m.balance.ranks.size(), 3u);
    std::uint64_t items = 0;
    for (const RankLoad& l : m.balance.ranks) items += l.items;
    EXPECT_GT(items, 0u);
  }
  s.proof_cache = true;
  const CertifiedMesh cached = mesh_certified(*scene.tape, s, one);
  EXPECT_EQ(cached.soup.triangles, ref.soup.triangles);
  EXPECT_LT(cached.stats.interval_evaluations, ref.stats.interval_evaluations);
  for (const CertifiedMesh& m :
       run_spread(3, [&](const Exec& e) { return mesh_certified(*scene.tape, s, e); })) {
    EXPECT_EQ(m.soup.vertices, ref.soup.vertices);
    EXPECT_EQ(m.soup.triangles, ref.soup.triangles);
    EXPECT_LE(m.stats.interval_evaluations, ref.stats.interval_evaluations);
  }
}

TEST(CertifiedSpread, OverTheBoxLimitFailsOnEveryProcess) {
  const Scene scene = test::bundled_scene("chubs");
  CertifiedMeshSettings s;
  s.bounds = scene.bounds;
  s.min_depth = 6;
  s.max_boxes = 3000;
  const auto failed = run_spread(2, [&](const Exec& e) {
    try {
      mesh_certified(*scene.tape, s, e);
    } catch (const SettingError&) {
      return 1;  // an int: the processes write their results at once (no vector<bool>)
    }
    return 0;
  });
  for (int f : failed) EXPECT_EQ(f, 1);
}

}  // namespace
}  // namespace iaa
