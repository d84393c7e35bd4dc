// `iaa bench render` end to end on a tiny image: the JSON has every field of the table, the
// iaa/adaptive ratios agree with the per-pixel figures, `--scene-dir` is honoured, and a bad
// directory is one clear error with no file written. No timing is asserted (only that times exist).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_run.h"

namespace {

namespace fs = std::filesystem;

const std::string kBin = IAA_BIN_DIR;
const std::string kScenes = std::string(IAA_SOURCE_DIR) + "/data/scenes";

using iaa::e2e::Outcome;
using iaa::e2e::quoted;
using iaa::e2e::run;

class BenchRenderCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("iaa_bench_cli_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string tmp(const std::string& name) const { return (dir_ / name).string(); }

  fs::path dir_;
};

constexpr const char* kSmall = " --size 16 --runs 1 --threads 1";

TEST_F(BenchRenderCli, JsonHasEveryFieldAndTheRatios) {
  const std::string json = tmp("b.json");
  const Outcome r = run(quoted(kBin + "/iaa") + " bench render --scenes teardrop" + kSmall +
                        " --json " + quoted(json));
  ASSERT_EQ(r.status, 0) << r.err;
  // The table has the three ratio columns.
  for (const char* col : {"time/ad", "evals/ad", "leaves/ad"}) {
    EXPECT_NE(r.out.find(col), std::string::npos) << col << "\n" << r.out;
  }
  std::ifstream in(json);
  const nlohmann::json rows = nlohmann::json::parse(in);
  ASSERT_TRUE(rows.is_array());
  ASSERT_EQ(rows.size(), 3u);
  const nlohmann::json* adaptive = nullptr;
  for (const auto& row : rows) {
    if (row.at("method") == "adaptive") adaptive = &row;
  }
  ASSERT_NE(adaptive, nullptr);
  const double ad_evals = adaptive->at("evals_per_pixel").get<double>();
  const double ad_leaves = adaptive->at("leaves_per_pixel").get<double>();
  ASSERT_GT(ad_evals, 0);
  ASSERT_GT(ad_leaves, 0);
  std::vector<std::string> methods;
  for (const auto& row : rows) {
    methods.push_back(row.at("method").get<std::string>());
    EXPECT_EQ(row.at("scene"), "teardrop");
    EXPECT_EQ(row.at("width"), 16);
    EXPECT_EQ(row.at("height"), 16);
    EXPECT_EQ(row.at("threads"), 1);
    EXPECT_EQ(row.at("reference"), "grid 16");
    for (const char* k :
         {"median_seconds", "reference_seconds", "rmse", "evals_per_pixel", "leaves_per_pixel",
          "time_ratio_vs_adaptive", "evals_ratio_vs_adaptive", "leaves_ratio_vs_adaptive"}) {
      ASSERT_TRUE(row.contains(k)) << k;
      ASSERT_TRUE(row.at(k).is_number()) << k << ": " << row.at(k);
      EXPECT_GE(row.at(k).get<double>(), 0) << k;
    }
    EXPECT_TRUE(row.at("missed").is_number_integer());
    EXPECT_TRUE(row.at("spurious").is_number_integer());
    // The ratios are the per-pixel figures over adaptive's, from the same run.
    EXPECT_DOUBLE_EQ(row.at("evals_ratio_vs_adaptive").get<double>(),
                     row.at("evals_per_pixel").get<double>() / ad_evals);
    EXPECT_DOUBLE_EQ(row.at("leaves_ratio_vs_adaptive").get<double>(),
                     row.at("leaves_per_pixel").get<double>() / ad_leaves);
  }
  EXPECT_EQ(methods, (std::vector<std::string>{"iaa", "adaptive", "point"}));
  EXPECT_DOUBLE_EQ(adaptive->at("evals_ratio_vs_adaptive").get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(adaptive->at("leaves_ratio_vs_adaptive").get<double>(), 1.0);
}

TEST_F(BenchRenderCli, SceneDirIsUsed) {
  fs::copy_file(kScenes + "/teardrop.toml", tmp("mine.toml"));
  const std::string json = tmp("b.json");
  // Run from the temporary directory, where there is no data/scenes.
  const Outcome r = run("cd " + quoted(dir_.string()) + " && " + quoted(kBin + "/iaa") +
                        " bench render --scene-dir " + quoted(dir_.string()) + " --scenes mine" +
                        kSmall + " --json " + quoted(json));
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream in(json);
  const nlohmann::json rows = nlohmann::json::parse(in);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].at("scene"), "mine");
  EXPECT_NE(run(quoted(kBin + "/iaa") + " bench render --help").out.find("--scene-dir"),
            std::string::npos);
}

TEST_F(BenchRenderCli, AllRendersEverySceneOfTheDirectoryInNameOrder) {
  fs::create_directories(tmp("scenes"));
  fs::copy_file(kScenes + "/teardrop.toml", tmp("scenes/b.toml"));
  fs::copy_file(kScenes + "/teardrop.toml", tmp("scenes/a.toml"));
  std::ofstream(tmp("scenes/notes.txt")) << "not a scene\n";
  const std::string json = tmp("b.json");
  const Outcome r = run(quoted(kBin + "/iaa") + " bench render --all --scene-dir " +
                        quoted(tmp("scenes")) + kSmall + " --json " + quoted(json));
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream in(json);
  const nlohmann::json rows = nlohmann::json::parse(in);
  ASSERT_EQ(rows.size(), 6u);
  EXPECT_EQ(rows[0].at("scene"), "a");
  EXPECT_EQ(rows[3].at("scene"), "b");
  // --all and --scenes together are refused; an empty directory is one clear error.
  EXPECT_NE(run(quoted(kBin + "/iaa") + " bench render --all --scenes a" + kSmall).status, 0);
  fs::create_directories(tmp("empty"));
  const Outcome e = run(quoted(kBin + "/iaa") + " bench render --all --scene-dir " +
                        quoted(tmp("empty")) + kSmall);
  EXPECT_EQ(e.status, 1);
  EXPECT_NE(e.err.find("no .toml scene"), std::string::npos) << e.err;
}

TEST_F(BenchRenderCli, BadSceneDirIsOneClearError) {
  const std::string json = tmp("b.json");
  const Outcome r = run(quoted(kBin + "/iaa") + " bench render --scene-dir " + quoted(tmp("nope")) +
                        " --scenes teardrop" + kSmall + " --json " + quoted(json));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("--scene-dir"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("not a directory"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(json));
  // A scene missing from the directory names the file.
  const Outcome m = run(quoted(kBin + "/iaa") + " bench render --scene-dir " +
                        quoted(dir_.string()) + " --scenes nothere" + kSmall);
  EXPECT_EQ(m.status, 1);
  EXPECT_NE(m.err.find("nothere.toml"), std::string::npos) << m.err;
}

}  // namespace
