// The effect plan (scene/effects.h): what each scene calls for, overrides, and the
// shader defines of a plan.
#include "scene/effects.h"

#include <gtest/gtest.h>

#include <set>

#include "app/cli.h"
#include "brdf_shared.h"
#include "scene/gltf_loader.h"
#include "scene_shared.h"
#include "support/scene_builder.h"
#include "support/test_paths.h"

namespace voxgi::scene {
namespace {

std::vector<std::string> skippedNames(const EffectPlan& p) {
  std::vector<std::string> out;
  for (const auto& [effect, reason] : p.skipped) out.push_back(effectName(effect));
  return out;
}

// A grey quad under one point light: nothing but diffuse light.
Scene diffuseScene(bool lit = true) {
  test::SceneBuilder b;
  const int grey = b.addMaterial(glm::vec3(0.5f));
  b.addTriangles({{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}, grey);
  if (lit) {
    Light l;
    l.position = glm::vec3(0.0f, 0.0f, 2.0f);
    b.scene().lights.push_back(l);
  }
  return b.finish();
}

TEST(EffectPlan, CornellRoom) {
  const EffectPlan p = planEffects(loadGltf(test::cornellRoom()));
  // A ceiling panel (emissive), a mirror sphere, no textures, no masks, no animation.
  EXPECT_EQ(p.enabledNames(),
            (std::vector<std::string>{"shadows", "emission", "indirect", "specular"}));
  EXPECT_EQ(skippedNames(p),
            (std::vector<std::string>{"textures", "alpha", "colors", "normalmaps", "animation"}));
  EXPECT_EQ(p.skipped.at(Effect::kTextures), "no textured material");
  EXPECT_EQ(p.skipped.at(Effect::kAlpha), "no alpha-masked or blended material");
  EXPECT_EQ(p.skipped.at(Effect::kColors), "no vertex colours");
  EXPECT_EQ(p.skipped.at(Effect::kAnimation), "nothing animated");
  EXPECT_EQ(p.summary(),
            "shadows, emission, indirect, specular (skipped: textures \u2014 no textured "
            "material, alpha \u2014 no alpha-masked or blended material, colors \u2014 no vertex "
            "colours, "
            "normalmaps \u2014 no normal-mapped material, animation \u2014 nothing animated)");
}

TEST(EffectPlan, DarkPlane) {
  // A floor, a diffuse and a mirror sphere, and one emissive sphere as the only light.
  const Scene s = loadGltf(test::darkPlane());
  EXPECT_TRUE(s.lights.empty());
  const EffectPlan p = planEffects(s);
  EXPECT_EQ(p.enabledNames(),
            (std::vector<std::string>{"shadows", "emission", "indirect", "specular"}));
  EXPECT_EQ(skippedNames(p),
            (std::vector<std::string>{"textures", "alpha", "colors", "normalmaps", "animation"}));
}

TEST(EffectPlan, DiffuseSceneHasNoSpecularOrEmission) {
  const EffectPlan p = planEffects(diffuseScene());
  EXPECT_EQ(p.enabledNames(), (std::vector<std::string>{"shadows", "indirect"}));
  EXPECT_EQ(p.skipped.at(Effect::kSpecular), "no mirror or glossy material");
  EXPECT_EQ(p.skipped.at(Effect::kEmission), "no emissive material");
}

TEST(EffectPlan, UnlitSceneHasNoLightEffects) {
  const EffectPlan p = planEffects(diffuseScene(false));
  EXPECT_TRUE(p.enabledList().empty());
  EXPECT_EQ(p.skipped.at(Effect::kShadows), "no light and no emissive surface");
  EXPECT_EQ(p.skipped.at(Effect::kIndirect), "no light and no emissive surface");
  EXPECT_EQ(p.summary().rfind("none (skipped: shadows", 0), 0u) << p.summary();
}

TEST(EffectPlan, MaterialsDecideTexturesAlphaSpecularEmission) {
  Scene s = diffuseScene();
  Texture t;
  t.width = t.height = 1;
  t.rgba8 = {255, 255, 255, 255};
  s.textures.push_back(t);
  s.materials[0].baseColorTexture = 0;
  s.materials[0].alphaMode = AlphaMode::kMask;
  s.materials[0].emission = glm::vec3(1.0f);
  s.materials[0].metallic = 1.0f;
  const EffectPlan p = planEffects(s);
  for (Effect e : {Effect::kShadows, Effect::kEmission, Effect::kIndirect, Effect::kSpecular,
                   Effect::kTextures, Effect::kAlpha})
    EXPECT_TRUE(p.has(e)) << effectName(e);
  EXPECT_FALSE(p.has(Effect::kAnimation));
  // An emissive surface is a light on its own.
  s.lights.clear();
  EXPECT_TRUE(planEffects(s).has(Effect::kShadows));
  EXPECT_TRUE(planEffects(s).has(Effect::kIndirect));
}

TEST(EffectPlan, MaterialsNobodyDrawsDoNotCount) {
  Scene s = diffuseScene();
  Material unused;
  unused.metallic = 1.0f;
  unused.roughness = 0.0f;
  unused.emission = glm::vec3(5.0f);
  unused.alphaMode = AlphaMode::kMask;
  s.materials.push_back(unused);
  const EffectPlan p = planEffects(s);
  EXPECT_EQ(p.enabledNames(), (std::vector<std::string>{"shadows", "indirect"}));
}

TEST(EffectPlan, Animation) {
  const EffectPlan p = planEffects(loadGltf(test::testDataDir() + "/animated/moving_box.gltf"));
  EXPECT_TRUE(p.has(Effect::kAnimation));
}

// One rule, shared with rtgi_specular.comp: metallic, or smoother than kGlossyRoughness.
TEST(EffectPlan, SpecularRule) {
  Material m;
  m.metallic = 0.0f;
  m.roughness = 1.0f;
  EXPECT_FALSE(isSpecular(m));
  m.roughness = gpu::kGlossyRoughness;
  EXPECT_FALSE(isSpecular(m));
  m.roughness = gpu::kGlossyRoughness - 0.01f;
  EXPECT_TRUE(isSpecular(m));
  m.roughness = 1.0f;
  m.metallic = 0.51f;
  EXPECT_TRUE(isSpecular(m));
  m.metallic = 0.5f;
  EXPECT_FALSE(isSpecular(m));
}

TEST(EffectPlan, Overrides) {
  EffectPlan p = planEffects(diffuseScene());
  applyOverrides(&p, "+specular,-shadows");
  EXPECT_TRUE(p.has(Effect::kSpecular));
  EXPECT_FALSE(p.skipped.count(Effect::kSpecular));
  EXPECT_FALSE(p.has(Effect::kShadows));
  EXPECT_EQ(p.skipped.at(Effect::kShadows), "--effects -shadows");
  applyOverrides(&p, "-all,+indirect");
  EXPECT_EQ(p.enabledNames(), std::vector<std::string>{"indirect"});
  applyOverrides(&p, "+all");
  EXPECT_EQ(p.enabledList(), allEffects().enabledList());
  EXPECT_TRUE(p.skipped.empty());
  applyOverrides(&p, "");  // nothing to do
  EXPECT_EQ(p.enabledList().size(), kEffects.size());
}

// Every effect round-trips through its name; no other string names an effect.
TEST(EffectPlan, NamesRoundTrip) {
  std::set<std::string> seen;
  for (Effect e : kEffects) {
    const std::string name = effectName(e);
    EXPECT_TRUE(parseEffect(name) == e) << name;
    EXPECT_TRUE(seen.insert(name).second) << name;
  }
  EXPECT_EQ(effectNames(),
            (std::vector<std::string>{"shadows", "emission", "indirect", "specular", "textures",
                                      "alpha", "colors", "normalmaps", "animation"}));
  for (const char* bad : {"", "all", "bloom", "Shadows", "normalMaps", "shadows "})
    EXPECT_FALSE(parseEffect(bad).has_value()) << bad;
}

TEST(EffectPlan, BadOverridesAreOneLineErrors) {
  EffectPlan p;
  auto message = [&](const std::string& spec) {
    try {
      applyOverrides(&p, spec);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(message("+bloom"),
            "--effects: unknown effect 'bloom' (shadows, emission, indirect, specular, textures, "
            "alpha, colors, normalmaps, animation, all)");
  EXPECT_EQ(message("specular"), "--effects: 'specular' needs a sign, +specular or -specular");
  EXPECT_EQ(message("+shadows,,-alpha"),
            "--effects: empty entry in '+shadows,,-alpha' (expected +name,-name)");
  EXPECT_NE(message("+specular,"), "(no error)");
  for (const char* bad : {"+bloom", "specular", "+shadows,,-alpha"})
    EXPECT_EQ(message(bad).find('\n'), std::string::npos);
}

TEST(EffectPlan, ShaderDefines) {
  EXPECT_TRUE(ShaderFeatures{}.defines().empty());  // everything on: the plain shaders
  EXPECT_TRUE(shaderFeatures(allEffects()).defines().empty());
  const ShaderFeatures f = shaderFeatures(planEffects(diffuseScene()));
  EXPECT_EQ(f.defines(),
            (std::vector<std::string>{"VOXGI_NO_EMISSION", "VOXGI_NO_TEXTURES", "VOXGI_NO_ALPHA",
                                      "VOXGI_NO_COLORS", "VOXGI_NO_NORMALMAPS"}));
}

// Vertex colours: the `colors` effect exactly when the scene has a COLOR_0 stream.
TEST(EffectPlan, VertexColors) {
  Scene s = diffuseScene();
  EXPECT_FALSE(planEffects(s).has(Effect::kColors));
  s.colors.assign(s.vertices.size(), glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
  const EffectPlan p = planEffects(s);
  EXPECT_TRUE(p.has(Effect::kColors));
  EXPECT_TRUE(shaderFeatures(p).colors);
  EXPECT_TRUE(planEffects(loadGltf(test::testDataDir() + "/vertex_colors/red_green_quad.gltf"))
                  .has(Effect::kColors));
}

// Normal maps: the `normalmaps` effect exactly when the scene has a tangent stream
// (a drawn normal-mapped material); read only with textures on.
TEST(EffectPlan, NormalMaps) {
  EXPECT_FALSE(planEffects(diffuseScene()).has(Effect::kNormalMaps));
  EffectPlan p = planEffects(loadGltf(test::testDataDir() + "/normal_maps/tilted_quad.gltf"));
  EXPECT_TRUE(p.has(Effect::kNormalMaps));
  EXPECT_TRUE(p.has(Effect::kTextures));
  EXPECT_TRUE(shaderFeatures(p).normalMaps);
  applyOverrides(&p, "-textures");
  EXPECT_FALSE(shaderFeatures(p).normalMaps);
}

TEST(EffectPlan, CommandLine) {
  const auto inv =
      app::parseCommandLine({"render", "--effects", "+specular", "--effects", "-alpha"});
  EXPECT_EQ(inv.render.render.effects, "+specular,-alpha");
  EXPECT_EQ(app::parseCommandLine({"view", "--effects", "-all"}).view.render.effects, "-all");
  EXPECT_EQ(app::parseCommandLine({"bench", "--effects", "+all"}).bench.render.render.effects,
            "+all");
  EXPECT_THROW(app::parseCommandLine({"render", "--effects", "+bloom"}), app::UsageError);
  EXPECT_THROW(app::parseCommandLine({"view", "--effects", "shadows"}), app::UsageError);
  EXPECT_NE(app::renderHelp().find("--effects"), std::string::npos);
  EXPECT_NE(app::viewHelp().find("--effects"), std::string::npos);
}

}  // namespace
}  // namespace voxgi::scene
