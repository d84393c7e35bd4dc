// The certified mesher's loops shared through core/spread.h, without MPI: K simulated processes
// are K threads of this test, each running mesh_certified() with its own Spread over a shared
// board that serves any number of loops (the mesher has one per refinement and per extraction).
// Every process must end with exactly the one-process mesh and statistics, and the box limit must
// fail on every process.
#include <gtest/gtest.h>

#include "core/error.h"
#include "core/exec.h"
#include "mesh/certified_mesher.h"
#include "test_scenes.h"
#include "test_spread.h"

namespace iaa {
namespace {

using test::run_spread;

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
  EXPECT_EQ(test::processes_failing_with_setting_error(
                2, [&](const Exec& e) { mesh_certified(*scene.tape, s, e); }),
            2);
}

}  // namespace
}  // namespace iaa
