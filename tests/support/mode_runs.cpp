#include "support/mode_runs.h"

#include <gtest/gtest.h>

#include "gl/program_cache.h"
#include "support/test_paths.h"

namespace voxgi::test {

using Primary = render::RtgiPass::Settings::Primary;

const std::array<ModeRun, 5> kEveryMode = {
    {{"raster", render::Mode::kRaster, render::PathtraceDevice::kAuto, 1},
     {"rtgi", render::Mode::kRtgi, render::PathtraceDevice::kAuto, 4, Primary::kRaster},
     {"rtgi primary rays", render::Mode::kRtgi, render::PathtraceDevice::kAuto, 4, Primary::kRays},
     {"pathtrace gl", render::Mode::kPathtrace, render::PathtraceDevice::kGl, 1},
     {"pathtrace cpu", render::Mode::kPathtrace, render::PathtraceDevice::kCpu, 1}}};

void applyRun(const ModeRun& run, render::RenderSettings* rs) {
  rs->mode = run.mode;
  rs->pathtrace.device = run.device;
  rs->rtgi.primary = run.primary;
}

std::vector<float> renderRun(const scene::Scene& s, const ModeRun& run, render::RenderSettings rs,
                             std::optional<scene::Effect> effect) {
  applyRun(run, &rs);
  gl::ProgramCache programs(sourceDir() + "/shaders");
  render::Renderer r(programs, s, rs);
  if (effect) {
    EXPECT_EQ(r.effects().has(*effect), rs.effects.empty()) << r.effects().summary();
  }
  for (int f = 0; f < run.frames; ++f) r.renderFrame();
  return r.readLinear();
}

}  // namespace voxgi::test
