#include "voxel/octree.h"

#include <algorithm>
#include <cstddef>

#include "core/log.h"
#include "scene_shared.h"
#include "voxel_shared.h"

namespace voxgi::voxel {
namespace {

// std430 limits one SSBO to 128 MiB on llvmpipe: the node buffer's ceiling.
constexpr uint32_t kMaxNodes = (128u << 20) / 4u;
constexpr uint64_t kDataBytesPerNode = 4 + 8 + 4;  // radiance, material, emission
constexpr GLbitfield kBarrier = GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT |
                                GL_UNIFORM_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT;

int depthFor(int resolution) {
  int d = 0;
  while ((1 << d) < resolution) ++d;
  return d;
}

// Nodes the build can allocate at most: a tile of 8 per listed voxel per level,
// and never more than the levels hold.
uint64_t worstCaseNodes(uint32_t listed, int depth) {
  uint64_t total = 1, levelNodes = 1;
  for (int l = 0; l < depth; ++l) {
    total += 8 * std::min<uint64_t>(listed, levelNodes);
    levelNodes *= 8;
  }
  return total;
}

void clearBuffer(GLuint buffer, GLsizeiptr bytes) {
  const uint32_t zero = 0;
  glClearNamedBufferSubData(buffer, GL_R32UI, 0, bytes, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
}

}  // namespace

Octree::Octree(gl::ProgramCache& programs, const Settings& settings)
    : settings_(settings),
      programs_(programs),
      buildLevel_(programs.get({{"voxel/octree_build.comp"}, {}})),
      fill_(programs.get({{"voxel/octree_fill.comp"}, {}})),
      filter_(programs.get({{"voxel/octree_filter.comp"}, {}})),
      inject_(programs.get({{"voxel/octree_inject.comp"}, settings.features.defines()})),
      bounce_(programs.get({{"voxel/octree_bounce.comp"}, {}})) {
  if (settings.bounces < 0 || settings.bounces > 16)
    throw Error(strf("--bounces %d: must be in [0, 16]", settings.bounces));
  params_ = gl::createBuffer(sizeof(gpu::OctreeParams), nullptr, GL_DYNAMIC_STORAGE_BIT);
  counters_ = gl::createBuffer(sizeof(gpu::OctreeCounters), nullptr, GL_DYNAMIC_STORAGE_BIT);
}

void Octree::setPass(uint32_t level, uint32_t first, uint32_t count, uint32_t bounce) {
  paramsData_.pass = glm::uvec4(level, first, count, settings_.seed);
  paramsData_.light.w = bounce;
  glNamedBufferSubData(params_.id(), 0, sizeof(paramsData_), &paramsData_);
}

void Octree::dispatch(const gl::Program& p, uint32_t count) {
  if (count == 0) return;
  glUseProgram(p.id());
  const uint32_t groups = (count + gpu::kOctreeGroupSize - 1) / gpu::kOctreeGroupSize;
  const uint32_t x = std::min<uint32_t>(groups, 65535u);
  const uint32_t y = (groups + x - 1) / x;
  glDispatchCompute(x, y, 1);
  glMemoryBarrier(kBarrier);
}

void Octree::bind() const {
  glBindBufferBase(GL_UNIFORM_BUFFER, gpu::kOctreeParamsBinding, params_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeNodeBinding, nodes_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeRadianceBinding, radiance_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeMaterialBinding, material_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeEmissionBinding, emission_.id());
  glBindTextureUnit(gpu::kOctreeNodeTexUnit, nodeTexture_.id());
}

void Octree::allocate(uint32_t capacity) {
  capacity_ = capacity;
  const auto n = static_cast<GLsizeiptr>(capacity);
  nodes_ = gl::createBuffer(n * 4, nullptr, GL_DYNAMIC_STORAGE_BIT);
  nodeTexture_ = gl::createTexture(GL_TEXTURE_BUFFER);
  glTextureBuffer(nodeTexture_.id(), GL_R32UI, nodes_.id());
  radiance_ = gl::createBuffer(n * 4, nullptr, GL_DYNAMIC_STORAGE_BIT);
  material_ = gl::createBuffer(n * 8, nullptr, GL_DYNAMIC_STORAGE_BIT);
  emission_ = gl::createBuffer(n * 4, nullptr, GL_DYNAMIC_STORAGE_BIT);
}

// Allocates the node structure into `nodes` (capacity in paramsData_.info.w); false
// if it ran out of nodes.
bool Octree::buildInto(gl::FrameContext& ctx, const VoxelizePass& grid, uint32_t listed) {
  (void)ctx;
  const GLuint nodes = nodes_.id();
  clearBuffer(nodes, static_cast<GLsizeiptr>(paramsData_.info.w) * 4);
  gpu::OctreeCounters c{};
  c.nodeCount = 1;
  c.levelStart[0] = 0;
  c.levelStart[1] = 1;
  glNamedBufferSubData(counters_.id(), 0, sizeof(c), &c);
  glBindBufferBase(GL_UNIFORM_BUFFER, gpu::kOctreeParamsBinding, params_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeNodeBinding, nodes);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeCounterBinding, counters_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kVoxelListBinding, grid.list());
  for (int l = 0; l < stats_.depth; ++l) {
    setPass(static_cast<uint32_t>(l), 0, listed);
    dispatch(buildLevel_, listed);
    glCopyNamedBufferSubData(counters_.id(), counters_.id(),
                             offsetof(gpu::OctreeCounters, nodeCount),
                             static_cast<GLintptr>(offsetof(gpu::OctreeCounters, levelStart) +
                                                   4 * static_cast<size_t>(l + 2)),
                             4);
    glMemoryBarrier(kBarrier);
  }
  glGetNamedBufferSubData(counters_.id(), 0, sizeof(c), &c);
  levelStart_.assign(c.levelStart, c.levelStart + stats_.depth + 2);
  stats_.nodes = c.nodeCount;
  return c.overflow == 0;
}

void Octree::build(gl::FrameContext& ctx, const VoxelizePass& grid) {
  gl::StageScope stage(ctx.timer, "octree");
  const int n = grid.resolution();
  stats_.depth = depthFor(n);
  const uint32_t listed = grid.stats().occupied;
  paramsData_.origin = glm::vec4(grid.gridOrigin(), grid.voxelSize());
  paramsData_.info = glm::uvec4(static_cast<uint32_t>(stats_.depth), 1u << stats_.depth,
                                static_cast<uint32_t>(n), capacity_);
  bool built = capacity_ > 0 && buildInto(ctx, grid, listed);
  if (!built) {
    // First build, or the surface outgrew the buffer: build into a worst-case node
    // buffer, then keep what was used plus headroom for re-builds.
    const uint64_t worst = worstCaseNodes(listed, stats_.depth);
    const auto scratchNodes = static_cast<uint32_t>(std::min<uint64_t>(worst, kMaxNodes));
    paramsData_.info.w = scratchNodes;
    nodes_ = gl::createBuffer(static_cast<GLsizeiptr>(scratchNodes) * 4, nullptr,
                              GL_DYNAMIC_STORAGE_BIT);
    stats_.buildBytes = uint64_t{scratchNodes} * 4;
    if (!buildInto(ctx, grid, listed))
      throw Error(strf("--voxels %d: the octree needs more than %u nodes (%u occupied voxels)", n,
                       kMaxNodes, listed));
    gl::Buffer scratch = std::move(nodes_);
    const uint32_t used = stats_.nodes;
    allocate(static_cast<uint32_t>(std::min<uint64_t>(kMaxNodes, used + used / 16 + 64)));
    glCopyNamedBufferSubData(scratch.id(), nodes_.id(), 0, 0, static_cast<GLsizeiptr>(used) * 4);
    const uint32_t zero = 0;
    glClearNamedBufferSubData(nodes_.id(), GL_R32UI, static_cast<GLintptr>(used) * 4,
                              static_cast<GLsizeiptr>(capacity_ - used) * 4, GL_RED_INTEGER,
                              GL_UNSIGNED_INT, &zero);
    paramsData_.info.w = capacity_;
  }
  const auto used = static_cast<GLsizeiptr>(stats_.nodes);
  clearBuffer(radiance_.id(), used * 4);
  clearBuffer(material_.id(), used * 8);
  clearBuffer(emission_.id(), used * 4);

  // Leaves: mark them and copy the resolved voxel into them.
  bind();
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kVoxelListBinding, grid.list());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kVoxelAttribBinding, grid.attributes());
  setPass(static_cast<uint32_t>(stats_.depth), 0, listed);
  dispatch(fill_, listed);

  stats_.leaves = listed;
  listBuffer_ = grid.list();
  stats_.levelNodes.clear();
  for (int l = 0; l <= stats_.depth; ++l)
    stats_.levelNodes.push_back(levelStart_[static_cast<size_t>(l) + 1] -
                                levelStart_[static_cast<size_t>(l)]);
  stats_.bytes = uint64_t{capacity_} * (4 + kDataBytesPerNode);
  const uint64_t nn = static_cast<uint64_t>(n);
  stats_.denseBytes = nn * nn * nn * (4 + 4 + 8);  // albedo rgba8, normal rgba8, emission rgba16f
  stats_.buildBytes = std::max(stats_.buildBytes, stats_.bytes);
}

void Octree::inject(gl::FrameContext& ctx, const scene::GpuScene& scene) {
  gl::StageScope stage(ctx.timer, "inject");
  paramsData_.light = glm::uvec4(static_cast<uint32_t>(settings_.injectRays),
                                 static_cast<uint32_t>(scene.lightCount()),
                                 static_cast<uint32_t>(scene.emitterCount()), 0u);
  bind();
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kLightBinding, scene.lights());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kEmitterBinding, scene.emitters());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeLightCdfBinding, scene.emitterCdf());
  gl::Buffer direct, previous;
  const int voxelBounces = std::max(0, settings_.bounces - 1);
  const auto bytes = static_cast<GLsizeiptr>(stats_.nodes) * 4;
  if (voxelBounces > 0) {
    direct = gl::createBuffer(bytes, nullptr, GL_DYNAMIC_STORAGE_BIT);
    previous = gl::createBuffer(bytes, nullptr, GL_DYNAMIC_STORAGE_BIT);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeDirectBinding, direct.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeScratchBinding, previous.id());
  }
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kVoxelListBinding, listBuffer_);
  setPass(static_cast<uint32_t>(stats_.depth), 0, stats_.leaves, voxelBounces > 0 ? 1u : 0u);
  dispatch(inject_, stats_.leaves);
  paramsData_.light.x = static_cast<uint32_t>(settings_.bounceRays);
  for (int b = 1; b <= voxelBounces; ++b) {
    glCopyNamedBufferSubData(radiance_.id(), previous.id(), 0, 0, bytes);
    glMemoryBarrier(kBarrier);
    setPass(static_cast<uint32_t>(stats_.depth), 0, stats_.leaves, static_cast<uint32_t>(b));
    dispatch(bounce_, stats_.leaves);
  }
  // Inner nodes, bottom-up.
  for (int l = stats_.depth - 1; l >= 0; --l) {
    const uint32_t first = levelStart_[static_cast<size_t>(l)];
    const uint32_t count = levelStart_[static_cast<size_t>(l) + 1] - first;
    setPass(static_cast<uint32_t>(l), first, count);
    dispatch(filter_, count);
  }
}

std::vector<glm::ivec4> Octree::raycast(const std::vector<gpu::OctreeRay>& rays) {
  std::vector<glm::ivec4> hits(rays.size());
  if (rays.empty()) return hits;
  const gl::Program& program = programs_.get({{"voxel/octree_raycast.comp"}, {}});
  gl::Buffer in =
      gl::createBuffer(static_cast<GLsizeiptr>(rays.size() * sizeof(gpu::OctreeRay)), rays.data());
  gl::Buffer out = gl::createBuffer(static_cast<GLsizeiptr>(hits.size() * sizeof(glm::ivec4)),
                                    nullptr, GL_DYNAMIC_STORAGE_BIT);
  bind();
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeRayBinding, in.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeRayHitBinding, out.id());
  setPass(0, 0, static_cast<uint32_t>(rays.size()));
  dispatch(program, static_cast<uint32_t>(rays.size()));
  glGetNamedBufferSubData(out.id(), 0, static_cast<GLsizeiptr>(hits.size() * sizeof(glm::ivec4)),
                          hits.data());
  return hits;
}

std::vector<uint32_t> Octree::readNodes() const {
  std::vector<uint32_t> out(stats_.nodes);
  glGetNamedBufferSubData(nodes_.id(), 0, static_cast<GLsizeiptr>(out.size() * 4), out.data());
  return out;
}

std::vector<uint32_t> Octree::readRadiance() const {
  std::vector<uint32_t> out(size_t{stats_.nodes});
  glGetNamedBufferSubData(radiance_.id(), 0, static_cast<GLsizeiptr>(out.size() * 4), out.data());
  return out;
}

std::vector<uint32_t> Octree::readMaterial() const {
  std::vector<uint32_t> out(size_t{stats_.nodes} * 2);
  glGetNamedBufferSubData(material_.id(), 0, static_cast<GLsizeiptr>(out.size() * 4), out.data());
  return out;
}

}  // namespace voxgi::voxel
