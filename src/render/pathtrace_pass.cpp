#include "render/pathtrace_pass.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>

#include "core/log.h"
#include "pathtrace_shared.h"

namespace voxgi::render {

PathtracePass::PathtracePass(gl::ProgramCache& programs, const GpuScene& gs,
                             const Settings& settings)
    : settings_(settings),
      scene_(gs),
      textured_(ptReadsTextures(gs.scene(), settings.textures)),
      program_(programs.get({{"render/pathtrace.comp"},
                             textured_ ? std::vector<std::string>{}
                                       : std::vector<std::string>{"VOXGI_NO_TEXTURES"}})),
      camera_(gs.scene().camera) {
  const scene::Scene& s = gs.scene();
  const auto start = std::chrono::steady_clock::now();
  const PtScene pt = buildPtScene(s);
  Bvh::Options options;
  options.maxLeafSize = static_cast<int>(gpu::kPtMaxLeafSize);  // what the kernel tests
  bvh_ = Bvh(pt.triangles, options);
  for (const gpu::GpuBvhNode& n : bvh_.nodes()) {
    VOXGI_CHECK_LE(std::bit_cast<uint32_t>(n.leftMax.w), gpu::kPtMaxLeafSize);
    VOXGI_CHECK_LE(std::bit_cast<uint32_t>(n.rightMax.w), gpu::kPtMaxLeafSize);
  }
  bvhMs_ =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

  // Per-triangle shading data in BVH order: vertex normals, material, emitter pdf.
  const std::vector<uint32_t>& order = bvh_.order();
  std::vector<gpu::GpuPtShading> shade(order.size());
  for (size_t slot = 0; slot < order.size(); ++slot) {
    const uint32_t t = order[slot];
    const uint32_t i = pt.firstIndex[t];
    gpu::GpuPtShading& g = shade[slot];
    g.n0 = glm::vec4(s.vertices[s.indices[i]].normal,
                     std::bit_cast<float>(static_cast<uint32_t>(pt.material[t])));
    g.n1 = glm::vec4(s.vertices[s.indices[i + 1]].normal, pt.emitterAreaPdf[t]);
    g.n2 = glm::vec4(s.vertices[s.indices[i + 2]].normal, 0.0f);
  }
  const std::vector<gpu::GpuPtEmissive>& emitters = pt.emitters;
  emissiveCount_ = static_cast<int>(emitters.size());

  const auto triangles = bvh_.gpuTriangles();
  const auto& nodes = bvh_.nodes();
  auto upload = [](const void* data, size_t bytes) {
    return gl::createBuffer(static_cast<GLsizeiptr>(bytes), bytes ? data : nullptr);
  };
  GLint maxTexels = 0;
  glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
  auto texels = [&](const gl::Buffer& buffer, size_t bytes) {
    if (bytes / 16 > static_cast<size_t>(maxTexels))
      throw Error(
          strf("pathtrace: %zu triangles need a BVH of %zu texels, more than this GL's "
               "buffer texture limit of %d",
               bvh_.triangleCount(), bytes / 16, maxTexels));
    gl::Texture t = gl::createTexture(GL_TEXTURE_BUFFER);
    if (bytes) glTextureBuffer(t.id(), GL_RGBA32UI, buffer.id());
    return t;
  };
  nodes_ = upload(nodes.data(), nodes.size() * sizeof(gpu::GpuBvhNode));
  triangles_ = upload(triangles.data(), triangles.size() * sizeof(gpu::GpuPtTriangle));
  nodeTexels_ = texels(nodes_, nodes.size() * sizeof(gpu::GpuBvhNode));
  triangleTexels_ = texels(triangles_, triangles.size() * sizeof(gpu::GpuPtTriangle));
  shading_ = upload(shade.data(), shade.size() * sizeof(gpu::GpuPtShading));
  if (textured_) {
    // Corner UVs in BVH order, then every texture's texels in one buffer and where
    // each starts.
    std::vector<glm::vec4> uvs(2 * order.size());
    for (size_t slot = 0; slot < order.size(); ++slot) {
      const uint32_t i = pt.firstIndex[order[slot]];
      const glm::vec2 a = s.vertices[s.indices[i]].uv, b = s.vertices[s.indices[i + 1]].uv,
                      c = s.vertices[s.indices[i + 2]].uv;
      uvs[2 * slot] = glm::vec4(a, b);
      uvs[2 * slot + 1] = glm::vec4(c, 0.0f, 0.0f);
    }
    std::vector<glm::uvec4> table;
    std::vector<uint32_t> pixels;
    buildPtTextures(s, &table, &pixels);
    if (pixels.size() > static_cast<size_t>(maxTexels))
      throw Error(
          strf("pathtrace: the scene's textures hold %zu texels, more than this GL's "
               "buffer texture limit of %d",
               pixels.size(), maxTexels));
    uvs_ = upload(uvs.data(), uvs.size() * sizeof(glm::vec4));
    uvTexels_ = texels(uvs_, uvs.size() * sizeof(glm::vec4));
    texels_ = upload(pixels.data(), pixels.size() * 4);
    textureTexels_ = gl::createTexture(GL_TEXTURE_BUFFER);
    glTextureBuffer(textureTexels_.id(), GL_R32UI, texels_.id());
    textureTable_ = upload(table.data(), table.size() * sizeof(glm::uvec4));
  }
  emissive_ = upload(emitters.data(), emitters.size() * sizeof(gpu::GpuPtEmissive));
  params_ = gl::createBuffer(sizeof(gpu::GpuPtParams), nullptr, GL_DYNAMIC_STORAGE_BIT);
  const uint32_t zero = 0;
  counter_ = gl::createBuffer(sizeof(uint32_t), &zero, GL_DYNAMIC_STORAGE_BIT);
  epsilon_ = pt.epsilon;
  logDebug(strf(
      "pathtrace: BVH of %zu triangles, %zu nodes, depth %d, SAH %.1f, %.1f ms; %d "
      "emissive triangles",
      bvh_.triangleCount(), nodes.size(), bvh_.depth(), bvh_.sahCost(), bvhMs_, emissiveCount_));
}

void PathtracePass::allocate(int width, int height) {
  if (width == width_ && height == height_) return;
  width_ = width;
  height_ = height;
  for (gl::Texture* t : {&sum_, &compensation_}) {
    *t = gl::createTexture(GL_TEXTURE_2D);
    glTextureStorage2D(t->id(), 1, GL_RGBA32F, width, height);
  }
  reset();
}

void PathtracePass::reset() {
  samples_ = 0;
  const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  for (gl::Texture* t : {&sum_, &compensation_})
    if (*t) glClearTexImage(t->id(), 0, GL_RGBA, GL_FLOAT, zero);
  const uint32_t none = 0;
  glNamedBufferSubData(counter_.id(), 0, sizeof(none), &none);
}

uint64_t PathtracePass::truncatedPaths() const {
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  uint32_t n = 0;
  glGetNamedBufferSubData(counter_.id(), 0, sizeof(n), &n);
  return n;
}

void PathtracePass::dispatch(FrameContext& ctx, GLuint hdrTexture, int x0, int y0, int w, int h,
                             int firstSample, int samples) {
  const scene::Camera& cam = camera_;
  const float aspect = static_cast<float>(ctx.width) / static_cast<float>(ctx.height);
  const float tanHalf = std::tan(0.5f * cam.yfov);
  const glm::vec3 forward = glm::normalize(cam.forward);
  const glm::vec3 right = glm::normalize(glm::cross(forward, cam.up));
  const glm::vec3 up = glm::cross(right, forward);
  gpu::GpuPtParams p{};
  p.cameraPosition = glm::vec4(cam.position, epsilon_);
  p.cameraRight = glm::vec4(right * (tanHalf * aspect), 0.0f);
  p.cameraUp = glm::vec4(up * tanHalf, 0.0f);
  p.cameraForward = glm::vec4(forward, 0.0f);
  p.image = glm::uvec4(ctx.width, ctx.height, firstSample, samples);
  p.tile = glm::uvec4(x0, y0, settings_.seed, settings_.nextEventEstimation ? emissiveCount_ : 0);
  p.depth = glm::uvec4(settings_.maxDepth, settings_.rrDepth, scene_.lightCount(), 0);
  glNamedBufferSubData(params_.id(), 0, sizeof(p), &p);

  glUseProgram(program_.id());
  glBindBufferBase(GL_UNIFORM_BUFFER, gpu::kPtParamsBinding, params_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kMaterialBinding, scene_.materials());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kLightBinding, scene_.lights());
  glBindTextureUnit(gpu::kPtNodeTexUnit, nodeTexels_.id());
  glBindTextureUnit(gpu::kPtTriangleTexUnit, triangleTexels_.id());
  if (textured_) {
    glBindTextureUnit(gpu::kPtUvTexUnit, uvTexels_.id());
    glBindTextureUnit(gpu::kPtTexelTexUnit, textureTexels_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kPtTextureBinding, textureTable_.id());
  }
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kPtShadingBinding, shading_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kPtEmissiveBinding, emissive_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kPtCounterBinding, counter_.id());
  glBindImageTexture(gpu::kPtSumImage, sum_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
  glBindImageTexture(gpu::kPtCompensationImage, compensation_.id(), 0, GL_FALSE, 0, GL_READ_WRITE,
                     GL_RGBA32F);
  glBindImageTexture(gpu::kPtOutputImage, hdrTexture, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  const auto groups = [](int n, uint32_t g) {
    return static_cast<GLuint>((static_cast<uint32_t>(n) + g - 1) / g);
  };
  glDispatchCompute(groups(w, gpu::kPtGroupX), groups(h, gpu::kPtGroupY), 1);
  for (GLuint unit :
       {gpu::kPtNodeTexUnit, gpu::kPtTriangleTexUnit, gpu::kPtUvTexUnit, gpu::kPtTexelTexUnit})
    glBindTextureUnit(unit, 0);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                  GL_TEXTURE_UPDATE_BARRIER_BIT);
}

void PathtracePass::warmUp(FrameContext& ctx, GLuint hdrTexture) {
  allocate(ctx.width, ctx.height);
  dispatch(ctx, hdrTexture, 0, 0, std::min<int>(ctx.width, gpu::kPtGroupX),
           std::min<int>(ctx.height, gpu::kPtGroupY), 0, 1);
  glFinish();
  reset();
}

void PathtracePass::execute(FrameContext& ctx, int spp, GLuint hdrTexture,
                            const Progress& progress) {
  gl::StageScope stage(ctx.timer, "pathtrace");
  allocate(ctx.width, ctx.height);
  const int64_t pixels = static_cast<int64_t>(ctx.width) * ctx.height;
  const int64_t budget = std::max<int64_t>(settings_.pixelsPerDispatch, 1);
  // One sample per pixel per pass; large images in bands of whole rows (multiples
  // of the group height).
  int rowsPerTile = ctx.height;
  constexpr int perPass = 1;
  if (pixels > budget) {
    const auto g = static_cast<int>(gpu::kPtGroupY);
    rowsPerTile = std::max<int>(g, static_cast<int>(budget / ctx.width) / g * g);
  }
  const int target = samples_ + spp;
  while (samples_ < target) {
    const int n = std::min(perPass, target - samples_);
    for (int y = 0; y < ctx.height; y += rowsPerTile)
      dispatch(ctx, hdrTexture, 0, y, ctx.width, std::min(rowsPerTile, ctx.height - y), samples_,
               n);
    samples_ += n;
    if (progress) {
      glFinish();
      progress(samples_ - (target - spp), spp);
    }
  }
  glUseProgram(0);
}

}  // namespace voxgi::render
