// The effect plan on the GPU: skipped effects have no stage, forcing them on adds
// their stage and changes nothing in the image of a scene that cannot show them,
// and the plan renders the same image as every effect forced on, never slower.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "support/gl_fixture.h"
#include "support/scene_builder.h"
#include "support/test_paths.h"

namespace voxgi::test {
namespace {

// A grey room corner and a grey box under one point light: diffuse only.
scene::Scene diffuseScene() {
  SceneBuilder b;
  const int grey = b.addMaterial(glm::vec3(0.6f));
  const int red = b.addMaterial(glm::vec3(0.7f, 0.2f, 0.1f));
  b.addBox({-1.0f, -1.1f, -1.0f}, {1.0f, -1.0f, 1.0f}, grey);  // floor
  b.addBox({-1.0f, -1.0f, -1.1f}, {1.0f, 1.0f, -1.0f}, grey);  // back wall
  b.addBox({-0.3f, -1.0f, -0.3f}, {0.3f, -0.4f, 0.3f}, red);
  scene::Light l;
  l.position = glm::vec3(0.5f, 0.8f, 0.8f);
  l.intensity = 3.0f;
  b.scene().lights.push_back(l);
  return b.finish();
}

std::vector<std::string> stageNames(const std::vector<gl::StageTime>& stages) {
  std::vector<std::string> out;
  for (const gl::StageTime& s : stages) out.push_back(stageName(s.stage));
  return out;
}

bool hasStage(const std::vector<std::string>& stages, const std::string& name) {
  return std::find(stages.begin(), stages.end(), name) != stages.end();
}

struct Frames {
  std::vector<float> linear;
  std::vector<std::string> stages;       // of the last frame
  std::vector<std::string> sceneStages;  // voxelize, octree, inject
};

// Largest |a - b| / (1 + |b|) over the colour channels, and the mean |a - b|.
std::pair<double, double> difference(const std::vector<float>& a, const std::vector<float>& b) {
  double worst = 0.0, sum = 0.0;
  size_t n = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    if (i % 4 == 3) continue;
    const double d = std::abs(static_cast<double>(a[i]) - b[i]);
    worst = std::max(worst, d / (1.0 + std::abs(static_cast<double>(b[i]))));
    sum += d;
    ++n;
  }
  return {worst, sum / static_cast<double>(n)};
}

class EffectsTest : public GlProgramsTest {
 protected:
  // Small and fixed: 48x48, a 64^3 grid, seed 7.
  static render::RenderSettings settings(const std::string& effects,
                                         render::Mode mode = render::Mode::kRtgi) {
    render::RenderSettings rs;
    rs.mode = mode;
    rs.width = rs.height = 48;
    rs.voxels = 64;
    rs.rtgi.seed = 7;
    rs.octree.seed = 7;
    rs.effects = effects;
    return rs;
  }

  Frames render(const scene::Scene& s, const render::RenderSettings& rs, int frames) {
    render::Renderer r(*programs_, s, rs);
    Frames run;
    for (int f = 0; f < frames; ++f) r.renderFrame();
    run.linear = r.readLinear();
    run.stages = stageNames(r.lastStages());
    run.sceneStages = stageNames(r.sceneStages());
    return run;
  }

  // The plan against every effect forced on: the same image within `tolerance`
  // (see README, "Effect plan"), and never a stage the forced run lacks.
  void expectPlanMatchesAllEffects(const std::string& path, int frames = 2) {
    SCOPED_TRACE(path);
    const scene::Scene s = scene::loadGltf(path);
    const Frames plan = render(s, settings(""), frames);
    const Frames all = render(s, settings("+all"), frames);
    for (const std::string& st : plan.stages) EXPECT_TRUE(hasStage(all.stages, st)) << st;
    const auto [worst, mean] = difference(plan.linear, all.linear);
    EXPECT_LE(worst, 1e-4) << "mean abs difference " << mean;
    const scene::EffectPlan p = render::effectPlan(s, settings(""));
    EXPECT_EQ(hasStage(plan.stages, "specular"), p.has(scene::Effect::kSpecular));
    EXPECT_TRUE(hasStage(all.stages, "specular"));
    EXPECT_TRUE(hasStage(all.stages, "shadows"));
    EXPECT_TRUE(hasStage(all.stages, "indirect"));
  }
};

TEST_F(EffectsTest, DiffuseSceneHasNoSpecularStage) {
  const scene::Scene s = diffuseScene();
  const Frames plan = render(s, settings(""), 3);
  EXPECT_EQ(plan.stages, (std::vector<std::string>{"refine", "gbuffer", "shadows", "indirect",
                                                   "accumulate", "tonemap"}));
  EXPECT_EQ(plan.sceneStages, (std::vector<std::string>{"voxelize", "octree", "inject"}));
  // Forced on, the specular stage runs and costs, and finds nothing to reflect: the
  // image is the same, bit for bit (its term is zero wherever it is added).
  const Frames forced = render(s, settings("+specular"), 3);
  EXPECT_EQ(forced.stages, (std::vector<std::string>{"refine", "gbuffer", "shadows", "indirect",
                                                     "specular", "accumulate", "tonemap"}));
  EXPECT_EQ(plan.linear, forced.linear);
  // So do the other effects this scene lacks: their code is compiled back in and
  // finds no emission, texture or mask.
  const Frames all = render(s, settings("+all"), 3);
  EXPECT_EQ(difference(plan.linear, all.linear).first, 0.0);
}

// A skipped stage's program is not even built.
TEST_F(EffectsTest, SkippedStagesCompileNothing) {
  const scene::Scene s = diffuseScene();
  auto programsFor = [&](const std::string& effects) {
    gl::ProgramCache cache(sourceDir() + "/shaders");
    render::Renderer r(cache, s, settings(effects));
    r.renderFrame();
    return cache.size();
  };
  // The specular stage is two programs: its selection of the specular pixels, and
  // the stage over them.
  EXPECT_EQ(programsFor("+specular"), programsFor("") + 2);
  EXPECT_EQ(programsFor("+specular,-indirect"), programsFor("") + 1);  // one traded for one
}

TEST_F(EffectsTest, ForcedOffEffectsLoseTheirStage) {
  const scene::Scene s = diffuseScene();
  const Frames noIndirect = render(s, settings("-indirect"), 1);
  EXPECT_FALSE(hasStage(noIndirect.stages, "indirect"));
  // Without shadows, direct light is the cheap unshadowed "direct" stage...
  const Frames noShadows = render(s, settings("-shadows"), 1);
  EXPECT_FALSE(hasStage(noShadows.stages, "shadows"));
  EXPECT_TRUE(hasStage(noShadows.stages, "direct"));
  // ...brighter where the box shadowed the floor.
  const Frames lit = render(s, settings(""), 1);
  double sumLit = 0.0, sumUnshadowed = 0.0;
  for (size_t i = 0; i < lit.linear.size(); ++i) {
    sumLit += lit.linear[i];
    sumUnshadowed += noShadows.linear[i];
  }
  EXPECT_GT(sumUnshadowed, sumLit);
  // --bounces 0 is no indirect light.
  render::RenderSettings rs = settings("");
  rs.octree.bounces = 0;
  EXPECT_FALSE(render::effectPlan(s, rs).has(scene::Effect::kIndirect));
  EXPECT_EQ(render::effectPlan(s, rs).skipped.at(scene::Effect::kIndirect), "--bounces 0");
}

TEST_F(EffectsTest, UnlitSceneRunsNoLightStage) {
  SceneBuilder b;
  b.addBox({-1, -1, -1}, {1, 1, 1}, b.addMaterial(glm::vec3(0.5f)));
  const scene::Scene s = b.finish();
  const Frames plan = render(s, settings(""), 1);
  // Nothing to trace: no voxels, no octree, no light stage.
  EXPECT_EQ(plan.stages, (std::vector<std::string>{"gbuffer", "accumulate", "tonemap"}));
  EXPECT_TRUE(plan.sceneStages.empty());
  for (float v : plan.linear) EXPECT_TRUE(v == 0.0f || v == 1.0f);  // black, alpha 1
}

TEST_F(EffectsTest, NothingTracedNeedsNoVoxels) {
  const scene::Scene s = diffuseScene();
  const Frames direct = render(s, settings("-shadows,-indirect,-specular"), 1);
  EXPECT_EQ(direct.stages,
            (std::vector<std::string>{"gbuffer", "direct", "accumulate", "tonemap"}));
  EXPECT_TRUE(direct.sceneStages.empty());
  double sum = 0.0;
  for (float v : direct.linear) sum += v;
  EXPECT_GT(sum, static_cast<double>(direct.linear.size()) / 4.0);  // alpha, plus the light
}

// The plan runs a subset of the stages that every effect forced on runs, and fewer.
// What that saves in time is a benchmark's to say (tools/bench-rtgi), not a test's:
// GPU timings on a shared llvmpipe machine scatter by tens of percent.
TEST_F(EffectsTest, PlanRunsASubsetOfTheStages) {
  const scene::Scene s = diffuseScene();
  const Frames plan = render(s, settings(""), 2);
  const Frames all = render(s, settings("+all"), 2);
  EXPECT_LT(plan.stages.size(), all.stages.size());
  for (const std::string& stage : plan.stages)
    EXPECT_NE(std::find(all.stages.begin(), all.stages.end(), stage), all.stages.end()) << stage;
}

TEST_F(EffectsTest, RasterAndPointsFollowThePlan) {
  // Raster and the voxel grid compile their variants too, with the same image.
  const scene::Scene s = scene::loadGltf(cornellRoom());
  for (render::Mode m : {render::Mode::kRaster, render::Mode::kPoints}) {
    const Frames plan = render(s, settings("", m), 1);
    const Frames all = render(s, settings("+all", m), 1);
    EXPECT_LE(difference(plan.linear, all.linear).first, 1e-4) << render::modeName(m);
  }
}

TEST_F(EffectsTest, CornellRoomPlanMatchesAllEffects) {
  expectPlanMatchesAllEffects(cornellRoom());
}

TEST_F(EffectsTest, DarkPlanePlanMatchesAllEffects) {
  expectPlanMatchesAllEffects(darkPlane());
}

TEST_F(EffectsTest, SamplesPlanMatchesAllEffects) {
  for (const char* path :
       {"box/Box.gltf", "duck/Duck.gltf", "avocado/Avocado.gltf",
        "metal_rough_spheres_no_textures/MetalRoughSpheresNoTextures.gltf",
        "lights_punctual_lamp/LightsPunctualLamp.gltf",
        "emissive_strength_test/EmissiveStrengthTest.gltf", "cornell_box/cornellBox.gltf"})
    expectPlanMatchesAllEffects(samplesDir() + "/" + path, 1);
}

// `render` prints the plan at start and writes it into the stats.
TEST(EffectsCli, PrintedAndInStats) {
  const std::string dir = scratchDir();
  const auto r = runCommand(voxgiBinary() + " render --size 16x16 --frames 1 --voxels 32 --stats " +
                            dir + "/s.json --effects -alpha,+textures");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(r.output.rfind("effects: shadows, emission, indirect, specular, textures (skipped: "
                           "alpha \u2014 --effects -alpha, colors \u2014 no vertex colours, "
                           "normalmaps \u2014 no normal-mapped material, animation \u2014 "
                           "nothing animated)\n",
                           0),
            0u)
      << r.output;
  std::ifstream in(dir + "/s.json");
  const auto stats = nlohmann::json::parse(in);
  EXPECT_EQ(stats["effects"]["enabled"],
            nlohmann::json({"shadows", "emission", "indirect", "specular", "textures"}));
  EXPECT_EQ(stats["effects"]["skipped"]["animation"], "nothing animated");
  EXPECT_EQ(stats["effects"]["skipped"]["alpha"], "--effects -alpha");
  EXPECT_TRUE(stats["stages"].contains("specular"));

  const auto bad = runCommand(voxgiBinary() + " render --effects +bloom");
  EXPECT_EQ(bad.exitCode, 2) << bad.output;
  EXPECT_NE(bad.output.find("unknown effect 'bloom'"), std::string::npos) << bad.output;
  EXPECT_EQ(std::count(bad.output.begin(), bad.output.end(), '\n'), 1) << bad.output;
}

}  // namespace
}  // namespace voxgi::test
