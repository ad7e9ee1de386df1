// `voxgi bench`: per-stage medians over repeated frames, for a list of voxel grid
// resolutions, as a table and JSON. Every frame re-voxelizes, so the voxelize
// stage is measured on every frame, not once.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>

#include <nlohmann/json.hpp>

#include "app/cli.h"
#include "core/statistics.h"
#include "gl/debug.h"
#include "image/image.h"
#include "scene/gltf_loader.h"

namespace voxgi::app {
namespace {}  // namespace

int runBench(const BenchOptions& b) {
  const RenderOptions& o = b.render;
  if (o.verbose) setLogLevel(LogLevel::kDebug);
  if (o.quiet) setLogLevel(LogLevel::kError);
  if (!b.json.empty()) image::checkWritable(b.json);
  const std::string scenePath = o.scene.empty() ? defaultScenePath() : o.scene;
  gl::ContextOptions co;
  co.backend = o.backend;
  auto context = gl::Context::create(co);
  render::checkImageSize(o.render.width, o.render.height);
  const scene::Scene scene = scene::loadGltf(scenePath);
  gl::ProgramCache programs(shaderRoot());

  nlohmann::ordered_json runs = nlohmann::ordered_json::array();
  std::printf(
      "%s: %zu triangles; %s %dx%d on %s (%s), %d frames per row, stage ms are medians "
      "(%s)\n",
      scenePath.c_str(), scene.triangleCount(), render::modeName(o.render.mode), o.render.width,
      o.render.height, gl::backendName(context->backend()), context->renderer().c_str(), o.frames,
      gl::stageTimingMethod());
  std::printf("effects: %s\n", render::effectPlan(scene, o.render).summary().c_str());
  bool header = false;
  std::vector<int> resolutions = b.voxels;
  if (!render::modeUsesVoxels(o.render.mode)) resolutions = {0};
  for (int n : resolutions) {
    render::RenderSettings rs = o.render;
    if (n > 0) rs.voxels = n;
    rs.revoxelize = true;
    rs.voxelChecksum = false;  // not shown
    render::Renderer renderer(programs, scene, rs);
    renderer.renderFrame();  // warm-up: shader variants compile at first use
    std::vector<std::string> order;
    std::map<std::string, std::vector<double>> ms;
    std::vector<double> frameMs;
    for (int f = 0; f < o.frames; ++f) {
      const auto t = std::chrono::steady_clock::now();
      renderer.renderFrame();
      frameMs.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count());
      for (const gl::StageTime& s : renderer.lastStages()) {
        if (!ms.count(s.name)) order.push_back(s.name);
        ms[s.name].push_back(s.gpuMs);
      }
    }
    if (!header) {
      std::printf("  %-8s", "voxels");
      for (const std::string& name : order) std::printf(" %10s", name.c_str());
      std::printf(" %10s %10s\n", "frame", "occupied");
      header = true;
    }
    nlohmann::ordered_json run;
    run["voxels"] = n;
    nlohmann::ordered_json stages = nlohmann::ordered_json::object();
    std::printf("  %-8s", n > 0 ? std::to_string(n).c_str() : "-");
    for (const std::string& name : order) {
      stages[name] = median(ms[name]);
      std::printf(" %10.1f", median(ms[name]));
    }
    run["stages"] = stages;
    run["frame_ms"] = median(frameMs);
    if (const voxel::VoxelizePass* grid = renderer.voxelGrid()) {
      run["occupied"] = grid->stats().occupied;
      run["bytes"] = grid->stats().bytes;
      run["peak_bytes"] = grid->stats().peakBytes;
      std::printf(" %10.1f %10u\n", median(frameMs), grid->stats().occupied);
    } else {
      std::printf(" %10.1f %10s\n", median(frameMs), "-");
    }
    std::fflush(stdout);
    runs.push_back(run);
  }
  nlohmann::ordered_json out;
  out["voxgi_version"] = VOXGI_VERSION;
  out["scene"] = scenePath;
  out["triangles"] = scene.triangleCount();
  out["mode"] = render::modeName(o.render.mode);
  out["size"] = {{"width", o.render.width}, {"height", o.render.height}};
  out["frames"] = o.frames;
  out["backend"] = gl::backendName(context->backend());
  out["renderer"] = context->renderer();
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
