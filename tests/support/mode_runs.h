// The modes a material channel must reach, for tests that render one scene in each:
// raster, rtgi (its G-buffer rasterized and made by rays) and the path tracer on
// each device.
#ifndef VOXGI_TESTS_MODE_RUNS_H
#define VOXGI_TESTS_MODE_RUNS_H

#include <array>
#include <optional>
#include <vector>

#include "render/renderer.h"
#include "scene/effects.h"
#include "scene/scene.h"

namespace voxgi::test {

struct ModeRun {
  const char* name;
  render::Mode mode;
  render::PathtraceDevice device;
  int frames;  // rtgi accumulates a few; the others render one
  // rtgi's G-buffer (RtgiPass::Settings::primary); the other modes ignore it.
  render::RtgiPass::Settings::Primary primary = render::RtgiPass::Settings::Primary::kRaster;
};

// raster, rtgi (4 frames; its G-buffer rasterized, then made by rays), pathtrace on
// GL, pathtrace on the CPU.
extern const std::array<ModeRun, 5> kEveryMode;

// rs for `run`: its mode, path-tracer device and rtgi G-buffer.
void applyRun(const ModeRun& run, render::RenderSettings* rs);

// The linear image of s rendered as `run` says (mode, device, frames), the rest of
// the settings from `rs` (size, spp, voxels, effects), with a fresh program cache.
// `effect`, when given: the scene's plan must have it exactly when rs.effects
// overrides nothing.
std::vector<float> renderRun(const scene::Scene& s, const ModeRun& run, render::RenderSettings rs,
                             std::optional<scene::Effect> effect = std::nullopt);

}  // namespace voxgi::test

#endif  // VOXGI_TESTS_MODE_RUNS_H
