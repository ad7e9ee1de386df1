#include "voxel/voxelize_pass.h"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "core/log.h"
#include "scene_shared.h"

namespace voxgi::voxel {
namespace {

constexpr uint64_t kSumBytesPerVoxel = gpu::kSumChannels * 4;
constexpr uint64_t kResolvedBytesPerVoxel = 4 + 4 + 8;

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

}  // namespace

uint32_t initialListCapacity(int resolution) {
  const uint64_t n = static_cast<uint64_t>(resolution);
  return static_cast<uint32_t>(std::min<uint64_t>(n * n * n, uint64_t{1} << 22));
}

VoxelMemory voxelMemory(int resolution) {
  const uint64_t n = static_cast<uint64_t>(resolution);
  const uint64_t voxels = n * n * n;
  const uint64_t list = uint64_t{4} * initialListCapacity(resolution);
  return {voxels * (kSumBytesPerVoxel + kResolvedBytesPerVoxel) + list,
          voxels * kResolvedBytesPerVoxel + list};
}

uint64_t voxelMemoryBudget(const std::string& renderer) {
  if (const char* env = std::getenv("VOXGI_VOXEL_BUDGET_MB")) {
    const long long mb = std::atoll(env);
    if (mb > 0) return static_cast<uint64_t>(mb) << 20;
  }
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
                              settings.features.defines()})),
      resolve_(programs.get({{"voxel/resolve.comp"},
                             settings.inspectSums ? std::vector<std::string>{"VOXGI_KEEP_SUMS"}
                                                  : std::vector<std::string>{}})),
      unresolve_(programs.get({{"voxel/unresolve.comp"}, {}})) {
  const int n = settings.resolution;
  if (n < kMinResolution || n > kMaxResolution)
    throw Error(strf("--voxels %d: the grid resolution must be in [%d, %d]", n, kMinResolution,
                     kMaxResolution));
  GLint max3d = 0;
  glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3d);
  if (n > max3d)
    throw Error(strf("--voxels %d: larger than this GL's 3D texture limit %d", n, max3d));
  const VoxelMemory need = voxelMemory(n);
  const uint64_t budget = voxelMemoryBudget(renderer);
  if (need.peakBytes > budget)
    throw Error(
        strf("--voxels %d: the grid needs %.2f GiB while voxelizing, more than the %.2f GiB "
             "available (set VOXGI_VOXEL_BUDGET_MB to override)",
             n, static_cast<double>(need.peakBytes) / (1 << 30),
             static_cast<double>(budget) / (1 << 30)));

  auto make3d = [n](GLenum format) {
    gl::Texture t = gl::createTexture(GL_TEXTURE_3D);
    glTextureStorage3D(t.id(), 1, format, n, n, n);
    glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTextureParameteri(t.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
    glTextureParameteri(t.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
    glTextureParameteri(t.id(), GL_TEXTURE_WRAP_R, GL_CLAMP_TO_BORDER);
    return t;
  };
  albedo_ = make3d(GL_RGBA8);
  normal_ = make3d(GL_RGBA8_SNORM);
  emission_ = make3d(GL_RGBA16F);
  // Cleared once; afterwards only listed voxels are ever written or zeroed.
  const uint32_t zero[4] = {0, 0, 0, 0};
  glClearTexImage(albedo_.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, zero);
  glClearTexImage(normal_.id(), 0, GL_RGBA, GL_BYTE, zero);
  glClearTexImage(emission_.id(), 0, GL_RGBA, GL_HALF_FLOAT, zero);
  allocateList(initialListCapacity(n));
  if (settings_.keepSums || settings_.inspectSums) allocateSums();

  fbo_ = gl::createFramebuffer();
  glNamedFramebufferParameteri(fbo_.id(), GL_FRAMEBUFFER_DEFAULT_WIDTH, n);
  glNamedFramebufferParameteri(fbo_.id(), GL_FRAMEBUFFER_DEFAULT_HEIGHT, n);
  glNamedFramebufferParameteri(fbo_.id(), GL_FRAMEBUFFER_DEFAULT_SAMPLES,
                               static_cast<GLint>(gpu::kSamplesPerFragment));
  params_ = gl::createBuffer(sizeof(gpu::VoxelParams), nullptr, GL_DYNAMIC_STORAGE_BIT);
  statsBuffer_ =
      gl::createBuffer(sizeof(gpu::VoxelStats), nullptr, GL_DYNAMIC_STORAGE_BIT | GL_MAP_READ_BIT);
  stats_.resolution = n;
  stats_.peakBytes = need.peakBytes;
  stats_.bytes = need.residentBytes;
}

void VoxelizePass::allocateSums() {
  if (!sums_.empty()) return;
  const int n = settings_.resolution;
  const uint32_t zero = 0;
  for (uint32_t c = 0; c < gpu::kSumChannels; ++c) {
    gl::Texture t = gl::createTexture(GL_TEXTURE_3D);
    glTextureStorage3D(t.id(), 1, GL_R32UI, n, n, n);
    glClearTexImage(t.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);  // once: resolve re-zeroes
    sums_.push_back(std::move(t));
  }
}

void VoxelizePass::allocateList(uint32_t capacity) {
  capacity_ = capacity;
  list_ = gl::createBuffer(static_cast<GLsizeiptr>(capacity) * 4, nullptr);
}

void VoxelizePass::raster(const scene::GpuScene& gs) {
  const scene::Scene& s = gs.scene();
  const int n = settings_.resolution;
  gpu::VoxelStats fresh{};
  fresh.capacity = capacity_;
  glNamedBufferSubData(statsBuffer_.id(), 0, sizeof(fresh), &fresh);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glViewport(0, 0, n, n);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glEnable(GL_MULTISAMPLE);
  glDisable(GL_SAMPLE_SHADING);
  glUseProgram(voxelize_.id());
  glBindVertexArray(gs.vertexArray());
  glBindBufferBase(GL_UNIFORM_BUFFER, gpu::kVoxelParamsBinding, params_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kMaterialBinding, gs.materials());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kVoxelStatsBinding, statsBuffer_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kVoxelListBinding, list_.id());
  glBindSampler(gpu::kBaseColorUnit, gs.sampler());
  for (uint32_t c = 0; c < gpu::kSumChannels; ++c)
    glBindImageTexture(gpu::kSumUnit0 + c, sums_[c].id(), 0, GL_TRUE, 0, GL_READ_WRITE, GL_R32UI);
  for (const scene::Draw& d : s.draws) {
    const scene::Material& m = s.materials[static_cast<size_t>(d.material)];
    glBindTextureUnit(gpu::kBaseColorUnit, gs.texture(m.baseColorTexture));
    glUniform1i(gpu::kMaterialIndexLocation, d.material);
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(d.indexCount), GL_UNSIGNED_INT,
                   reinterpret_cast<const void*>(static_cast<uintptr_t>(d.firstIndex) * 4));
  }
  glBindTextureUnit(gpu::kBaseColorUnit, 0);
  glBindSampler(gpu::kBaseColorUnit, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT |
                  GL_BUFFER_UPDATE_BARRIER_BIT);
}

void VoxelizePass::dispatchOverList(const gl::Program& program, uint32_t count) {
  if (count == 0) return;
  glUseProgram(program.id());
  glBindBufferBase(GL_UNIFORM_BUFFER, gpu::kVoxelParamsBinding, params_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kVoxelStatsBinding, statsBuffer_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kVoxelListBinding, list_.id());
  for (uint32_t c = 0; c < gpu::kSumChannels && !sums_.empty(); ++c)
    glBindImageTexture(gpu::kSumUnit0 + c, sums_[c].id(), 0, GL_TRUE, 0, GL_READ_WRITE, GL_R32UI);
  glBindImageTexture(gpu::kResolvedUnit0 + 0, albedo_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA8);
  glBindImageTexture(gpu::kResolvedUnit0 + 1, normal_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY,
                     GL_RGBA8_SNORM);
  glBindImageTexture(gpu::kResolvedUnit0 + 2, emission_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY,
                     GL_RGBA16F);
  glDispatchCompute((count + gpu::kResolveGroupSize - 1) / gpu::kResolveGroupSize, 1, 1);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                  GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
}

void VoxelizePass::execute(gl::FrameContext& ctx, const scene::GpuScene& gs) {
  gl::StageScope stage(ctx.timer, "voxelize");
  const scene::Scene& s = gs.scene();
  const int n = settings_.resolution;
  gridOrigin_ = s.scale.gridOrigin;
  voxelSize_ = s.scale.gridSize / static_cast<float>(n);

  // Emission in fixed point relative to the scene's brightest emitter.
  float maxEmission = 0.0f;
  for (const scene::Material& m : s.materials)
    maxEmission = std::max({maxEmission, m.emission.r, m.emission.g, m.emission.b});
  const float emissionScale = maxEmission > 0.0f ? 1.0f / maxEmission : 1.0f;
  gpu::VoxelParams params{};
  params.gridOrigin = glm::vec4(gridOrigin_, voxelSize_);
  params.gridInfo = glm::vec4(static_cast<float>(n), emissionScale, 1.0f / emissionScale, 0.0f);
  glNamedBufferSubData(params_.id(), 0, sizeof(params), &params);

  allocateSums();
  if (settings_.inspectSums) {
    const uint32_t zero = 0;
    for (const gl::Texture& t : sums_)
      glClearTexImage(t.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  }

  // What the previous voxelization listed is zeroed first (its list is about to
  // be overwritten).
  dispatchOverList(unresolve_, listed_);

  raster(gs);
  gpu::VoxelStats out{};
  glGetNamedBufferSubData(statsBuffer_.id(), 0, sizeof(out), &out);
  if (out.listCount > capacity_) {
    // The list overflowed: grow it, clear the sums fully once and raster again.
    if (out.listCount > gpu::kMaxListEntries)
      throw Error(strf("--voxels %d: %u occupied voxels exceed the voxel list's limit of %u", n,
                       out.listCount, gpu::kMaxListEntries));
    allocateList(std::min<uint32_t>(gpu::kMaxListEntries, out.listCount + out.listCount / 4));
    const uint32_t zero = 0;
    for (const gl::Texture& t : sums_)
      glClearTexImage(t.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    raster(gs);
    glGetNamedBufferSubData(statsBuffer_.id(), 0, sizeof(out), &out);
    VOXGI_CHECK_LE(out.listCount, capacity_);
  }
  listed_ = out.listCount;
  dispatchOverList(resolve_, listed_);
  for (uint32_t u = 0; u < gpu::kSumChannels + 3; ++u)
    glBindImageTexture(u, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32UI);
  glGetNamedBufferSubData(statsBuffer_.id(), 0, sizeof(out), &out);
  stats_.occupied = listed_;
  stats_.checksum = (static_cast<uint64_t>(out.checksumXor) << 32) | out.checksumSum;
  stats_.bytes =
      voxelMemory(n).residentBytes - uint64_t{4} * initialListCapacity(n) + uint64_t{4} * capacity_;
  if (!settings_.keepSums && !settings_.inspectSums)
    sums_.clear();  // only the resolved grid stays resident
}

std::vector<uint8_t> VoxelizePass::readAlbedo() const {
  const size_t n = static_cast<size_t>(settings_.resolution);
  std::vector<uint8_t> out(n * n * n * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(albedo_.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(out.size()),
                    out.data());
  return out;
}

std::vector<int8_t> VoxelizePass::readNormal() const {
  const size_t n = static_cast<size_t>(settings_.resolution);
  std::vector<int8_t> out(n * n * n * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(normal_.id(), 0, GL_RGBA, GL_BYTE, static_cast<GLsizei>(out.size()),
                    out.data());
  return out;
}

std::vector<uint16_t> VoxelizePass::readEmission() const {
  const size_t n = static_cast<size_t>(settings_.resolution);
  std::vector<uint16_t> out(n * n * n * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(emission_.id(), 0, GL_RGBA, GL_HALF_FLOAT, static_cast<GLsizei>(out.size() * 2),
                    out.data());
  return out;
}

std::vector<uint32_t> VoxelizePass::readSum(uint32_t channel) const {
  VOXGI_CHECK(settings_.inspectSums && channel < sums_.size());
  const size_t n = static_cast<size_t>(settings_.resolution);
  std::vector<uint32_t> out(n * n * n);
  glGetTextureImage(sums_[channel].id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT,
                    static_cast<GLsizei>(out.size() * 4), out.data());
  return out;
}

}  // namespace voxgi::voxel
