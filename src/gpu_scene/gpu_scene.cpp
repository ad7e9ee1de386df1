#include "gpu_scene/gpu_scene.h"

#include "scene/light_tree.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <utility>

namespace voxgi::scene {

std::vector<gpu::GpuMaterial> GpuScene::packMaterials(const Scene& s) {
  std::vector<gpu::GpuMaterial> out;
  for (const Material& m : s.materials) {
    gpu::GpuMaterial g{};
    g.baseColor = m.baseColor;
    g.emission = m.emission;
    g.metallic = m.metallic;
    g.roughness = m.roughness;
    // BLEND: alphaStops draws its threshold; the voxels, solid or empty, take the
    // surface where it is at least half opaque.
    g.alphaCutoff = m.alphaMode == AlphaMode::kBlend ? 0.5f : m.alphaCutoff;
    if (m.normalTexture >= 0) {
      g.normalTexture = static_cast<uint32_t>(m.normalTexture);
      g.normalScale = m.normalScale;
    }
    g.flags = (m.baseColorTexture >= 0 ? gpu::kMaterialHasTexture : 0u) |
              (m.doubleSided ? gpu::kMaterialDoubleSided : 0u) |
              (m.alphaMode == AlphaMode::kMask ? gpu::kMaterialAlphaMask : 0u) |
              (m.alphaMode == AlphaMode::kBlend ? gpu::kMaterialAlphaBlend : 0u) |
              (m.emissiveTexture >= 0 ? gpu::kMaterialHasEmissiveTexture : 0u) |
              (m.metallicRoughnessTexture >= 0 ? gpu::kMaterialHasMetallicRoughnessTexture : 0u) |
              (m.normalTexture >= 0 ? gpu::kMaterialHasNormalTexture : 0u) |
              (m.occlusionTexture >= 0 ? gpu::kMaterialHasOcclusionTexture : 0u) |
              (m.emissiveChannel == 1 ? gpu::kMaterialEmissiveUv2 : 0u) |
              (m.metallicRoughnessChannel == 1 ? gpu::kMaterialMetallicRoughnessUv2 : 0u) |
              (m.normalChannel == 1 ? gpu::kMaterialNormalUv2 : 0u) |
              (m.occlusionChannel == 1 ? gpu::kMaterialOcclusionUv2 : 0u);
    if (m.occlusionTexture >= 0) {
      g.occlusionStrength = m.occlusionStrength;
      g.occlusionTexture = static_cast<uint32_t>(m.occlusionTexture);
    }
    g.texture = m.baseColorTexture >= 0 ? static_cast<uint32_t>(m.baseColorTexture) : 0u;
    g.emissiveTexture = m.emissiveTexture >= 0 ? static_cast<uint32_t>(m.emissiveTexture) : 0u;
    g.metallicRoughnessTexture =
        m.metallicRoughnessTexture >= 0 ? static_cast<uint32_t>(m.metallicRoughnessTexture) : 0u;
    out.push_back(g);
  }
  return out;
}

std::vector<gpu::GpuLight> GpuScene::packLights(const Scene& s) {
  std::vector<gpu::GpuLight> out;
  for (const Light& l : s.lights) {
    gpu::GpuLight g{};
    const uint32_t type = l.type == LightType::kDirectional ? gpu::kLightDirectional
                          : l.type == LightType::kPoint     ? gpu::kLightPoint
                                                            : gpu::kLightSpot;
    g.positionType = glm::vec4(l.position, static_cast<float>(type));
    g.directionRange = glm::vec4(l.direction, l.range);
    g.radiance = glm::vec4(l.color * l.intensity, 0.0f);
    g.cone = glm::vec4(std::cos(l.innerConeAngle), std::cos(l.outerConeAngle), 0.0f, 0.0f);
    out.push_back(g);
  }
  return out;
}

GpuScene::GpuScene(const Scene& s) : scene_(s) {
  const auto start = std::chrono::steady_clock::now();
  hasOcclusion_ = std::any_of(s.materials.begin(), s.materials.end(),
                              [](const Material& m) { return m.occlusionTexture >= 0; });
  bytes_ = createGeometry(s);
  bytes_ += createShadingBuffers(s);
  createTextures(s);
  bytes_ += textureBytes_;
  sampler_ = gl::createSampler();
  glSamplerParameteri(sampler_.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glSamplerParameteri(sampler_.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glSamplerParameteri(sampler_.id(), GL_TEXTURE_WRAP_S, GL_REPEAT);
  glSamplerParameteri(sampler_.id(), GL_TEXTURE_WRAP_T, GL_REPEAT);
  uploadMs_ =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

size_t GpuScene::createGeometry(const Scene& s) {
  const auto vbytes = static_cast<GLsizeiptr>(s.vertices.size() * sizeof(Vertex));
  const auto ibytes = static_cast<GLsizeiptr>(s.indices.size() * sizeof(uint32_t));
  // Animated scenes rewrite their vertices (updateGeometry); others never do.
  vertices_ = gl::createBuffer(vbytes, s.vertices.empty() ? nullptr : s.vertices.data(),
                               s.meshesAnimated() ? GL_DYNAMIC_STORAGE_BIT : 0);
  indices_ = gl::createBuffer(ibytes, s.indices.empty() ? nullptr : s.indices.data());
  if (s.meshesAnimated())
    previousVertices_ = gl::createBuffer(vbytes, s.vertices.empty() ? nullptr : s.vertices.data());
  vao_ = gl::createVertexArray();
  const GLuint vao = vao_.id();
  glVertexArrayVertexBuffer(vao, 0, vertices_.id(), 0, sizeof(Vertex));
  // The position in the previous frame (motion vectors), from binding 2: the same
  // buffer unless meshes move.
  glVertexArrayVertexBuffer(vao, 2, s.meshesAnimated() ? previousVertices_.id() : vertices_.id(), 0,
                            sizeof(Vertex));
  glEnableVertexArrayAttrib(vao, gpu::kPreviousPositionAttribute);
  glVertexArrayAttribFormat(vao, gpu::kPreviousPositionAttribute, 3, GL_FLOAT, GL_FALSE,
                            offsetof(Vertex, position));
  glVertexArrayAttribBinding(vao, gpu::kPreviousPositionAttribute, 2);
  glVertexArrayElementBuffer(vao, indices_.id());
  const GLuint attributes[4] = {0, 1, 2, gpu::kUv2Attribute};
  const GLuint offsets[4] = {offsetof(Vertex, position), offsetof(Vertex, normal),
                             offsetof(Vertex, uv), offsetof(Vertex, uv2)};
  const GLint sizes[4] = {3, 3, 2, 2};
  for (size_t i = 0; i < 4; ++i) {
    const GLuint a = attributes[i];
    glEnableVertexArrayAttrib(vao, a);
    glVertexArrayAttribFormat(vao, a, sizes[i], GL_FLOAT, GL_FALSE, offsets[i]);
    glVertexArrayAttribBinding(vao, a, 0);
  }
  return static_cast<size_t>(vbytes + ibytes) + createOptionalStreams(s);
}

size_t GpuScene::createOptionalStreams(const Scene& s) {
  const GLuint vao = vao_.id();
  size_t cbytes = 0;
  if (s.hasVertexColors()) {
    // A stream of its own, bound only here: scenes without colours carry none.
    cbytes = s.colors.size() * sizeof(glm::vec4);
    colors_ = gl::createBuffer(static_cast<GLsizeiptr>(cbytes), s.colors.data());
    glVertexArrayVertexBuffer(vao, 1, colors_.id(), 0, sizeof(glm::vec4));
    glEnableVertexArrayAttrib(vao, gpu::kColorAttribute);
    glVertexArrayAttribFormat(vao, gpu::kColorAttribute, 4, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao, gpu::kColorAttribute, 1);
  }
  if (s.hasNormalMaps()) {
    // Tangents likewise: only scenes with normal maps carry them (binding 3).
    const auto tbytes = static_cast<GLsizeiptr>(s.tangents.size() * sizeof(glm::vec4));
    cbytes += static_cast<size_t>(tbytes);
    tangents_ = gl::createBuffer(tbytes, s.tangents.data(),
                                 s.meshesAnimated() ? GL_DYNAMIC_STORAGE_BIT : 0);
    glVertexArrayVertexBuffer(vao, 3, tangents_.id(), 0, sizeof(glm::vec4));
    glEnableVertexArrayAttrib(vao, gpu::kTangentAttribute);
    glVertexArrayAttribFormat(vao, gpu::kTangentAttribute, 4, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao, gpu::kTangentAttribute, 3);
  }
  return cbytes;
}

size_t GpuScene::createShadingBuffers(const Scene& s) {
  const auto mats = packMaterials(s);
  const auto lights = packLights(s);
  const auto emitters = packEmitters(buildEmitters(s));
  materials_ = gl::createBuffer(static_cast<GLsizeiptr>(mats.size() * sizeof(gpu::GpuMaterial)),
                                mats.data());
  lights_ = gl::createBuffer(static_cast<GLsizeiptr>(lights.size() * sizeof(gpu::GpuLight)),
                             lights.empty() ? nullptr : lights.data(),
                             s.lightsAnimated() ? GL_DYNAMIC_STORAGE_BIT : 0);
  emitters_ = gl::createBuffer(static_cast<GLsizeiptr>(emitters.size() * sizeof(gpu::GpuEmitter)),
                               emitters.empty() ? nullptr : emitters.data(),
                               s.meshesAnimated() ? GL_DYNAMIC_STORAGE_BIT : 0);
  emitterData_ = emitters;
  auto cdf = emitterPowerCdf(emitters);
  if (cdf.empty()) cdf.push_back(0.0f);
  emitterCdf_ = gl::createBuffer(static_cast<GLsizeiptr>(cdf.size() * sizeof(float)), cdf.data(),
                                 s.meshesAnimated() ? GL_DYNAMIC_STORAGE_BIT : 0);
  lightCount_ = static_cast<int>(lights.size());
  emitterCount_ = static_cast<int>(emitters.size());
  auto tree = buildLightTree(emitters);
  if (tree.empty()) tree.emplace_back();  // a node of no power: no emitter is drawn
  lightTree_ = gl::createBuffer(static_cast<GLsizeiptr>(tree.size() * sizeof(gpu::GpuLightNode)),
                                tree.data(), s.meshesAnimated() ? GL_DYNAMIC_STORAGE_BIT : 0);
  return mats.size() * sizeof(gpu::GpuMaterial) + lights.size() * sizeof(gpu::GpuLight) +
         emitters.size() * sizeof(gpu::GpuEmitter) + tree.size() * sizeof(gpu::GpuLightNode);
}

void GpuScene::createTextures(const Scene& s) {
  for (const Texture& t : s.textures) {
    gl::Texture tex = gl::createTexture(GL_TEXTURE_2D);
    const int levels = 1 + static_cast<int>(std::floor(std::log2(std::max(t.width, t.height))));
    // Colour textures decode from sRGB as they are sampled; data textures are linear.
    glTextureStorage2D(tex.id(), levels, t.srgb ? GL_SRGB8_ALPHA8 : GL_RGBA8, t.width, t.height);
    glTextureSubImage2D(tex.id(), 0, 0, 0, t.width, t.height, GL_RGBA, GL_UNSIGNED_BYTE,
                        t.rgba8.data());
    // The whole mip chain, whatever the sampler: a minification filter without
    // mipmaps reads level 0 only.
    glGenerateTextureMipmap(tex.id());
    for (int l = 0; l < levels; ++l)
      textureBytes_ += static_cast<size_t>(std::max(t.width >> l, 1)) *
                       static_cast<size_t>(std::max(t.height >> l, 1)) * 4;
    textures_.push_back(std::move(tex));
    // The file's sampler (glTF's values are the GL enums).
    gl::Sampler sampler = gl::createSampler();
    glSamplerParameteri(sampler.id(), GL_TEXTURE_MIN_FILTER, t.minFilter);
    glSamplerParameteri(sampler.id(), GL_TEXTURE_MAG_FILTER, t.magFilter);
    glSamplerParameteri(sampler.id(), GL_TEXTURE_WRAP_S, t.wrapS);
    glSamplerParameteri(sampler.id(), GL_TEXTURE_WRAP_T, t.wrapT);
    samplers_.push_back(std::move(sampler));
  }
}

void GpuScene::setDefaultColor() const {
  if (!scene_.hasVertexColors()) glVertexAttrib4f(gpu::kColorAttribute, 1.0f, 1.0f, 1.0f, 1.0f);
}

void GpuScene::bindMaterialTextures(const Material& m) const {
  std::vector<std::pair<GLuint, int>> slots = {
      {gpu::kBaseColorUnit, m.baseColorTexture},
      {gpu::kEmissiveUnit, m.emissiveTexture},
      {gpu::kMetallicRoughnessUnit, m.metallicRoughnessTexture}};
  if (scene_.hasNormalMaps()) slots.emplace_back(gpu::kNormalUnit, m.normalTexture);
  if (hasOcclusion_) slots.emplace_back(gpu::kOcclusionUnit, m.occlusionTexture);
  for (const auto& [unit, index] : slots) {
    glBindTextureUnit(unit, texture(index));
    glBindSampler(unit, sampler(index));
  }
}

void GpuScene::bindSampler() const {
  for (GLuint unit : {gpu::kBaseColorUnit, gpu::kEmissiveUnit, gpu::kMetallicRoughnessUnit})
    glBindSampler(unit, sampler_.id());
  if (scene_.hasNormalMaps()) glBindSampler(gpu::kNormalUnit, sampler_.id());
  if (hasOcclusion_) glBindSampler(gpu::kOcclusionUnit, sampler_.id());
}

void GpuScene::unbindMaterialTextures() {
  for (GLuint unit : {gpu::kBaseColorUnit, gpu::kEmissiveUnit, gpu::kMetallicRoughnessUnit,
                      gpu::kNormalUnit, gpu::kOcclusionUnit}) {
    glBindTextureUnit(unit, 0);
    glBindSampler(unit, 0);
  }
}

void GpuScene::updateLights() {
  if (!scene_.lightsAnimated()) return;
  const auto lights = packLights(scene_);
  glNamedBufferSubData(lights_.id(), 0,
                       static_cast<GLsizeiptr>(lights.size() * sizeof(gpu::GpuLight)),
                       lights.data());
}

void GpuScene::updateGeometry() {
  if (!scene_.meshesAnimated()) return;
  uint32_t lo = UINT32_MAX, hi = 0;
  for (const AnimatedRange& r : scene_.animatedRanges) {
    lo = std::min(lo, r.firstVertex);
    hi = std::max(hi, r.firstVertex + static_cast<uint32_t>(r.localPositions.size()));
  }
  // What was drawn last becomes the previous pose.
  glCopyNamedBufferSubData(vertices_.id(), previousVertices_.id(),
                           static_cast<GLintptr>(lo) * sizeof(Vertex),
                           static_cast<GLintptr>(lo) * sizeof(Vertex),
                           static_cast<GLsizeiptr>(hi - lo) * sizeof(Vertex));
  glNamedBufferSubData(vertices_.id(), static_cast<GLintptr>(lo) * sizeof(Vertex),
                       static_cast<GLsizeiptr>(hi - lo) * sizeof(Vertex),
                       scene_.vertices.data() + lo);
  if (scene_.hasNormalMaps())
    glNamedBufferSubData(tangents_.id(), static_cast<GLintptr>(lo) * sizeof(glm::vec4),
                         static_cast<GLsizeiptr>(hi - lo) * sizeof(glm::vec4),
                         scene_.tangents.data() + lo);
  // Moving emissive surfaces move their light.
  const auto emitters = packEmitters(buildEmitters(scene_));
  if (static_cast<int>(emitters.size()) == emitterCount_ && !emitters.empty()) {
    glNamedBufferSubData(emitters_.id(), 0,
                         static_cast<GLsizeiptr>(emitters.size() * sizeof(gpu::GpuEmitter)),
                         emitters.data());
    const auto cdf = emitterPowerCdf(emitters);
    glNamedBufferSubData(emitterCdf_.id(), 0, static_cast<GLsizeiptr>(cdf.size() * sizeof(float)),
                         cdf.data());
    // Rebuilt whole: the same emitters give a tree of the same size.
    const auto tree = buildLightTree(emitters);
    glNamedBufferSubData(lightTree_.id(), 0,
                         static_cast<GLsizeiptr>(tree.size() * sizeof(gpu::GpuLightNode)),
                         tree.data());
    emitterData_ = emitters;
  }
}

void GpuScene::settleGeometry() {
  if (!scene_.meshesAnimated()) return;
  glCopyNamedBufferSubData(vertices_.id(), previousVertices_.id(), 0, 0,
                           static_cast<GLsizeiptr>(scene_.vertices.size() * sizeof(Vertex)));
}

}  // namespace voxgi::scene
