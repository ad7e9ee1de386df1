// The glTF loader: each primitive into vertices, indices and draws, with its
// colours and tangents.
#include "scene/gltf_loader_impl.h"

namespace voxgi::scene::gltf_detail {

void Loader::addPrimitive(int meshIndex, size_t pi, int nodeIndex, const glm::dmat4& world) {
  const auto& prim = model_.meshes[static_cast<size_t>(meshIndex)].primitives[pi];
  const std::string where = strf("mesh %d primitive %zu", meshIndex, pi);
  const int mode = prim.mode == -1 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
  if (mode < 0 || mode > 6)
    fail(strf("%s: mode %d is not a glTF primitive mode (0-6)", where.c_str(), mode));
  if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
      mode != TINYGLTF_MODE_TRIANGLE_FAN) {
    ignored_.pointsAndLines.add(where);
    return;
  }
  if (!prim.targets.empty()) ignored_.morphed.add(where);
  const PrimitiveAttributes attr = readAttributes(prim, where);
  const size_t count = attr.position.count;
  const std::vector<uint32_t> idx = triangleList(readIndices(prim, count, where), mode);
  const bool mirrored = glm::determinant(glm::dmat3(world)) < 0.0;
  const size_t base = scene_.vertices.size();
  addVertices(attr, base, world, where);
  std::vector<glm::dvec3> faceSum(count, glm::dvec3(0.0));
  const std::vector<uint32_t> kept = keepNonDegenerate(idx, base, mirrored, where, &faceSum);
  repairNormals(base, faceSum, attr.hasNormals, where);
  if (attr.normalMapped || !scene_.tangents.empty()) {
    // (1, 0, 0, 1) before the first normal-mapped primitive and for primitives
    // without a normal map: never read.
    scene_.tangents.resize(base + count, glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
    if (attr.normalMapped)
      readTangents(attr.tangent, attr.hasTangent, attr.normalChannel, kept, base, world, mirrored);
  }
  if (kept.empty()) return;
  if (moving_[static_cast<size_t>(nodeIndex)])
    addAnimatedRange(nodeIndex, base, count, world, mirrored);
  addDraw(prim, meshIndex, nodeIndex, base, kept, where);
}

// POSITION, NORMAL, the material's TEXCOORD_n, COLOR_0 and TANGENT, in that order.
Loader::PrimitiveAttributes Loader::readAttributes(const tinygltf::Primitive& prim,
                                                   const std::string& where) {
  PrimitiveAttributes a;
  auto pos = prim.attributes.find("POSITION");
  if (pos == prim.attributes.end()) fail(where + ": no POSITION attribute");
  a.position = vertexAttribute(pos->second, "POSITION");
  const size_t count = a.position.count;
  if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
    a.normal = vertexAttribute(it->second, "NORMAL");
    if (a.normal.count != count) fail(where + ": NORMAL and POSITION counts differ");
    a.hasNormals = true;
  }
  // The texture coordinates the material's textures read (Material::uv, uv2),
  // baked with their KHR_texture_transform into the vertex UVs.
  const bool hasMaterial =
      prim.material >= 0 && static_cast<size_t>(prim.material) < model_.materials.size();
  const Material* mat =
      hasMaterial ? &scene_.materials[static_cast<size_t>(prim.material)] : nullptr;
  if (mat) {
    a.uvMap[0] = mat->uv;
    a.uvMap[1] = mat->hasUv2 ? mat->uv2 : mat->uv;
  }
  for (int c = 0; c < 2; ++c) {
    const int set = a.uvMap[c].texCoord;
    const std::string uvName = strf("TEXCOORD_%d", set);
    if (auto it = prim.attributes.find(uvName); it != prim.attributes.end()) {
      a.uv[c] = vertexAttribute(it->second, uvName.c_str());
      if (a.uv[c].count != count)
        fail(strf("%s: %s and POSITION counts differ", where.c_str(), uvName.c_str()));
      a.hasUv[c] = true;
    } else if (set != 0) {
      const std::array<std::string, 2>& fields = uvField_[static_cast<size_t>(prim.material)];
      fail(strf("%s: %s %d: the primitive has no %s attribute", where.c_str(),
                (c == 1 && !fields[1].empty() ? fields[1] : fields[0]).c_str(), set,
                uvName.c_str()));
    }
  }
  if (auto it = prim.attributes.find("COLOR_0"); it != prim.attributes.end()) {
    a.color = colorAttribute(it->second, count, where);
    a.hasColor = true;
  }
  if (auto it = prim.attributes.find("TANGENT"); it != prim.attributes.end()) {
    a.tangent = tangentAttribute(it->second, count, where);
    a.hasTangent = true;
  }
  a.normalMapped = mat && mat->normalTexture >= 0;
  a.normalChannel = mat ? mat->normalChannel : 0;
  return a;
}

Loader::View Loader::colorAttribute(int index, size_t count, const std::string& where) const {
  const View col = accessor(index, "COLOR_0", {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4},
                            {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                             TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT});
  if (col.count != count) fail(where + ": COLOR_0 and POSITION counts differ");
  if (col.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT && !col.normalized)
    fail(strf("accessors[%d] (COLOR_0): integer colours must be normalized", index));
  return col;
}

Loader::View Loader::tangentAttribute(int index, size_t count, const std::string& where) const {
  const View tan =
      accessor(index, "TANGENT", {TINYGLTF_TYPE_VEC4}, {TINYGLTF_COMPONENT_TYPE_FLOAT});
  if (tan.count != count) fail(where + ": TANGENT and POSITION counts differ");
  for (size_t i = 0; i < tan.count; ++i)
    for (size_t k = 0; k < 4; ++k)
      if (!std::isfinite(
              readComponent(tan.data + i * tan.stride + 4 * k, tan.componentType, false)))
        fail(strf("accessors[%d] (TANGENT): element %zu is NaN or Inf", index, i));
  return tan;
}

// The primitive's indices, each checked against the vertex count; 0, 1, 2, ...
// without an index accessor.
std::vector<uint32_t> Loader::readIndices(const tinygltf::Primitive& prim, size_t vertexCount,
                                          const std::string& where) const {
  std::vector<uint32_t> idx;
  if (prim.indices == -1) {
    idx.resize(vertexCount);
    for (size_t i = 0; i < vertexCount; ++i) idx[i] = static_cast<uint32_t>(i);
    return idx;
  }
  const View iv =
      accessor(prim.indices, "indices", {TINYGLTF_TYPE_SCALAR},
               {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT});
  idx.resize(iv.count);
  for (size_t i = 0; i < iv.count; ++i) {
    const unsigned char* q = iv.data + i * iv.stride;
    uint32_t v = 0;
    if (iv.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE)
      v = *q;
    else if (iv.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
      uint16_t s;
      std::memcpy(&s, q, 2);
      v = s;
    } else
      std::memcpy(&v, q, 4);
    const uint32_t restart = iv.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ? 0xffu
                             : iv.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT
                                 ? 0xffffu
                                 : 0xffffffffu;
    if (v == restart)
      fail(strf("%s: index %u at %zu is the primitive restart value, which glTF forbids",
                where.c_str(), v, i));
    if (v >= vertexCount)
      fail(strf("%s: index %u at %zu is out of range (%zu vertices)", where.c_str(), v, i,
                vertexCount));
    idx[i] = v;
  }
  return idx;
}

// Appends the primitive's vertices at `base`: world positions (world_), normals
// by the normal matrix (zero when absent), transformed UVs and colours.
void Loader::addVertices(const PrimitiveAttributes& a, size_t base, const glm::dmat4& world,
                         const std::string& where) {
  const size_t count = a.position.count;
  const glm::mat3 normalMatrix = glm::mat3(glm::transpose(glm::inverse(glm::dmat3(world))));
  scene_.vertices.resize(base + count);
  world_.resize(base + count);
  if (a.hasColor || !scene_.colors.empty()) {
    // White for the vertices before the first coloured primitive and for
    // primitives without COLOR_0.
    scene_.colors.resize(base + count, glm::vec4(1.0f));
    if (a.hasColor) readColors(a.color, base, where);
  }
  for (size_t i = 0; i < count; ++i) {
    Vertex& v = scene_.vertices[base + i];
    const glm::vec3 lp = readVec3(a.position, i);
    if (!finite(lp)) fail(strf("%s: vertex %zu has a NaN or Inf position", where.c_str(), i));
    world_[base + i] = glm::dvec3(world * glm::dvec4(glm::dvec3(lp), 1.0));
    if (!finite(glm::vec3(world_[base + i])))
      fail(strf("%s: vertex %zu overflows after the node transform", where.c_str(), i));
    v.normal = glm::vec3(0.0f);
    if (a.hasNormals) {
      v.normal = normalMatrix * readVec3(a.normal, i);
    }
    v.uv = glm::vec2(0.0f);
    if (a.hasUv[0]) v.uv = readUv(a.uv[0], i, a.uvMap[0]);
    v.uv2 = glm::vec2(0.0f);
    if (a.hasUv[1]) v.uv2 = readUv(a.uv[1], i, a.uvMap[1]);
  }
}

// Element i of a TEXCOORD_n accessor through the material's texture transform;
// (0, 0) where it or the transformed value is NaN or Inf.
glm::vec2 Loader::readUv(const View& t, size_t i, const TextureTransform& uvMap) {
  const size_t cs = static_cast<size_t>(
      tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(t.componentType)));
  glm::vec2 uv(readComponent(t.data + i * t.stride, t.componentType, t.normalized),
               readComponent(t.data + i * t.stride + cs, t.componentType, t.normalized));
  if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) uv = glm::vec2(0.0f);
  uv = uvMap.apply(uv);
  if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) uv = glm::vec2(0.0f);
  return uv;
}

// Drops zero-area triangles (counted in dropped_); adds each kept face's
// area-weighted normal to faceSum of its three vertices. Mirrored transforms
// swap the winding back to counter-clockwise.
std::vector<uint32_t> Loader::keepNonDegenerate(const std::vector<uint32_t>& idx, size_t base,
                                                bool mirrored, const std::string& where,
                                                std::vector<glm::dvec3>* faceSum) {
  std::vector<uint32_t> kept;
  kept.reserve(idx.size());
  size_t degenerate = 0;
  for (size_t i = 0; i < idx.size(); i += 3) {
    uint32_t a = idx[i], b = idx[i + 1], c = idx[i + 2];
    if (mirrored) std::swap(b, c);
    const glm::dvec3 e =
        glm::cross(world_[base + b] - world_[base + a], world_[base + c] - world_[base + a]);
    if (!(glm::dot(e, e) > 0.0) || !std::isfinite(glm::dot(e, e))) {
      ++degenerate;
      continue;
    }
    kept.insert(kept.end(), {a, b, c});
    for (uint32_t k : {a, b, c}) (*faceSum)[k] += e;
  }
  if (degenerate) {
    dropped_ += degenerate;
    droppedIn_.push_back(where);
  }
  return kept;
}

// Normalizes the normals at `base`; those missing, zero or NaN become the
// area-weighted average of the faces around the vertex (counted in repaired_
// when the file had normals).
void Loader::repairNormals(size_t base, const std::vector<glm::dvec3>& faceSum, bool hasNormals,
                           const std::string& where) {
  size_t repaired = 0;
  for (size_t i = 0; i < faceSum.size(); ++i) {
    Vertex& v = scene_.vertices[base + i];
    const float len2 = glm::dot(v.normal, v.normal);
    if (len2 > 0.0f && std::isfinite(len2)) {
      v.normal = glm::normalize(v.normal);
    } else {
      if (hasNormals) ++repaired;
      const double f2 = glm::dot(faceSum[i], faceSum[i]);
      v.normal = f2 > 0.0 && std::isfinite(f2) ? glm::vec3(glm::normalize(faceSum[i]))
                                               : glm::vec3(0, 1, 0);
    }
  }
  if (repaired) {
    repaired_ += repaired;
    repairedIn_.push_back(where);
  }
}

// The vertices at `base` kept in the node's own space, to be re-posed (Scene::pose).
void Loader::addAnimatedRange(int nodeIndex, size_t base, size_t count, const glm::dmat4& world,
                              bool mirrored) {
  AnimatedRange r;
  r.firstVertex = static_cast<uint32_t>(base);
  r.node = nodeIndex;
  const glm::mat3 toLocal = glm::mat3(glm::transpose(glm::dmat3(world)));
  const glm::dmat4 inverse = glm::inverse(world);
  for (size_t i = 0; i < count; ++i) {
    r.localPositions.push_back(glm::dvec3(inverse * glm::dvec4(world_[base + i], 1.0)));
    r.localNormals.push_back(toLocal * scene_.vertices[base + i].normal);
  }
  if (!scene_.tangents.empty()) {
    const glm::mat3 inverse3 = glm::mat3(glm::inverse(glm::dmat3(world)));
    for (size_t i = 0; i < count; ++i) {
      const glm::vec4 wt = scene_.tangents[base + i];
      r.localTangents.push_back(glm::vec4(inverse3 * glm::vec3(wt), mirrored ? -wt.w : wt.w));
    }
  }
  scene_.animatedRanges.push_back(std::move(r));
}

void Loader::addDraw(const tinygltf::Primitive& prim, int meshIndex, int nodeIndex, size_t base,
                     const std::vector<uint32_t>& kept, const std::string& where) {
  Draw d;
  d.firstIndex = static_cast<uint32_t>(scene_.indices.size());
  d.indexCount = static_cast<uint32_t>(kept.size());
  d.node = nodeIndex;
  d.mesh = meshIndex;
  if (prim.material != -1) {
    if (prim.material < 0 || static_cast<size_t>(prim.material) >= model_.materials.size())
      fail(strf("%s: material %d does not exist", where.c_str(), prim.material));
    d.material = prim.material;
  } else {
    d.material = defaultMaterial_;
  }
  for (uint32_t k : kept) scene_.indices.push_back(static_cast<uint32_t>(base) + k);
  scene_.draws.push_back(d);
  drawWhere_.push_back(where);
}

// Tangents of a normal-mapped primitive into scene_.tangents from `base` on: the
// file's TANGENT through the node transform (a mirroring transform flips the
// handedness), or, without one, generated with MikkTSpace (scene/tangents.h) over
// the primitive's triangles `kept` in world space, with the UVs of `channel` (the
// one the normal texture reads). A zero tangent or one parallel
// to its normal gets any perpendicular vector; w is read by its sign.
void Loader::readTangents(const View& t, bool fromFile, int channel,
                          const std::vector<uint32_t>& kept, size_t base, const glm::dmat4& world,
                          bool mirrored) {
  const size_t count = t.count ? t.count : scene_.vertices.size() - base;
  if (!fromFile) {
    std::vector<glm::vec3> pos(count), nrm(count);
    std::vector<glm::vec2> uv(count);
    for (size_t i = 0; i < count; ++i) {
      pos[i] = glm::vec3(world_[base + i] - world_[base]);
      nrm[i] = scene_.vertices[base + i].normal;
      // glTF's v runs down the image, MikkTSpace's up (the bitangent of a glTF
      // tangent points up the image, as exporters write it): v enters flipped.
      const glm::vec2 tuv = channelUv(scene_.vertices[base + i], channel);
      uv[i] = glm::vec2(tuv.x, -tuv.y);
    }
    const std::vector<glm::vec4> gen = generateTangents(pos, nrm, uv, kept);
    std::copy(gen.begin(), gen.end(), scene_.tangents.begin() + static_cast<ptrdiff_t>(base));
    return;
  }
  const glm::mat3 m = glm::mat3(world);
  for (size_t i = 0; i < count; ++i) {
    glm::vec4 lt;
    for (int k = 0; k < 4; ++k)
      lt[k] =
          readComponent(t.data + i * t.stride + 4 * static_cast<size_t>(k), t.componentType, false);
    const glm::vec3 n = scene_.vertices[base + i].normal;
    glm::vec3 wt = m * glm::vec3(lt);
    wt -= n * glm::dot(n, wt);
    const float len = glm::length(wt);
    wt = len > 1e-6f && std::isfinite(len) ? wt / len : anyPerpendicular(n);
    const float w = (lt.w < 0.0f) != mirrored ? -1.0f : 1.0f;
    scene_.tangents[base + i] = glm::vec4(wt, w);
  }
}

// COLOR_0 into scene_.colors from `base` on: VEC3 (alpha 1) or VEC4; a value that
// is NaN, Inf or outside [0, 1] is clamped (NaN reads as 1).
void Loader::readColors(const View& c, size_t base, const std::string& where) {
  const size_t cs = static_cast<size_t>(
      tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(c.componentType)));
  const int n = c.type == TINYGLTF_TYPE_VEC4 ? 4 : 3;
  size_t bad = 0;
  for (size_t i = 0; i < c.count; ++i) {
    glm::vec4 rgba(1.0f);
    for (int k = 0; k < n; ++k) {
      float x = readComponent(c.data + i * c.stride + static_cast<size_t>(k) * cs, c.componentType,
                              c.normalized);
      if (!(x >= 0.0f && x <= 1.0f)) {
        ++bad;
        x = std::isnan(x) ? 1.0f : std::clamp(x, 0.0f, 1.0f);
      }
      rgba[k] = x;
    }
    scene_.colors[base + i] = rgba;
  }
  if (bad && !colorWarned_) {
    colorWarned_ = true;
    warn_(strf("%s: %zu COLOR_0 components outside [0, 1] (clamped)", where.c_str(), bad));
  }
}

}  // namespace voxgi::scene::gltf_detail
