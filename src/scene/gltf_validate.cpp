// The glTF loader: validity, as the glTF 2.0 spec states it, of the parts voxgi
// reads, checked before anything is read.
#include "scene/gltf_loader_impl.h"

namespace voxgi::scene::gltf_detail {

// --- validity, as the glTF 2.0 spec states it, of the parts voxgi reads ---------
// Those parts: asset, extensionsRequired, scene and scenes, every node (hierarchy,
// transform, mesh, camera, light), every mesh's primitives (mode, indices,
// material, attribute references), the accessors of POSITION, NORMAL, the TEXCOORD_n read,
// indices and animation samplers, every bufferView and buffer, every material's
// fields that the renderer uses, the textures and images those materials
// reference, every camera and every KHR_lights_punctual light. Anything else
// (textures no material uses, normal maps, skins, morph targets) is not read and
// not checked. Each problem is one line naming the field, e.g.
// "nodes[3].mesh 7 points nowhere (5 meshes)".
void Loader::validateDocument() const {
  checkAsset();
  checkExtensions();
  validateBuffers();
  validateNodeGraph();
  checkMeshes();
  checkMaterialFields();
  checkCameras();
  checkLights();
}

std::string Loader::countOf(size_t n, const char* one, const char* many) {
  return strf("%zu %s", n, n == 1 ? one : many);
}

// An index into an array of `size` elements, `field` naming where it was found.
void Loader::checkIndex(int index, size_t size, const std::string& field, const char* one,
                        const char* many) const {
  if (index < 0 || static_cast<size_t>(index) >= size)
    fail(strf("%s %d points nowhere (%s)", field.c_str(), index, countOf(size, one, many).c_str()));
}

// "2.0" -> 2, 0; false unless the text is MAJOR.MINOR in digits.
bool Loader::parseVersion(const std::string& v, int* major, int* minor) {
  const size_t dot = v.find('.');
  auto digits = [](const std::string& s) {
    return !s.empty() && s.size() < 9 &&
           std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if (dot == std::string::npos || !digits(v.substr(0, dot)) || !digits(v.substr(dot + 1)))
    return false;
  *major = std::stoi(v.substr(0, dot));
  *minor = std::stoi(v.substr(dot + 1));
  return true;
}

void Loader::checkAsset() const {
  int major = 0, minor = 0;
  const std::string& v = model_.asset.version;
  if (!parseVersion(v, &major, &minor))
    fail("asset.version \"" + v + "\": not a MAJOR.MINOR version");
  if (major != 2) fail("asset.version \"" + v + "\": only glTF 2.x is supported");
  const std::string& mv = model_.asset.minVersion;
  if (mv.empty()) return;
  if (!parseVersion(mv, &major, &minor))
    fail("asset.minVersion \"" + mv + "\": not a MAJOR.MINOR version");
  if (major != 2 || minor > 0)
    fail("asset.minVersion \"" + mv + "\": needs a reader newer than glTF 2.0");
}

void Loader::checkExtensions() const {
  const auto& used = model_.extensionsUsed;
  for (size_t i = 0; i < model_.extensionsRequired.size(); ++i) {
    const std::string& r = model_.extensionsRequired[i];
    if (!kSupportedExtensions.count(r)) fail("requires the unsupported extension " + r);
    if (std::find(used.begin(), used.end(), r) == used.end())
      fail(strf("extensionsRequired[%zu] %s is not in extensionsUsed", i, r.c_str()));
  }
}

void Loader::checkMeshes() const {
  for (size_t m = 0; m < model_.meshes.size(); ++m) {
    const auto& prims = model_.meshes[m].primitives;
    if (prims.empty()) fail(strf("meshes[%zu].primitives is empty", m));
    for (size_t p = 0; p < prims.size(); ++p) {
      const auto& prim = prims[p];
      const std::string where = strf("meshes[%zu].primitives[%zu]", m, p);
      for (const auto& [name, index] : prim.attributes)
        checkIndex(index, model_.accessors.size(), where + ".attributes." + name, "accessor",
                   "accessors");
      if (prim.indices != -1)
        checkIndex(prim.indices, model_.accessors.size(), where + ".indices", "accessor",
                   "accessors");
      if (prim.material != -1)
        checkIndex(prim.material, model_.materials.size(), where + ".material", "material",
                   "materials");
    }
  }
}

// A factor the spec bounds: refused outside [lo, hi] (NaN included).
void Loader::checkRange(double v, double lo, double hi, const std::string& field) const {
  if (!(v >= lo && v <= hi)) fail(strf("%s %g: outside [%g, %g]", field.c_str(), v, lo, hi));
}

void Loader::checkMaterialFields() const {
  constexpr double kHuge = std::numeric_limits<double>::max();
  for (size_t i = 0; i < model_.materials.size(); ++i) {
    const auto& m = model_.materials[i];
    const std::string at = strf("materials[%zu]", i);
    const auto& pbr = m.pbrMetallicRoughness;
    const std::string p = at + ".pbrMetallicRoughness.";
    if (pbr.baseColorFactor.size() != 4) fail(p + "baseColorFactor: needs 4 numbers");
    for (size_t c = 0; c < 4; ++c)
      checkRange(pbr.baseColorFactor[c], 0.0, 1.0, strf("%sbaseColorFactor[%zu]", p.c_str(), c));
    checkRange(pbr.metallicFactor, 0.0, 1.0, p + "metallicFactor");
    checkRange(pbr.roughnessFactor, 0.0, 1.0, p + "roughnessFactor");
    // Above 1 is accepted: exporters wrote HDR emission so before
    // KHR_materials_emissive_strength (scenes/cornell_box does).
    if (m.emissiveFactor.size() != 3) fail(at + ".emissiveFactor: needs 3 numbers");
    for (size_t c = 0; c < 3; ++c)
      checkRange(m.emissiveFactor[c], 0.0, kHuge, strf("%s.emissiveFactor[%zu]", at.c_str(), c));
    auto it = m.extensions.find("KHR_materials_emissive_strength");
    if (it != m.extensions.end() && it->second.Has("emissiveStrength"))
      checkRange(it->second.Get("emissiveStrength").GetNumberAsDouble(), 0.0, kHuge,
                 at + ".extensions.KHR_materials_emissive_strength.emissiveStrength");
    if (m.alphaMode != "OPAQUE" && m.alphaMode != "MASK" && m.alphaMode != "BLEND")
      fail(at + ".alphaMode \"" + m.alphaMode + "\": not OPAQUE, MASK or BLEND");
    checkRange(m.alphaCutoff, 0.0, kHuge, at + ".alphaCutoff");
    if (pbr.baseColorTexture.index != -1)
      checkIndex(pbr.baseColorTexture.index, model_.textures.size(), p + "baseColorTexture.index",
                 "texture", "textures");
    if (pbr.metallicRoughnessTexture.index != -1)
      checkIndex(pbr.metallicRoughnessTexture.index, model_.textures.size(),
                 p + "metallicRoughnessTexture.index", "texture", "textures");
    if (m.emissiveTexture.index != -1)
      checkIndex(m.emissiveTexture.index, model_.textures.size(), at + ".emissiveTexture.index",
                 "texture", "textures");
    if (m.normalTexture.index != -1) {
      checkIndex(m.normalTexture.index, model_.textures.size(), at + ".normalTexture.index",
                 "texture", "textures");
      checkRange(m.normalTexture.scale, -kHuge, kHuge, at + ".normalTexture.scale");
    }
    if (m.occlusionTexture.index != -1) {
      checkIndex(m.occlusionTexture.index, model_.textures.size(), at + ".occlusionTexture.index",
                 "texture", "textures");
      checkRange(m.occlusionTexture.strength, 0.0, 1.0, at + ".occlusionTexture.strength");
    }
  }
}

void Loader::checkCameras() const {
  constexpr double kHuge = std::numeric_limits<double>::max();
  for (size_t i = 0; i < model_.cameras.size(); ++i) {
    const auto& c = model_.cameras[i];
    const std::string at = strf("cameras[%zu]", i);
    if (c.type == "perspective") {
      const auto& p = c.perspective;
      const std::string f = at + ".perspective.";
      if (!(p.yfov > 0.0)) fail(strf("%syfov %g: must be positive", f.c_str(), p.yfov));
      if (!(p.znear > 0.0)) fail(strf("%sznear %g: must be positive", f.c_str(), p.znear));
      if (p.zfar != 0.0 && !(p.zfar > p.znear))
        fail(strf("%szfar %g: must be greater than znear %g", f.c_str(), p.zfar, p.znear));
      checkRange(p.aspectRatio, 0.0, kHuge, f + "aspectRatio");
    } else if (c.type == "orthographic") {
      const auto& o = c.orthographic;
      const std::string f = at + ".orthographic.";
      if (o.xmag == 0.0 || o.ymag == 0.0 || !std::isfinite(o.xmag) || !std::isfinite(o.ymag))
        fail(f + "xmag and ymag: must be finite and not zero");
      checkRange(o.znear, 0.0, kHuge, f + "znear");
      if (!(o.zfar > o.znear))
        fail(strf("%szfar %g: must be greater than znear %g", f.c_str(), o.zfar, o.znear));
    } else {
      fail(at + ".type \"" + c.type + "\": not perspective or orthographic");
    }
  }
}

void Loader::checkLights() const {
  constexpr double kHalfPi = 1.5707963267948966;
  for (size_t i = 0; i < model_.lights.size(); ++i) {
    const auto& l = model_.lights[i];
    const std::string at = strf("KHR_lights_punctual.lights[%zu]", i);
    if (l.type != "directional" && l.type != "point" && l.type != "spot")
      fail(at + ".type: unknown type '" + l.type + "'");
    if (!l.color.empty() && l.color.size() != 3) fail(at + ".color: needs 3 numbers");
    for (size_t c = 0; c < l.color.size(); ++c)
      checkRange(l.color[c], 0.0, 1.0, strf("%s.color[%zu]", at.c_str(), c));
    checkRange(l.intensity, 0.0, std::numeric_limits<double>::max(), at + ".intensity");
    if (l.range < 0.0 || !std::isfinite(l.range))
      fail(strf("%s.range %g: must be positive", at.c_str(), l.range));
    if (l.type != "spot") continue;
    checkRange(l.spot.outerConeAngle, 0.0, kHalfPi, at + ".spot.outerConeAngle");
    if (!(l.spot.innerConeAngle >= 0.0 && l.spot.innerConeAngle < l.spot.outerConeAngle))
      fail(strf("%s.spot.innerConeAngle %g: outside [0, outerConeAngle %g)", at.c_str(),
                l.spot.innerConeAngle, l.spot.outerConeAngle));
  }
}

void Loader::validateBuffers() const {
  for (size_t i = 0; i < model_.bufferViews.size(); ++i) {
    const auto& bv = model_.bufferViews[i];
    checkIndex(bv.buffer, model_.buffers.size(), strf("bufferViews[%zu].buffer", i), "buffer",
               "buffers");
    if (bv.byteStride != 0 && (bv.byteStride < 4 || bv.byteStride > 252 || bv.byteStride % 4))
      fail(strf("bufferViews[%zu].byteStride %zu: not a multiple of 4 from 4 to 252", i,
                bv.byteStride));
    const size_t size = model_.buffers[static_cast<size_t>(bv.buffer)].data.size();
    if (bv.byteOffset > size || bv.byteLength > size - bv.byteOffset)
      fail(strf("bufferView %zu: bytes [%zu, %zu) exceed buffer %d of %zu bytes", i, bv.byteOffset,
                bv.byteOffset + bv.byteLength, bv.buffer, size));
  }
}

// The indices a node holds (its children are checked with the graph).
void Loader::checkNode(size_t i) const {
  const auto& node = model_.nodes[i];
  const std::string at = strf("nodes[%zu]", i);
  if (node.mesh != -1) checkIndex(node.mesh, model_.meshes.size(), at + ".mesh", "mesh", "meshes");
  if (node.camera != -1)
    checkIndex(node.camera, model_.cameras.size(), at + ".camera", "camera", "cameras");
  auto le = node.extensions.find("KHR_lights_punctual");
  if (le != node.extensions.end() && le->second.Has("light"))
    checkIndex(le->second.Get("light").GetNumberAsInt(), model_.lights.size(),
               at + ".extensions.KHR_lights_punctual.light", "light", "lights");
}

void Loader::validateNodeGraph() const {
  const size_t n = model_.nodes.size();
  std::vector<int> parent(n, -1);
  for (size_t i = 0; i < n; ++i) {
    checkNode(i);
    const auto& children = model_.nodes[i].children;
    for (size_t k = 0; k < children.size(); ++k) {
      const int c = children[k];
      checkIndex(c, n, strf("nodes[%zu].children[%zu]", i, k), "node", "nodes");
      if (static_cast<size_t>(c) == i) fail(strf("node %zu: is its own child (cycle)", i));
      if (parent[static_cast<size_t>(c)] >= 0)
        fail(strf("node %d: has two parents (%d and %zu); the node graph must be a forest", c,
                  parent[static_cast<size_t>(c)], i));
      parent[static_cast<size_t>(c)] = static_cast<int>(i);
    }
  }
  // With one parent each, a cycle is a loop of parent links. Node i's walk up
  // stops at a root or at a node an earlier walk showed to reach one, and meets
  // itself again only on a loop: each node is walked once, however deep the
  // hierarchy.
  std::vector<char> rooted(n, 0);
  std::vector<size_t> walkedFrom(n, n);  // the node whose walk passed here; n: none
  std::vector<size_t> walk;
  for (size_t i = 0; i < n; ++i) {
    walk.clear();
    for (size_t u = i; !rooted[u];) {
      if (walkedFrom[u] == i) fail(strf("node %zu: cycle in the node graph", i));
      walkedFrom[u] = i;
      walk.push_back(u);
      if (parent[u] < 0) break;
      u = static_cast<size_t>(parent[u]);
    }
    for (size_t u : walk) rooted[u] = 1;
  }
  checkScenes(parent);
}

void Loader::checkScenes(const std::vector<int>& parent) const {
  const size_t count = model_.scenes.size();
  if (model_.defaultScene != -1 &&
      (model_.defaultScene < 0 || static_cast<size_t>(model_.defaultScene) >= count))
    fail(strf("scene %d out of range (%s)", model_.defaultScene,
              countOf(count, "scene", "scenes").c_str()));
  for (size_t s = 0; s < count; ++s) {
    const auto& roots = model_.scenes[s].nodes;
    for (size_t k = 0; k < roots.size(); ++k) {
      const std::string at = strf("scenes[%zu].nodes[%zu]", s, k);
      checkIndex(roots[k], model_.nodes.size(), at, "node", "nodes");
      const int p = parent[static_cast<size_t>(roots[k])];
      if (p >= 0)
        fail(strf("%s %d is not a root node: node %d is its parent", at.c_str(), roots[k], p));
      if (std::find(roots.begin(), roots.begin() + static_cast<long>(k), roots[k]) !=
          roots.begin() + static_cast<long>(k))
        fail(strf("%s %d is listed twice", at.c_str(), roots[k]));
    }
  }
}

}  // namespace voxgi::scene::gltf_detail
