// The library's loops shared through core/spread.h, without MPI: K simulated processes are K
// threads of this test, each running render() or enclose() with its own Spread over a shared
// board. Every process must end with exactly the one-process result, and the balance must account
// for every item and evaluation.
#include <gtest/gtest.h>

#include "core/error.h"
#include "core/exec.h"
#include "enclose/octree.h"
#include "render/render.h"
#include "test_scenes.h"
#include "test_spread.h"

namespace iaa {
namespace {

using test::run_spread;

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
  EXPECT_EQ(test::processes_failing_with_setting_error(
                2, [&](const Exec& e) { enclose(*scene.tape, s, e); }),
            2);
}

}  // namespace
}  // namespace iaa
