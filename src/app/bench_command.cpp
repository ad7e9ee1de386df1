// `voxgi bench`: per-stage medians over repeated frames, for a list of voxel grid
// resolutions, as a table and JSON. Every frame re-voxelizes, so the voxelize
// stage is measured on every frame, not once.
#include <algorithm>
#include <chrono>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "app/cli.h"
#include "app/stage_report.h"
#include "core/memory.h"
#include "gl/debug.h"
#include "image/image.h"
#include "scene/gltf_loader.h"

namespace voxgi::app {
namespace {

// One row of the table and of the JSON: the stage medians at one grid resolution
// (0: the mode reads no voxels). The first row prints the table's heading.
nlohmann::ordered_json benchRun(const RenderOptions& o, gl::ProgramCache& programs,
                                const scene::Scene& scene, int n, bool heading) {
  render::RenderSettings rs = o.render;
  if (n > 0) rs.voxels = n;
  rs.revoxelize = true;
  rs.voxelChecksum = false;  // not shown
  render::Renderer renderer(programs, scene, rs);
  renderer.renderFrame();  // warm-up: shader variants compile at first use
  pauseHugePages(false);   // started: the frames want them (core/memory.h)
  StageTimes times;
  for (int f = 0; f < o.frames; ++f) {
    const auto t = std::chrono::steady_clock::now();
    renderer.renderFrame();
    times.add(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count(),
        renderer.lastStages());
  }
  if (heading)
    std::printf("  %-8s%s %10s %10s\n", "voxels", times.columnHeads().c_str(), "frame", "occupied");
  nlohmann::ordered_json run;
  run["voxels"] = n;
  std::printf("  %-8s%s", n > 0 ? std::to_string(n).c_str() : "-", times.columnMedians().c_str());
  run["stages"] = times.json();
  run["frame_ms"] = times.frameMedian();
  if (const voxel::VoxelizePass* grid = renderer.voxelGrid()) {
    run["occupied"] = grid->stats().occupied;
    run["bytes"] = grid->stats().bytes;
    run["peak_bytes"] = grid->stats().peakBytes;
    std::printf(" %10.1f %10u\n", times.frameMedian(), grid->stats().occupied);
  } else {
    std::printf(" %10.1f %10s\n", times.frameMedian(), "-");
  }
  std::fflush(stdout);
  return run;
}

}  // namespace

int runBench(const BenchOptions& b) {
  const RenderOptions& o = b.render;
  if (o.verbose) setLogLevel(LogLevel::kDebug);
  if (o.quiet) setLogLevel(LogLevel::kError);
  if (!b.json.empty()) image::checkWritable(b.json);
  const std::string scenePath = o.scene.empty() ? defaultScenePath() : o.scene;
  gl::ContextOptions co;
  co.backend = o.backend;
  co.eglDevice = o.eglDevice;
  auto context = gl::Context::create(co);
  render::checkImageSize(o.render.width, o.render.height);
  const scene::Scene scene = scene::loadGltf(scenePath);
  gl::ProgramCache programs(shaderRoot());

  std::printf(
      "%s: %zu triangles; %s %dx%d on %s (%s), %d frames per row, stage ms are medians "
      "(%s)\n",
      scenePath.c_str(), scene.triangleCount(), render::modeName(o.render.mode), o.render.width,
      o.render.height, gl::backendName(context->backend()), context->renderer().c_str(), o.frames,
      gl::stageTimingMethod());
  std::printf("effects: %s\n", render::effectPlan(scene, o.render).summary().c_str());
  std::vector<int> resolutions = b.voxels;
  if (!render::modeUsesVoxels(o.render.mode)) resolutions = {0};
  nlohmann::ordered_json runs = nlohmann::ordered_json::array();
  for (int n : resolutions) runs.push_back(benchRun(o, programs, scene, n, runs.empty()));

  nlohmann::ordered_json out = statsHeaderJson(
      {"", scenePath, render::modeName(o.render.mode), o.render.width, o.render.height,
       gl::backendName(context->backend()), context->renderer(), context->version()});
  out["triangles"] = scene.triangleCount();
  out["frames"] = o.frames;
  out["stage_timing"] = gl::stageTimingMethod();
  out["runs"] = runs;
  out["gl_errors"] = gl::debugErrorCount();
  if (!b.json.empty()) {
    image::writeText(b.json, out.dump(2) + "\n");
    std::printf("wrote %s\n", b.json.c_str());
  }
  return gl::debugErrorCount() > 0 ? 1 : 0;
}

}  // namespace voxgi::app
