#include "scene/effects.h"

#include <algorithm>

#include "core/log.h"
#include "scene_shared.h"

namespace voxgi::scene {

const std::vector<std::string>& effectNames() {
  static const std::vector<std::string> names = {"shadows",  "emission",   "indirect",
                                                 "specular", "textures",   "alpha",
                                                 "colors",   "normalmaps", "animation"};
  return names;
}

bool isSpecular(const Material& m) {
  // A metallic-roughness texture scales both factors down, as far as a mirror.
  return m.metallic > 0.5f || m.roughness < gpu::kGlossyRoughness ||
         m.metallicRoughnessTexture >= 0;
}

void EffectPlan::enable(const std::string& name) {
  skipped.erase(name);
  enabled.insert(name);
}

void EffectPlan::skip(const std::string& name, const std::string& reason) {
  enabled.erase(name);
  skipped[name] = reason;
}

std::vector<std::string> EffectPlan::enabledList() const {
  std::vector<std::string> out;
  for (const std::string& n : effectNames())
    if (has(n)) out.push_back(n);
  return out;
}

std::string EffectPlan::summary() const {
  std::string s;
  for (const std::string& n : enabledList()) s += (s.empty() ? "" : ", ") + n;
  if (s.empty()) s = "none";
  std::string skips;
  for (const std::string& n : effectNames()) {
    auto it = skipped.find(n);
    if (it != skipped.end()) skips += (skips.empty() ? "" : ", ") + n + " \u2014 " + it->second;
  }
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
    masked = masked || m.alphaMode == AlphaMode::kMask;
  }
  const bool lit = !scene.lights.empty() || emissive;
  EffectPlan plan;
  auto decide = [&](const char* name, bool on, const char* reason) {
    if (on)
      plan.enable(name);
    else
      plan.skip(name, reason);
  };
  decide("shadows", lit, "no light and no emissive surface");
  decide("emission", emissive, "no emissive material");
  decide("indirect", lit, "no light and no emissive surface");
  decide("specular", specular, "no mirror or glossy material");
  decide("textures", textured, "no textured material");
  decide("alpha", masked, "no alpha-masked material");
  decide("colors", scene.hasVertexColors(), "no vertex colours");
  decide("normalmaps", scene.hasNormalMaps(), "no normal-mapped material");
  decide("animation", scene.animated(), "nothing animated");
  return plan;
}

EffectPlan allEffects() {
  EffectPlan plan;
  for (const std::string& n : effectNames()) plan.enable(n);
  return plan;
}

namespace {

struct Override {
  bool on;
  std::string name;  // "all" or one of effectNames()
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
    const auto& names = effectNames();
    if (name != "all" && std::find(names.begin(), names.end(), name) == names.end()) {
      std::string known;
      for (const std::string& n : names) known += n + ", ";
      throw Error("--effects: unknown effect '" + name + "' (" + known + "all)");
    }
    out.push_back({item[0] == '+', name});
  }
  return out;
}

}  // namespace

void checkOverrides(const std::string& spec) {
  parseOverrides(spec);
}

void applyOverrides(EffectPlan* plan, const std::string& spec) {
  for (const Override& o : parseOverrides(spec)) {
    const std::vector<std::string> which =
        o.name == "all" ? effectNames() : std::vector<std::string>{o.name};
    for (const std::string& n : which) {
      if (o.on)
        plan->enable(n);
      else
        plan->skip(n, "--effects -" + o.name);
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
  return d;
}

ShaderFeatures shaderFeatures(const EffectPlan& plan) {
  ShaderFeatures f;
  f.shadows = plan.has("shadows");
  f.emission = plan.has("emission");
  f.textures = plan.has("textures");
  f.alpha = plan.has("alpha");
  f.colors = plan.has("colors");
  // Normal maps are textures: without the textures effect none is read.
  f.normalMaps = plan.has("normalmaps") && plan.has("textures");
  return f;
}

}  // namespace voxgi::scene
