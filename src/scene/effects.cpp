#include "scene/effects.h"

#include <algorithm>

#include "brdf_shared.h"
#include "core/log.h"

namespace voxgi::scene {

namespace {

// Indexed by Effect.
constexpr std::array<const char*, kEffects.size()> kEffectNames = {
    "shadows", "emission", "indirect",   "specular", "textures",
    "alpha",   "colors",   "normalmaps", "animation"};

}  // namespace

const char* effectName(Effect e) {
  return kEffectNames[static_cast<size_t>(e)];
}

std::optional<Effect> parseEffect(std::string_view name) {
  for (Effect e : kEffects)
    if (name == effectName(e)) return e;
  return std::nullopt;
}

std::vector<std::string> effectNames() {
  std::vector<std::string> names;
  for (Effect e : kEffects) names.push_back(effectName(e));
  return names;
}

bool isSpecular(const Material& m) {
  // A metallic-roughness texture scales both factors down, as far as a mirror.
  return gpu::isSpecular(m.metallic, m.roughness) || m.metallicRoughnessTexture >= 0;
}

void EffectPlan::enable(Effect e) {
  skipped.erase(e);
  enabled.insert(e);
}

void EffectPlan::skip(Effect e, const std::string& reason) {
  enabled.erase(e);
  skipped[e] = reason;
}

std::vector<Effect> EffectPlan::enabledList() const {
  return std::vector<Effect>(enabled.begin(), enabled.end());
}

std::vector<std::string> EffectPlan::enabledNames() const {
  std::vector<std::string> out;
  for (Effect e : enabled) out.push_back(effectName(e));
  return out;
}

std::string EffectPlan::summary() const {
  std::string s;
  for (Effect e : enabled) s += (s.empty() ? "" : ", ") + std::string(effectName(e));
  if (s.empty()) s = "none";
  std::string skips;
  for (const auto& [e, reason] : skipped)
    skips += (skips.empty() ? "" : ", ") + std::string(effectName(e)) + " \u2014 " + reason;
  if (!skips.empty()) s += " (skipped: " + skips + ")";
  return s;
}

EffectPlan planEffects(const Scene& scene) {
  bool emissive = false, specular = false, textured = false, masked = false;
  std::vector<bool> drawn(scene.materials.size(), false);
  for (const Draw& d : scene.draws)
    if (d.material >= 0 && static_cast<size_t>(d.material) < drawn.size())
      drawn[static_cast<size_t>(d.material)] = true;
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    if (!drawn[i]) continue;
    const Material& m = scene.materials[i];
    emissive = emissive || m.isEmissive();
    specular = specular || isSpecular(m);
    for (int t : {m.baseColorTexture, m.emissiveTexture, m.metallicRoughnessTexture,
                  m.normalTexture, m.occlusionTexture})
      textured = textured || (t >= 0 && static_cast<size_t>(t) < scene.textures.size());
    masked = masked || m.alphaMode != AlphaMode::kOpaque;
  }
  const bool lit = !scene.lights.empty() || emissive;
  EffectPlan plan;
  auto decide = [&](Effect e, bool on, const char* reason) {
    if (on)
      plan.enable(e);
    else
      plan.skip(e, reason);
  };
  decide(Effect::kShadows, lit, "no light and no emissive surface");
  decide(Effect::kEmission, emissive, "no emissive material");
  decide(Effect::kIndirect, lit, "no light and no emissive surface");
  decide(Effect::kSpecular, specular, "no mirror or glossy material");
  decide(Effect::kTextures, textured, "no textured material");
  decide(Effect::kAlpha, masked, "no alpha-masked or blended material");
  decide(Effect::kColors, scene.hasVertexColors(), "no vertex colours");
  decide(Effect::kNormalMaps, scene.hasNormalMaps(), "no normal-mapped material");
  decide(Effect::kAnimation, scene.animated(), "nothing animated");
  return plan;
}

EffectPlan allEffects() {
  EffectPlan plan;
  for (Effect e : kEffects) plan.enable(e);
  return plan;
}

namespace {

struct Override {
  bool on;
  std::string name;              // as written: "all" or an effect's name
  std::optional<Effect> effect;  // nullopt: "all"
};

std::vector<Override> parseOverrides(const std::string& spec) {
  std::vector<Override> out;
  size_t start = 0;
  while (start <= spec.size()) {
    const size_t comma = std::min(spec.find(',', start), spec.size());
    const std::string item = spec.substr(start, comma - start);
    start = comma + 1;
    if (item.empty()) {
      if (spec.empty()) break;
      throw Error("--effects: empty entry in '" + spec + "' (expected +name,-name)");
    }
    if (item[0] != '+' && item[0] != '-')
      throw Error("--effects: '" + item + "' needs a sign, +" + item + " or -" + item);
    const std::string name = item.substr(1);
    const std::optional<Effect> effect = parseEffect(name);
    if (name != "all" && !effect) {
      std::string known;
      for (Effect e : kEffects) known += std::string(effectName(e)) + ", ";
      throw Error("--effects: unknown effect '" + name + "' (" + known + "all)");
    }
    out.push_back({item[0] == '+', name, effect});
  }
  return out;
}

}  // namespace

void checkOverrides(const std::string& spec) {
  parseOverrides(spec);
}

void applyOverrides(EffectPlan* plan, const std::string& spec) {
  for (const Override& o : parseOverrides(spec)) {
    const std::vector<Effect> which = o.effect
                                          ? std::vector<Effect>{*o.effect}
                                          : std::vector<Effect>(kEffects.begin(), kEffects.end());
    for (Effect e : which) {
      if (o.on)
        plan->enable(e);
      else
        plan->skip(e, "--effects -" + o.name);
    }
  }
}

std::vector<std::string> ShaderFeatures::defines() const {
  std::vector<std::string> d;
  if (!shadows) d.push_back("VOXGI_NO_SHADOWS");
  if (!emission) d.push_back("VOXGI_NO_EMISSION");
  if (!textures) d.push_back("VOXGI_NO_TEXTURES");
  if (!alpha) d.push_back("VOXGI_NO_ALPHA");
  if (!colors) d.push_back("VOXGI_NO_COLORS");
  if (!normalMaps) d.push_back("VOXGI_NO_NORMALMAPS");
  if (!secondUv) d.push_back("VOXGI_NO_UV2");
  return d;
}

ShaderFeatures shaderFeatures(const EffectPlan& plan) {
  ShaderFeatures f;
  f.shadows = plan.has(Effect::kShadows);
  f.emission = plan.has(Effect::kEmission);
  f.textures = plan.has(Effect::kTextures);
  f.alpha = plan.has(Effect::kAlpha);
  f.colors = plan.has(Effect::kColors);
  // Normal maps are textures: without the textures effect none is read.
  f.normalMaps = plan.has(Effect::kNormalMaps) && plan.has(Effect::kTextures);
  return f;
}

}  // namespace voxgi::scene
