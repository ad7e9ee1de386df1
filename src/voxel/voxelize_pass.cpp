#include "voxel/voxelize_pass.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "core/log.h"
#include "scene_shared.h"

namespace voxgi::voxel {
namespace {

constexpr uint64_t kBytesPerSlot = 3 * 16;                  // sums
constexpr uint64_t kBytesPerBrick = gpu::kBrickVoxels * 4;  // pool entries
constexpr uint64_t kBytesPerListEntry = 4 + 16;             // coordinates, attributes
// Deferred records in one SSBO (llvmpipe's limit is 128 MiB).
constexpr uint32_t kMaxDeferred = (128u << 20) / sizeof(gpu::VoxelDeferred);

uint64_t bricksPerAxis(int resolution) {
  return (static_cast<uint64_t>(resolution) + gpu::kBrickSize - 1) / gpu::kBrickSize;
}

uint32_t initialBrickCapacity(int resolution) {
  const uint64_t b = bricksPerAxis(resolution);
  return static_cast<uint32_t>(std::min<uint64_t>(b * b * b, uint64_t{1} << 16));
}

// Groups of kResolveGroupSize for `invocations`.
uint64_t groupsFor(uint64_t invocations) {
  return (invocations + gpu::kResolveGroupSize - 1) / gpu::kResolveGroupSize;
}

// Groups for `count` invocations, 2D past kMaxGroupsX.
void dispatchFor(uint64_t count) {
  const uint64_t groups = groupsFor(count);
  const uint64_t x = std::min<uint64_t>(groups, gpu::kMaxGroupsX);
  glDispatchCompute(static_cast<GLuint>(x), static_cast<GLuint>((groups + x - 1) / x), 1);
}

std::vector<std::string> withDefine(std::vector<std::string> defines, const char* extra) {
  if (*extra) defines.emplace_back(extra);
  return defines;
}

// The voxelizing programs' defines: the effect-plan variant, the tests' wait.
std::vector<std::string> claimDefines(std::vector<std::string> defines,
                                      const VoxelizePass::Settings& settings) {
  if (settings.claimSpins >= 0)
    defines.push_back("VOXGI_CLAIM_SPINS=" + std::to_string(settings.claimSpins) + "u");
  if (settings.deferAll) defines.emplace_back("VOXGI_DEFER_ALL");
  return defines;
}

std::vector<std::string> resolveDefines(const VoxelizePass::Settings& settings) {
  std::vector<std::string> defines;
  if (settings.inspectSums) defines.emplace_back("VOXGI_KEEP_SUMS");
  if (!settings.checksum) defines.emplace_back("VOXGI_NO_CHECKSUM");
  return defines;
}

bool hasGlExtension(const char* name) {
  GLint n = 0;
  glGetIntegerv(GL_NUM_EXTENSIONS, &n);
  for (GLint i = 0; i < n; ++i) {
    const auto* e =
        reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i)));
    if (e && std::strcmp(e, name) == 0) return true;
  }
  return false;
}

// Emission is stored in fixed point relative to the scene's brightest emitter:
// the scale that maps it to 1.
float emissionScaleOf(const scene::Scene& s) {
  float maxEmission = 0.0f;
  for (const scene::Material& m : s.materials)
    maxEmission = std::max({maxEmission, m.emission.r, m.emission.g, m.emission.b});
  return maxEmission > 0.0f ? 1.0f / maxEmission : 1.0f;
}

}  // namespace

uint32_t initialListCapacity(int resolution) {
  const uint64_t n = static_cast<uint64_t>(resolution);
  return static_cast<uint32_t>(std::min<uint64_t>(n * n * n, uint64_t{1} << 22));
}

namespace {

// Twice the vector area of the part of triangle abc inside the box [lo, hi]
// (Sutherland-Hodgman: clipped by each of the box's six planes in turn).
glm::dvec3 clippedTwiceArea(glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, glm::dvec3 lo,
                            glm::dvec3 hi) {
  std::array<glm::dvec3, 9> poly{a, b, c}, next{};
  size_t count = 3;
  for (int plane = 0; plane < 6 && count > 0; ++plane) {
    const int axis = plane / 2;
    const double bound = plane % 2 ? hi[axis] : lo[axis];
    const double sign = plane % 2 ? -1.0 : 1.0;  // inside: sign * (p - bound) >= 0
    size_t kept = 0;
    for (size_t i = 0; i < count; ++i) {
      const glm::dvec3 p = poly[i], q = poly[(i + 1) % count];
      const double dp = sign * (p[axis] - bound), dq = sign * (q[axis] - bound);
      if (dp >= 0.0) next[kept++] = p;
      if ((dp >= 0.0) != (dq >= 0.0) && kept < next.size())
        next[kept++] = p + (q - p) * (dp / (dp - dq));
    }
    poly = next;
    count = kept;
  }
  glm::dvec3 twiceArea(0.0);
  for (size_t i = 1; i + 1 < count; ++i)
    twiceArea += glm::cross(poly[i] - poly[0], poly[i + 1] - poly[0]);
  return twiceArea;
}

}  // namespace

// A plane of area A crosses about A (|n.x| + |n.y| + |n.z|) / h^2 cells of a grid of
// spacing h (the cells along each axis its projection covers), and the voxelizer
// marks every cell the plane's depth spans over a pixel of its dominant projection
// that a sample falls in: as many on axis-aligned walls (the Cornell room: 0.98x),
// about twice as many on tilted ones (a box at random orientations: 1.8-2.0x).
// Summed over the triangles' parts inside the grid (which may leave out a large
// floor's far parts: Scene::voxelBounds), it overcounts where triangles share cells
// (fine meshes, overlapping geometry); the cap is the dense grid's. 2.5 times the
// sum, plus one grid face, covers the validation set's scenes and the test scenes in
// one round.
uint32_t listEntriesFor(const scene::Scene& s, int n, float voxelSize) {
  const uint32_t cap = initialListCapacity(n);
  if (!(voxelSize > 0.0f)) return cap;
  const glm::dvec3 lo(s.scale.gridOrigin);
  const glm::dvec3 hi = lo + glm::dvec3(static_cast<double>(s.scale.gridSize));
  double cells = 0.0;
  for (const scene::Draw& d : s.draws)
    for (uint32_t i = d.firstIndex; i + 2 < d.firstIndex + d.indexCount; i += 3) {
      const glm::dvec3 a(s.vertices[s.indices[i]].position);
      const glm::dvec3 b(s.vertices[s.indices[i + 1]].position);
      const glm::dvec3 c(s.vertices[s.indices[i + 2]].position);
      const glm::dvec3 low = glm::min(a, glm::min(b, c)), high = glm::max(a, glm::max(b, c));
      const bool inside =
          glm::all(glm::greaterThanEqual(low, lo)) && glm::all(glm::lessThanEqual(high, hi));
      const glm::dvec3 twiceArea =
          inside ? glm::cross(b - a, c - a) : clippedTwiceArea(a, b, c, lo, hi);
      const double l1 = std::abs(twiceArea.x) + std::abs(twiceArea.y) + std::abs(twiceArea.z);
      if (std::isfinite(l1)) cells += 0.5 * l1;
    }
  const double h2 = static_cast<double>(voxelSize) * voxelSize;
  const double want = 2.5 * cells / h2 + static_cast<double>(n) * n;
  return static_cast<uint32_t>(std::min(want, static_cast<double>(cap)));
}

VoxelMemory voxelMemory(int resolution) {
  const uint64_t b = bricksPerAxis(resolution);
  const uint64_t list = kBytesPerListEntry * initialListCapacity(resolution);
  const uint64_t sparse = b * b * b * 4 + kBytesPerBrick * initialBrickCapacity(resolution) +
                          kBytesPerSlot * initialListCapacity(resolution) +
                          sizeof(gpu::VoxelDeferred) * uint64_t{gpu::kInitialDeferred};
  return {sparse + list, list};
}

uint64_t voxelMemoryBudget(const std::string& renderer, uint64_t overrideBytes) {
  if (overrideBytes > 0) return overrideBytes;
  if (hasGlExtension("GL_NVX_gpu_memory_info")) {
    GLint kb = 0;
    glGetIntegerv(0x9049, &kb);  // GPU_MEMORY_INFO_CURRENT_AVAILABLE_VIDMEM_NVX
    if (kb > 0) return static_cast<uint64_t>(kb) * 1024 * 9 / 10;
  }
  if (hasGlExtension("GL_ATI_meminfo")) {
    GLint info[4] = {0, 0, 0, 0};
    glGetIntegerv(0x87FC, info);  // TEXTURE_FREE_MEMORY_ATI, KB
    if (info[0] > 0) return static_cast<uint64_t>(info[0]) * 1024 * 9 / 10;
  }
  if (renderer.find("llvmpipe") != std::string::npos ||
      renderer.find("softpipe") != std::string::npos) {
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    if (pages > 0 && page > 0)
      return static_cast<uint64_t>(pages) * static_cast<uint64_t>(page) / 2;
  }
  return uint64_t{4} << 30;  // unknown driver: assume 4 GiB
}

VoxelizePass::VoxelizePass(gl::ProgramCache& programs, const std::string& renderer,
                           const Settings& settings)
    : settings_(settings),
      voxelize_(programs.get({{"voxel/voxelize.vert", "voxel/voxelize.geom", "voxel/voxelize.frag"},
                              claimDefines(settings.features.defines(), settings)})),
      voxelizeSmall_(
          programs.get({{"voxel/voxelize_small.comp"},
                        claimDefines(withDefine(settings.features.defines(),
                                                settings.inspectSums ? "VOXGI_COUNT_SMALL" : ""),
                                     settings)})),
      resolve_(programs.get({{"voxel/resolve.comp"}, resolveDefines(settings)})),
      addDeferred_(programs.get({{"voxel/voxelize_deferred.comp"}, claimDefines({}, settings)})) {
  const int n = settings.resolution;
  if (n < kMinResolution || n > kMaxResolution)
    throw Error(strf("--voxels %d: the grid resolution must be in [%d, %d]", n, kMinResolution,
                     kMaxResolution));
  const VoxelMemory need = voxelMemory(n);
  const uint64_t budget = voxelMemoryBudget(renderer, settings.memoryBudgetBytes);
  if (need.peakBytes > budget)
    throw Error(
        strf("--voxels %d: the grid needs %.2f GiB while voxelizing, more than the %.2f GiB "
             "available (set VOXGI_VOXEL_BUDGET_MB to override)",
             n, static_cast<double>(need.peakBytes) / (1 << 30),
             static_cast<double>(budget) / (1 << 30)));

  capacity_ = initialListCapacity(n);
  brickCapacity_ = settings.initialBricks > 0 ? settings.initialBricks : initialBrickCapacity(n);
  allocateLists();
  allocateDeferred();
  if (settings_.keepSums || settings_.inspectSums) allocateSums();

  fbo_ = gl::createFramebuffer();
  glNamedFramebufferParameteri(fbo_.id(), GL_FRAMEBUFFER_DEFAULT_WIDTH, n);
  glNamedFramebufferParameteri(fbo_.id(), GL_FRAMEBUFFER_DEFAULT_HEIGHT, n);
  glNamedFramebufferParameteri(fbo_.id(), GL_FRAMEBUFFER_DEFAULT_SAMPLES,
                               static_cast<GLint>(gpu::kSamplesPerFragment));
  // The compute path for small triangles covers them with the rasterizer's own
  // samples and sub-pixel grid.
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  GLint samples = 0;
  glGetIntegerv(GL_SAMPLES, &samples);
  for (uint32_t i = 0; i < gpu::kSamplesPerFragment; ++i) {
    // The standard 4x pattern where the driver reports fewer samples.
    const float standard[8] = {0.375f, 0.125f, 0.875f, 0.375f, 0.125f, 0.625f, 0.625f, 0.875f};
    float xy[2] = {standard[2 * i], standard[2 * i + 1]};
    if (i < static_cast<uint32_t>(samples)) glGetMultisamplefv(GL_SAMPLE_POSITION, i, xy);
    params_.samplePositions[i / 2][(i % 2) * 2] = xy[0];
    params_.samplePositions[i / 2][(i % 2) * 2 + 1] = xy[1];
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  GLint subpixelBits = 0;
  glGetIntegerv(GL_SUBPIXEL_BITS, &subpixelBits);
  params_.slotInfo.z = 1u << std::clamp(subpixelBits, 4, 12);
  paramsBuffer_ = gl::createBuffer(sizeof(gpu::VoxelParams), nullptr, GL_DYNAMIC_STORAGE_BIT);
  statsBuffer_ =
      gl::createBuffer(sizeof(gpu::VoxelStats), nullptr, GL_DYNAMIC_STORAGE_BIT | GL_MAP_READ_BIT);
  stats_.resolution = n;
  stats_.peakBytes = need.peakBytes;
  stats_.bytes = need.residentBytes;
}

void VoxelizePass::allocateSums() {
  if (brickMap_) return;
  const uint64_t b = bricksPerAxis(settings_.resolution);
  brickMap_ = gl::createBuffer(static_cast<GLsizeiptr>(b * b * b * 4), nullptr);
  // Cleared once (and when the epochs run out): entries of older epochs read as empty.
  clear(brickMap_);
  epoch_ = 0;
  allocateSlots();
  allocateBricks();
}

void VoxelizePass::allocateDeferred() {
  deferred_ = gl::createBuffer(
      static_cast<GLsizeiptr>(deferredCapacity_) * sizeof(gpu::VoxelDeferred), nullptr);
}

void VoxelizePass::allocateLists() {
  list_ = gl::createBuffer(static_cast<GLsizeiptr>(capacity_) * 4, nullptr);
  attributes_ = gl::createBuffer(static_cast<GLsizeiptr>(capacity_) * 16, nullptr);
}

void VoxelizePass::clear(const gl::Buffer& buffer) {
  const uint32_t zero = 0;
  glClearNamedBufferData(buffer.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
}

void VoxelizePass::allocateSlots() {
  for (gl::Buffer* b : {&sumsA_, &sumsN_, &sumsE_}) {
    *b = gl::createBuffer(static_cast<GLsizeiptr>(capacity_) * 16, nullptr);
    clear(*b);  // once: the resolve re-zeroes what it reads
  }
}

void VoxelizePass::allocateBricks() {
  pool_ =
      gl::createBuffer(static_cast<GLsizeiptr>(brickCapacity_) * gpu::kBrickVoxels * 4, nullptr);
  clear(pool_);
}

void VoxelizePass::clearSums() {
  for (gl::Buffer* b : {&sumsA_, &sumsN_, &sumsE_}) clear(*b);
}

void VoxelizePass::nextEpoch() {
  if (++epoch_ >= gpu::kEpochCount) {
    clear(brickMap_);
    clear(pool_);
    epoch_ = 1;
  }
  params_.slotInfo.x = epoch_ << gpu::kSlotBits;
  params_.slotInfo.y = static_cast<uint32_t>(bricksPerAxis(settings_.resolution));
  params_.limits = glm::uvec4(capacity_, brickCapacity_, 0u, deferredCapacity_);
  glNamedBufferSubData(paramsBuffer_.id(), 0, sizeof(params_), &params_);
}

void VoxelizePass::raster(const scene::GpuScene& gs) {
  const scene::Scene& s = gs.scene();
  const int n = settings_.resolution;
  gpu::VoxelStats fresh{};
  glNamedBufferSubData(statsBuffer_.id(), 0, sizeof(fresh), &fresh);

  // Small triangles: one compute invocation each (the geometry stage drops them).
  if (settings_.smallTrianglesInCompute) rasterSmall(gs);

  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glViewport(0, 0, n, n);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glEnable(GL_MULTISAMPLE);
  glDisable(GL_SAMPLE_SHADING);
  glUseProgram(voxelize_.id());
  glBindVertexArray(gs.vertexArray());
  gs.setDefaultColor();
  glBindBufferBase(GL_UNIFORM_BUFFER, gpu::kVoxelParamsBinding, paramsBuffer_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kMaterialBinding, gs.materials());
  bindSlots();
  gs.bindSampler();
  // After the compute path: only the triangles it passed on, counted on the GPU.
  if (settings_.smallTrianglesInCompute) {
    glVertexArrayElementBuffer(gs.vertexArray(), largeIndices_.id());
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, drawCommands_.id());
  }
  for (size_t i = 0; i < s.draws.size(); ++i) {
    const scene::Draw& d = s.draws[i];
    if (d.indexCount < 3) continue;
    const scene::Material& m = s.materials[static_cast<size_t>(d.material)];
    gs.bindMaterialTextures(m);
    glUniform1i(gpu::kMaterialIndexLocation, d.material);
    if (settings_.smallTrianglesInCompute)
      glMultiDrawElementsIndirect(
          GL_TRIANGLES, GL_UNSIGNED_INT,
          reinterpret_cast<const void*>(size_t{firstCommand_[i]} * gpu::kDrawCommandWords * 4),
          static_cast<GLsizei>(groupsFor(d.indexCount / 3)), 0);
    else
      glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(d.indexCount), GL_UNSIGNED_INT,
                     reinterpret_cast<const void*>(static_cast<uintptr_t>(d.firstIndex) * 4));
  }
  scene::GpuScene::unbindMaterialTextures();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  if (settings_.smallTrianglesInCompute) {
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
    glVertexArrayElementBuffer(gs.vertexArray(), gs.indexBuffer());
  }
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT |
                  GL_BUFFER_UPDATE_BARRIER_BIT);
}

void VoxelizePass::rasterSmall(const scene::GpuScene& gs) {
  const scene::Scene& s = gs.scene();
  // Views made afresh each time: a buffer name can come back for another scene.
  const gl::Texture vertexTexture = gl::createTexture(GL_TEXTURE_BUFFER);
  const gl::Texture indexTexture = gl::createTexture(GL_TEXTURE_BUFFER);
  // scene::Vertex as 5 RG32F texels (its 40 bytes are not a whole number of RGBA32F).
  static_assert(sizeof(scene::Vertex) == 5 * sizeof(glm::vec2));
  if (!s.vertices.empty()) glTextureBuffer(vertexTexture.id(), GL_RG32F, gs.vertexBuffer());
  if (!s.indices.empty()) glTextureBuffer(indexTexture.id(), GL_R32UI, gs.indexBuffer());
  const gl::Texture colorTexture = gl::createTexture(GL_TEXTURE_BUFFER);
  if (s.hasVertexColors()) glTextureBuffer(colorTexture.id(), GL_RGBA32F, gs.colorBuffer());
  // Where the triangles it passes on go: a buffer the size of the scene's indices.
  const size_t indexBytes = std::max<size_t>(s.indices.size(), 1) * 4;
  if (!largeIndices_ || largeIndexBytes_ != indexBytes) {
    largeIndices_ = gl::createBuffer(static_cast<GLsizeiptr>(indexBytes), nullptr);
    largeIndexBytes_ = indexBytes;
  }
  // One command per group of triangles, each counting from the group's first index.
  firstCommand_.assign(s.draws.size(), 0);
  std::vector<uint32_t> commands;
  for (size_t i = 0; i < s.draws.size(); ++i) {
    firstCommand_[i] = static_cast<uint32_t>(commands.size() / gpu::kDrawCommandWords);
    for (uint32_t g = 0; g < groupsFor(s.draws[i].indexCount / 3); ++g)
      commands.insert(commands.end(),
                      {0u, 1u, s.draws[i].firstIndex + 3 * gpu::kResolveGroupSize * g, 0u, 0u});
  }
  if (commands.empty()) commands.assign(gpu::kDrawCommandWords, 0u);
  const auto commandBytes = static_cast<GLsizeiptr>(commands.size() * 4);
  if (!drawCommands_ || drawCommandBytes_ != commandBytes) {
    drawCommands_ = gl::createBuffer(commandBytes, nullptr, GL_DYNAMIC_STORAGE_BIT);
    drawCommandBytes_ = commandBytes;
  }
  glNamedBufferSubData(drawCommands_.id(), 0, commandBytes, commands.data());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kLargeIndexBinding, largeIndices_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kDrawCommandBinding, drawCommands_.id());

  glUseProgram(voxelizeSmall_.id());
  glBindBufferBase(GL_UNIFORM_BUFFER, gpu::kVoxelParamsBinding, paramsBuffer_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kMaterialBinding, gs.materials());
  bindSlots();
  glBindTextureUnit(gpu::kVoxelVertexUnit, vertexTexture.id());
  glBindTextureUnit(gpu::kVoxelIndexUnit, indexTexture.id());
  glBindTextureUnit(gpu::kVoxelColorUnit, colorTexture.id());
  if (settings_.features.colors)
    glUniform1ui(gpu::kVoxelHasColorsLocation, s.hasVertexColors() ? 1u : 0u);
  gs.bindSampler();
  for (size_t i = 0; i < s.draws.size(); ++i) {
    const scene::Draw& d = s.draws[i];
    const uint32_t triangles = d.indexCount / 3;
    if (triangles == 0) continue;
    const scene::Material& m = s.materials[static_cast<size_t>(d.material)];
    gs.bindMaterialTextures(m);
    glUniform1i(gpu::kMaterialIndexLocation, d.material);
    glUniform1ui(gpu::kVoxelFirstIndexLocation, d.firstIndex);
    glUniform1ui(gpu::kVoxelTriangleCountLocation, triangles);
    glUniform1ui(gpu::kVoxelCommandLocation, firstCommand_[i]);
    dispatchFor(triangles);
  }
  scene::GpuScene::unbindMaterialTextures();
  glBindTextureUnit(gpu::kVoxelVertexUnit, 0);
  glBindTextureUnit(gpu::kVoxelIndexUnit, 0);
  glBindTextureUnit(gpu::kVoxelColorUnit, 0);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT |
                  GL_ELEMENT_ARRAY_BARRIER_BIT);
}

void VoxelizePass::bindSlots() {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kVoxelStatsBinding, statsBuffer_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kVoxelListBinding, list_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kVoxelAttribBinding, attributes_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kBrickMapBinding, brickMap_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kBrickPoolBinding, pool_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kSlotSumsABinding, sumsA_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kSlotSumsNBinding, sumsN_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kSlotSumsEBinding, sumsE_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kVoxelDeferredBinding, deferred_.id());
}

void VoxelizePass::dispatch(const gl::Program& program, uint64_t invocations) {
  if (invocations == 0) return;
  glUseProgram(program.id());
  glBindBufferBase(GL_UNIFORM_BUFFER, gpu::kVoxelParamsBinding, paramsBuffer_.id());
  bindSlots();
  dispatchFor(invocations);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT |
                  GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT);
}

void VoxelizePass::execute(gl::FrameContext& ctx, const scene::GpuScene& gs) {
  gl::StageScope stage(ctx.timer, Stage::kVoxelize);
  const scene::Scene& s = gs.scene();
  const int n = settings_.resolution;
  gridOrigin_ = s.scale.gridOrigin;
  voxelSize_ = s.scale.gridSize / static_cast<float>(n);
  const float emissionScale = emissionScaleOf(s);
  params_.gridOrigin = glm::vec4(gridOrigin_, voxelSize_);
  params_.gridInfo = glm::vec4(static_cast<float>(n), emissionScale, 1.0f / emissionScale, 0.0f);

  if (!sized_ && !brickMap_) {
    // Sized for the scene, not the dense grid: at 128^3 the list and sums of every
    // cell take 142 MB, the validation set's scenes occupy 2-5% of them.
    const uint32_t entries = settings_.initialListEntries > 0 ? settings_.initialListEntries
                                                              : listEntriesFor(s, n, voxelSize_);
    if (entries < capacity_) {
      capacity_ = std::max<uint32_t>(entries, 1);
      allocateLists();
    }
  }
  sized_ = true;
  allocateSums();
  if (settings_.inspectSums) clearSums();
  nextEpoch();  // uploads params_

  gpu::VoxelStats out = rasterUntilItFits(gs);
  const uint64_t b = bricksPerAxis(n);
  stats_.peakBytes = b * b * b * 4 + kBytesPerBrick * brickCapacity_ +
                     (kBytesPerSlot + kBytesPerListEntry) * uint64_t{capacity_} +
                     sizeof(gpu::VoxelDeferred) * uint64_t{deferredCapacity_};
  params_.limits.z = out.listCount;  // slots to resolve
  glNamedBufferSubData(paramsBuffer_.id(), 0, sizeof(params_), &params_);
  dispatch(resolve_, out.listCount);
  glGetNamedBufferSubData(statsBuffer_.id(), 0, sizeof(out), &out);
  listed_ = out.listCount;  // the rounds above made room for every one
  recordStats(out);
  if (!settings_.keepSums && !settings_.inspectSums) keepListOnly();
  stats_.bytes = kBytesPerListEntry * uint64_t{capacity_};
}

gpu::VoxelStats VoxelizePass::readCounters() const {
  gpu::VoxelStats out{};
  glGetNamedBufferSubData(statsBuffer_.id(), 0, sizeof(out), &out);
  return out;
}

gpu::VoxelStats VoxelizePass::rasterOnce(const scene::GpuScene& gs) {
  raster(gs);
  gpu::VoxelStats out = readCounters();
  const bool fits = out.listCount <= capacity_ && out.brickCount <= brickCapacity_ &&
                    out.deferred <= deferredCapacity_;
  if (out.deferred > 0 && fits) {
    // Claim, then add: every slot is published before any record is added.
    for (GLuint add : {0u, 1u}) {
      glProgramUniform1ui(addDeferred_.id(), gpu::kVoxelDeferredAddLocation, add);
      dispatch(addDeferred_, out.deferred);
    }
    out = readCounters();
  }
  return out;
}

gpu::VoxelStats VoxelizePass::rasterUntilItFits(const scene::GpuScene& gs) {
  const int n = settings_.resolution;
  gpu::VoxelStats out = rasterOnce(gs);
  stats_.rounds = 1;
  // Out of voxel slots, pool bricks or deferred records: grow what ran out and
  // raster again in a fresh epoch, from cleared sums (bricks that did not fit took
  // no voxel slots, so this can take two rounds).
  for (int round = 0; out.listCount > capacity_ || out.brickCount > brickCapacity_ ||
                      out.deferred > deferredCapacity_ || out.deferredLost > 0;
       ++round) {
    if (round >= 4)
      throw Error(
          strf("--voxels %d: voxelization did not settle in %d rounds (%u voxels, %u "
               "bricks, %u deferred fragments, %u lost)",
               n, round + 1, out.listCount, out.brickCount, out.deferred, out.deferredLost));
    if (out.listCount > gpu::kMaxListEntries)
      throw Error(strf("--voxels %d: %u occupied voxels exceed the voxel list's limit of %u", n,
                       out.listCount, gpu::kMaxListEntries));
    if (out.brickCount > gpu::kMaxBricks)
      throw Error(strf("--voxels %d: %u occupied bricks of 4^3 voxels exceed the limit of %u", n,
                       out.brickCount, gpu::kMaxBricks));
    if (out.listCount > capacity_) {
      capacity_ = std::min<uint32_t>(gpu::kMaxListEntries, out.listCount + out.listCount / 4);
      allocateSlots();
      allocateLists();
    } else {
      clearSums();  // what the round added stays there otherwise: nothing resolved it
    }
    if (out.brickCount > brickCapacity_) {
      brickCapacity_ = std::min<uint32_t>(gpu::kMaxBricks, out.brickCount + out.brickCount / 4);
      allocateBricks();
    }
    if (out.deferred > deferredCapacity_) {
      deferredCapacity_ = std::min<uint32_t>(kMaxDeferred, out.deferred + out.deferred / 4);
      allocateDeferred();
    }
    nextEpoch();
    out = rasterOnce(gs);
    ++stats_.rounds;
  }
  stats_.deferred = out.deferred;
  return out;
}

void VoxelizePass::recordStats(const gpu::VoxelStats& out) {
  stats_.occupied = listed_;
  stats_.smallTriangles = out.smallTriangles;
  stats_.rasterTriangles = 0;
  if (settings_.inspectSums && settings_.smallTrianglesInCompute && drawCommands_) {
    std::vector<uint32_t> commands(static_cast<size_t>(drawCommandBytes_) / 4);
    glGetNamedBufferSubData(drawCommands_.id(), 0, drawCommandBytes_, commands.data());
    for (size_t i = 0; i < commands.size(); i += gpu::kDrawCommandWords)
      stats_.rasterTriangles += commands[i] / 3;
  }
  stats_.checksum = (static_cast<uint64_t>(out.checksumXor) << 32) | out.checksumSum;
  const uint64_t b = bricksPerAxis(settings_.resolution);
  stats_.peakBytes = b * b * b * 4 + kBytesPerBrick * brickCapacity_ +
                     (kBytesPerSlot + kBytesPerListEntry) * uint64_t{capacity_} +
                     (settings_.smallTrianglesInCompute ? largeIndexBytes_ : 0) +
                     sizeof(gpu::VoxelDeferred) * uint64_t{deferredCapacity_};
}

void VoxelizePass::keepListOnly() {
  // Only the list stays resident, trimmed to the voxels it holds.
  for (gl::Buffer* buffer :
       {&brickMap_, &pool_, &sumsA_, &sumsN_, &sumsE_, &largeIndices_, &drawCommands_})
    buffer->reset();
  if (listed_ < capacity_) {
    const uint32_t keep = std::max<uint32_t>(listed_, 1);
    gl::Buffer list = gl::createBuffer(static_cast<GLsizeiptr>(keep) * 4, nullptr);
    gl::Buffer attributes = gl::createBuffer(static_cast<GLsizeiptr>(keep) * 16, nullptr);
    if (listed_ > 0) {
      glCopyNamedBufferSubData(list_.id(), list.id(), 0, 0, static_cast<GLsizeiptr>(listed_) * 4);
      glCopyNamedBufferSubData(attributes_.id(), attributes.id(), 0, 0,
                               static_cast<GLsizeiptr>(listed_) * 16);
    }
    list_ = std::move(list);
    attributes_ = std::move(attributes);
    capacity_ = keep;
  }
}

template <typename T>
std::vector<T> VoxelizePass::readResolved(uint32_t component) const {
  const size_t n = static_cast<size_t>(settings_.resolution);
  std::vector<uint32_t> codes(listed_);
  std::vector<uint32_t> attributes(size_t{listed_} * 4);
  if (listed_ > 0) {
    glGetNamedBufferSubData(list_.id(), 0, static_cast<GLsizeiptr>(codes.size() * 4), codes.data());
    glGetNamedBufferSubData(attributes_.id(), 0, static_cast<GLsizeiptr>(attributes.size() * 4),
                            attributes.data());
  }
  std::vector<T> out(n * n * n * 4, T{0});
  for (size_t i = 0; i < codes.size(); ++i) {
    const uint32_t c = codes[i];
    const size_t voxel = (c & 1023u) + n * (((c >> 10) & 1023u) + n * ((c >> 20) & 1023u));
    if constexpr (sizeof(T) == 1) {  // 4 bytes of one packed word
      std::memcpy(&out[voxel * 4], &attributes[i * 4 + component], 4);
    } else {  // 4 half floats: emission rgb, 0
      std::memcpy(&out[voxel * 4], &attributes[i * 4 + 2], 8);
    }
  }
  return out;
}

std::vector<uint8_t> VoxelizePass::readAlbedo() const {
  return readResolved<uint8_t>(0);
}
std::vector<int8_t> VoxelizePass::readNormal() const {
  return readResolved<int8_t>(1);
}
std::vector<uint16_t> VoxelizePass::readEmission() const {
  return readResolved<uint16_t>(2);
}

std::vector<uint32_t> VoxelizePass::readSum(uint32_t channel) const {
  VOXGI_CHECK(settings_.inspectSums && channel < gpu::kSumChannels);
  const size_t n = static_cast<size_t>(settings_.resolution);
  // Slot i of the sums is voxel i of the list.
  std::vector<uint32_t> codes(listed_), sums(size_t{listed_} * 4);
  if (listed_ == 0) return std::vector<uint32_t>(n * n * n, 0u);
  glGetNamedBufferSubData(list_.id(), 0, static_cast<GLsizeiptr>(codes.size() * 4), codes.data());
  // albedo rgb + weight, normal xyz, emission rgb: see voxel_shared.h
  const gl::Buffer& b = channel < gpu::kSumNormal || channel == gpu::kSumWeight ? sumsA_
                        : channel < gpu::kSumEmission                           ? sumsN_
                                                                                : sumsE_;
  const uint32_t lane = channel == gpu::kSumWeight ? 3u : channel % 3u;
  glGetNamedBufferSubData(b.id(), 0, static_cast<GLsizeiptr>(sums.size() * 4), sums.data());
  std::vector<uint32_t> out(n * n * n, 0u);
  for (size_t i = 0; i < codes.size(); ++i) {
    const uint32_t c = codes[i];
    out[(c & 1023u) + n * (((c >> 10) & 1023u) + n * ((c >> 20) & 1023u))] = sums[i * 4 + lane];
  }
  return out;
}

}  // namespace voxgi::voxel
