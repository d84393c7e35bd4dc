// The library's loops shared through core/spread.h, without MPI: K simulated processes are K
// threads of this test, each running render() or enclose() with its own Spread over a shared
// board. Every process must end with exactly the one-process result, and the balance must account
// for every item and evaluation.
#include <gtest/gtest.h>

#include <condition_variable>
#include <mutex>
#include <thread>

#include "core/error.h"
#include "core/exec.h"
#include "core/spread.h"
#include "enclose/octree.h"
#include "render/render.h"
#include "test_scenes.h"

namespace iaa {
namespace {

/// What the simulated processes share: the next item, and the results once all have arrived.
struct Board {
  explicit Board(int k) : processes(k) {}
  int processes;
  std::mutex m;
  std::condition_variable cv;
  std::uint64_t items = 0, next = 0;
  std::vector<int> owner;
  std::vector<std::string> results;
  std::vector<std::uint64_t> work;
  int begun = 0, arrived = 0;
};

class BoardSpread final : public Spread {
 public:
  BoardSpread(Board& b, int rank) : b_(b), rank_(rank) {}
  int size() const override { return b_.processes; }
  int rank() const override { return rank_; }
  void begin(std::uint64_t items, const ProgressPhase*) override {
    std::lock_guard<std::mutex> lock(b_.m);
    if (b_.begun++ == 0) {
      b_.items = items;
      b_.owner.assign(items, -1);
      b_.results.assign(items, {});
      b_.work.assign(items, 0);
    }
    EXPECT_EQ(b_.items, items);
  }
  std::int64_t next() override {
    std::lock_guard<std::mutex> lock(b_.m);
    if (b_.next >= b_.items) return -1;
    b_.owner[b_.next] = rank_;
    return static_cast<std::int64_t>(b_.next++);
  }
  SpreadBalance finish(std::vector<std::string>& results,
                       std::vector<std::uint64_t>& work) override {
    std::unique_lock<std::mutex> lock(b_.m);
    for (std::uint64_t i = 0; i < b_.items; ++i) {
      if (b_.owner[i] != rank_) continue;
      b_.results[i] = results[i];
      b_.work[i] = work[i];
    }
    ++b_.arrived;
    b_.cv.notify_all();
    b_.cv.wait(lock, [&] { return b_.arrived == b_.processes; });
    results = b_.results;
    work = b_.work;
    SpreadBalance bal;
    bal.ranks.resize(std::size_t(b_.processes));
    for (std::uint64_t i = 0; i < b_.items; ++i) {
      RankLoad& l = bal.ranks[std::size_t(b_.owner[i])];
      ++l.items;
      l.work += b_.work[i];
    }
    return bal;
  }

 private:
  Board& b_;
  int rank_;
};

/// Runs f(exec) as K simulated processes (one thread each), returning each one's result.
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

TEST(Spread, RenderEqualsOneProcessOnEveryProcess) {
  const Scene scene = test::bundled_scene("teardrop", test::image_size(100));
  RenderSettings st = scene.settings;
  Exec one;
  one.threads = 2;
  const Film ref = render(scene, st, one);
  EXPECT_TRUE(ref.balance.ranks.empty());
  const auto films = run_spread(3, [&](const Exec& e) { return render(scene, st, e); });
  for (const Film& f : films) {
    EXPECT_EQ(f.color, ref.color);
    EXPECT_EQ(f.certificate, ref.certificate);
    EXPECT_EQ(f.leaves, ref.leaves);
    EXPECT_EQ(f.evals, ref.evals);
    EXPECT_EQ(f.coverage, ref.coverage);
    EXPECT_EQ(f.stats.evals, ref.stats.evals);
    EXPECT_EQ(f.stats.block_evals, ref.stats.block_evals);
    EXPECT_EQ(f.stats.pruned_evals, ref.stats.pruned_evals);
    ASSERT_EQ(f.balance.ranks.size(), 3u);
    std::uint64_t items = 0, work = 0;
    for (const RankLoad& l : f.balance.ranks) {
      items += l.items;
      work += l.work;
    }
    EXPECT_EQ(items, 16u);  // 100x100 pixels: 4x4 root blocks of 32
    EXPECT_EQ(work, ref.stats.evals);
    EXPECT_GE(f.balance.max_over_mean(), 1.0);
  }
}

TEST(Spread, RenderWindowEqualsOneProcess) {
  const Scene scene = test::bundled_scene("chubs", test::image_size(90));
  RenderSettings st = scene.settings;
  st.window = {7, 11, 80, 64};
  const Film ref = render(scene, st, Exec{});
  const auto films = run_spread(2, [&](const Exec& e) { return render(scene, st, e); });
  for (const Film& f : films) {
    EXPECT_EQ(f.color, ref.color);
    EXPECT_EQ(f.certificate, ref.certificate);
    EXPECT_EQ(f.stats.evals, ref.stats.evals);
  }
}

TEST(Spread, EnclosureEqualsOneProcessOnEveryProcess) {
  const Scene scene = test::bundled_scene("chubs");
  EncloseSettings s;
  s.bounds = scene.bounds;
  s.depth = 6;
  s.refine_possible = 2;
  const Enclosure ref = enclose(*scene.tape, s, Exec{});
  const auto encs = run_spread(3, [&](const Exec& e) { return enclose(*scene.tape, s, e); });
  for (const Enclosure& e : encs) {
    ASSERT_EQ(e.cells.size(), ref.cells.size());
    for (std::size_t i = 0; i < e.cells.size(); ++i) {
      EXPECT_EQ(e.cells[i].index, ref.cells[i].index);
      EXPECT_EQ(e.cells[i].depth, ref.cells[i].depth);
      EXPECT_EQ(e.cells[i].cls, ref.cells[i].cls);
      EXPECT_EQ(e.cells[i].corner_signs, ref.cells[i].corner_signs);
    }
    EXPECT_EQ(e.evaluations, ref.evaluations);
    EXPECT_EQ(e.corner_evaluations, ref.corner_evaluations);
    EXPECT_EQ(e.counts_by_depth, ref.counts_by_depth);
  }
}

TEST(Spread, EnclosureOverTheBoxLimitFailsOnEveryProcess) {
  const Scene scene = test::bundled_scene("chubs");
  EncloseSettings s;
  s.bounds = scene.bounds;
  s.depth = 7;
  s.max_boxes = 500;
  const auto failed = run_spread(2, [&](const Exec& e) {
    try {
      enclose(*scene.tape, s, e);
    } catch (const SettingError&) {
      return 1;  // an int: the processes write their results at once (no vector<bool>)
    }
    return 0;
  });
  for (int f : failed) EXPECT_EQ(f, 1);
}

}  // namespace
}  // namespace iaa
