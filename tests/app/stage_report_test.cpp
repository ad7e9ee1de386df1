// Stage medians, the stats header and the stage table without GL: stages keep
// the order they were first seen, medians are per stage, the header's keys come
// in the order every stats file writes them.
#include "app/stage_report.h"

#include <gtest/gtest.h>

#include <set>

namespace voxgi::app {
namespace {

StageTimes threeFrames() {
  StageTimes t;
  t.add(10.0, {{Stage::kShadows, 1.0, 0.0}, {Stage::kGbuffer, 2.0, 0.0}});
  t.add(30.0,
        {{Stage::kShadows, 3.0, 0.0}, {Stage::kGbuffer, 4.0, 0.0}, {Stage::kTonemap, 0.5, 0.0}});
  t.add(20.0, {{Stage::kShadows, 2.0, 0.0}, {Stage::kGbuffer, 8.0, 0.0}});
  return t;
}

TEST(StageTimes, MediansPerStageInFirstSeenOrder) {
  const StageTimes t = threeFrames();
  EXPECT_EQ(t.order(), (std::vector<Stage>{Stage::kShadows, Stage::kGbuffer, Stage::kTonemap}));
  EXPECT_DOUBLE_EQ(t.frameMedian(), 20.0);
  EXPECT_EQ(t.frameMs(), (std::vector<double>{10.0, 30.0, 20.0}));
  EXPECT_DOUBLE_EQ(t.median(Stage::kShadows), 2.0);
  EXPECT_DOUBLE_EQ(t.median(Stage::kGbuffer), 4.0);
  EXPECT_DOUBLE_EQ(t.median(Stage::kTonemap), 0.5);
  EXPECT_TRUE(t.has(Stage::kTonemap));
  EXPECT_FALSE(t.has(Stage::kVoxelize));
  EXPECT_DOUBLE_EQ(t.median(Stage::kVoxelize), 0.0);
}

// A stage timed in two passes of one frame costs their sum; the order stays the
// order first seen.
TEST(StageTimes, AStageInTwoPassesOfAFrameCostsTheirSum) {
  const std::vector<gl::StageTime> merged = gl::sumByStage({{Stage::kGbuffer, 2.0, 2.5},
                                                            {Stage::kShadows, 1.0, 1.5},
                                                            {Stage::kIndirect, 4.0, 4.0},
                                                            {Stage::kShadows, 3.0, 3.5}});
  ASSERT_EQ(merged.size(), 3u);
  EXPECT_EQ(merged[0].stage, Stage::kGbuffer);
  EXPECT_EQ(merged[1].stage, Stage::kShadows);
  EXPECT_DOUBLE_EQ(merged[1].gpuMs, 4.0);
  EXPECT_DOUBLE_EQ(merged[1].cpuMs, 5.0);
  EXPECT_EQ(merged[2].stage, Stage::kIndirect);
}

TEST(StageTimes, EmptyRunHasZeroMediansAndNoStages) {
  const StageTimes t;
  EXPECT_DOUBLE_EQ(t.frameMedian(), 0.0);
  EXPECT_EQ(t.json().dump(), "{}");
  EXPECT_EQ(t.table("synchronous"), "  stage              ms   (synchronous)\n");
  EXPECT_EQ(t.columnHeads(), "");
}

TEST(StageTimes, JsonKeepsStageOrder) {
  EXPECT_EQ(threeFrames().json().dump(), R"({"shadows":2.0,"gbuffer":4.0,"tonemap":0.5})");
}

TEST(StageTimes, TableAndColumns) {
  const StageTimes t = threeFrames();
  EXPECT_EQ(t.table("gpu-queries"),
            "  stage              ms   (gpu-queries)\n"
            "  shadows          2.00\n"
            "  gbuffer          4.00\n"
            "  tonemap          0.50\n");
  EXPECT_EQ(t.columnHeads(), "    shadows    gbuffer    tonemap");
  EXPECT_EQ(t.columnMedians(), "        2.0        4.0        0.5");
}

// Every stage round-trips through its name; no other string names a stage.
TEST(StageNames, RoundTrip) {
  std::set<std::string> seen;
  for (Stage s : kStages) {
    const std::string name = stageName(s);
    EXPECT_TRUE(parseStage(name) == s) << name;
    EXPECT_TRUE(seen.insert(name).second) << name;
  }
  EXPECT_EQ(std::string(stageName(Stage::kGbuffer)), "gbuffer");
  EXPECT_EQ(std::string(stageName(Stage::kTonemap)), "tonemap");
  for (const char* bad : {"", "shadow", "GBuffer", "frame", "stage", "tonemap "})
    EXPECT_FALSE(parseStage(bad).has_value()) << bad;
}

TEST(StatsHeader, KeysInOrderCommandOnlyWhenGiven) {
  StatsHeader h{"", "room.gltf", "rtgi", 64, 32, "egl", "llvmpipe", "4.5"};
  nlohmann::ordered_json j = statsHeaderJson(h);
  std::vector<std::string> keys;
  for (const auto& [key, value] : j.items()) keys.push_back(key);
  EXPECT_EQ(keys, (std::vector<std::string>{"voxgi_version", "scene", "mode", "size", "backend",
                                            "renderer", "gl_version"}));
  EXPECT_EQ(j["size"].dump(), R"({"width":64,"height":32})");
  EXPECT_EQ(j["scene"], "room.gltf");
  EXPECT_EQ(j["gl_version"], "4.5");
  EXPECT_FALSE(j["voxgi_version"].get<std::string>().empty());

  h.command = "view";
  j = statsHeaderJson(h);
  auto it = j.begin();
  ++it;
  EXPECT_EQ(it.key(), "command");
  EXPECT_EQ(j["command"], "view");
}

}  // namespace
}  // namespace voxgi::app
