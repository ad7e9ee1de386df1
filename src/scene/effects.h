// The effect plan: from the scene alone, which effects exist and therefore which
// passes run and which shader variants are compiled (issue #7).
//
// Effects, by the names used in flags, stats and the viewer:
//   shadows    shadow rays for direct light        a punctual light or an emissive surface
//   emission   emitted light, emitters as lights   an emissive material
//   indirect   diffuse bounces (pixel and voxels)  a punctual light or an emissive surface
//   specular   the traced reflection stage         a mirror or glossy material
//   textures   texture sampling (base colour,      a textured material
//              emissive, metallic-roughness,
//              occlusion in raster)
//   alpha      alpha-mask discard                  an alpha-masked material
//   colors     vertex colours (COLOR_0) multiply   a drawn primitive with COLOR_0
//              the base colour
//   normalmaps tangent-space normal maps bend      a drawn normal-mapped material
//              the shading normal (needs textures)
//   animation  the scene is re-posed per frame     an animated node
// Only materials that are drawn count. A skipped effect costs nothing: its stage
// is absent and its shader code is compiled out (ShaderFeatures). `--effects
// +name,-name` overrides the plan; forcing an effect on that the scene cannot
// show is allowed (it then runs, and finds nothing to do).
#ifndef VOXGI_SCENE_EFFECTS_H
#define VOXGI_SCENE_EFFECTS_H

#include <array>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "scene/scene.h"

namespace voxgi::scene {

// The effects, in the order plans are printed (and sets and maps of them sort).
enum class Effect {
  kShadows,
  kEmission,
  kIndirect,
  kSpecular,
  kTextures,
  kAlpha,
  kColors,
  kNormalMaps,
  kAnimation,
};
inline constexpr std::array<Effect, 9> kEffects = {
    Effect::kShadows, Effect::kEmission, Effect::kIndirect,   Effect::kSpecular, Effect::kTextures,
    Effect::kAlpha,   Effect::kColors,   Effect::kNormalMaps, Effect::kAnimation};

// The name used in flags, stats and the viewer ("normalmaps" for kNormalMaps).
const char* effectName(Effect e);
// The effect of that name; nullopt for any other string ("all" included).
std::optional<Effect> parseEffect(std::string_view name);
// Every effect name, in kEffects order.
std::vector<std::string> effectNames();

// Whether a material reflects enough, sharply enough, for the specular stage to
// trace it: metallic, a dielectric smoother than gpu::kGlossyRoughness, or one with a
// metallic-roughness texture (which can make any texel a mirror).
// rtgi_specular.comp applies the same rule per pixel (gpu::isSpecular, brdf_shared.h).
bool isSpecular(const Material& m);

struct EffectPlan {
  std::set<Effect> enabled;
  std::map<Effect, std::string> skipped;  // effect -> reason, in plain words

  bool has(Effect e) const { return enabled.count(e) != 0; }
  void enable(Effect e);
  void skip(Effect e, const std::string& reason);
  // Enabled effects in kEffects order, and their names.
  std::vector<Effect> enabledList() const;
  std::vector<std::string> enabledNames() const;
  // "shadows, indirect (skipped: specular \u2014 no mirror or glossy material, ...)"
  std::string summary() const;
};

EffectPlan planEffects(const Scene& scene);
// Every effect on (what tests compare a plan against).
EffectPlan allEffects();

// Applies "+name,-name,..." in order ("all" names every effect). Forced off
// effects are skipped with the reason "--effects -name". Throws voxgi::Error with
// a one-line message on an unknown name or a missing sign.
void applyOverrides(EffectPlan* plan, const std::string& spec);
// The same checks without a plan (command-line parsing).
void checkOverrides(const std::string& spec);

// The effect-dependent code a shader variant keeps. The default keeps everything;
// each effect turned off adds a VOXGI_NO_<EFFECT> define that compiles its code out.
struct ShaderFeatures {
  bool shadows = true;
  bool emission = true;
  bool textures = true;
  bool alpha = true;
  bool colors = true;
  bool normalMaps = true;
  // Texture-coordinate channel 1 (scene::Vertex::uv2) in the raster stages: from
  // the scene, not the plan (Scene::hasSecondUv); false compiles it out.
  bool secondUv = true;
  std::vector<std::string> defines() const;
};
ShaderFeatures shaderFeatures(const EffectPlan& plan);

}  // namespace voxgi::scene

#endif  // VOXGI_SCENE_EFFECTS_H
