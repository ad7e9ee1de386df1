#include "voxel/octree.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "core/log.h"
#include "scene_shared.h"
#include "voxel_shared.h"

namespace voxgi::voxel {
namespace {

// std430 limits one SSBO to 128 MiB on llvmpipe: the node buffer's ceiling.
constexpr uint32_t kMaxNodes = (128u << 20) / 4u;
// Two-sided leaves with a second light slot: the index has 24 bits (octree_fill.comp).
constexpr uint32_t kMaxTwoSided = 0xFFFFFFu;
// Per light slot (one a node, one more a two-sided leaf: allocateLight) and per node.
constexpr uint64_t kRadianceBytes = 4;
constexpr uint64_t kSurfaceBytes = 4;          // the triangle under a side (kOctreeSurfaceBinding)
constexpr uint64_t kDataBytesPerNode = 8 + 4;  // material, emission
constexpr uint64_t kBounceBytes = 16;          // Settings::keepBounces
// The light's refinement: this estimate, its direct light, the previous bounce, the mean.
constexpr uint64_t kRefineBytes = 4 + 4 + 4 + 16;
// With all bounces, the first estimate's chain of bounces (the pixel's included).
// Refinement adds a bounce a cycle, and a cycle is every leaf once (15 frames in the
// hall), so what the chain leaves out, about a^K of the light of a closed room of
// albedo a, is missing from the first seconds: 12% at a = 0.7 and K = 6, 1.4% at 12
// (docs/octree.md).
constexpr int kFirstChainBounces = 12;
// The most bounce rays a side whose hits the chain records and reads again (estimate).
constexpr int kMaxReplayRays = 16;
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

// octree_bounce.comp's variant: OCTREE_BVH and the BVH's defines, with a BVH.
std::vector<std::string> bounceDefines(const Octree::Settings& settings) {
  std::vector<std::string> defines;
  if (!settings.bvhDefines.empty()) {
    defines = settings.bvhDefines;
    defines.emplace_back("OCTREE_BVH");
  }
  return defines;
}

// octree_inject.comp's: the effect plan's as well.
std::vector<std::string> injectDefines(const Octree::Settings& settings) {
  std::vector<std::string> defines = settings.features.defines();
  for (std::string& d : bounceDefines(settings)) defines.push_back(std::move(d));
  return defines;
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
      inject_(programs.get({{"voxel/octree_inject.comp"}, injectDefines(settings)})),
      bounce_(programs.get({{"voxel/octree_bounce.comp"}, bounceDefines(settings)})),
      average_(programs.get({{"voxel/octree_average.comp"}, {}})),
      filterRadiance_(programs.get({{"voxel/octree_filter.comp"}, {"OCTREE_FILTER_RADIANCE"}})) {
  if (settings.bounces < 0 || (settings.bounces > 16 && !allBounces()))
    throw Error(strf("--bounces %d: must be in [0, 16] or all", settings.bounces));
  if (settings.refineRays < 0)
    throw Error(strf("--refine-rays %d: must be at least 0", settings.refineRays));
  params_ = gl::createBuffer(sizeof(gpu::OctreeParams), nullptr, GL_DYNAMIC_STORAGE_BIT);
  counters_ = gl::createBuffer(sizeof(gpu::OctreeCounters), nullptr, GL_DYNAMIC_STORAGE_BIT);
  const uint32_t zero = 0;
  nonfinite_ = gl::createBuffer(sizeof(zero), &zero);
}

void Octree::setPass(uint32_t level, uint32_t first, uint32_t count, uint32_t bounce) {
  paramsData_.pass = glm::uvec4(level, first, count, seed_);
  paramsData_.light.w = bounce;
  glNamedBufferSubData(params_.id(), 0, sizeof(paramsData_), &paramsData_);
}

void Octree::dispatch(const gl::Program& p, uint32_t count) {
  if (count == 0) return;
  glUseProgram(p.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kNonfiniteCountBinding, nonfinite_.id());
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
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeBounceBinding, bounceMean_.id());
  glBindTextureUnit(gpu::kOctreeNodeTexUnit, nodeTexture_.id());
}

uint32_t Octree::nonfiniteTerms() const {
  uint32_t n = 0;
  glGetNamedBufferSubData(nonfinite_.id(), 0, sizeof(n), &n);
  return n;
}

void Octree::allocate(uint32_t capacity) {
  capacity_ = capacity;
  const auto n = static_cast<GLsizeiptr>(capacity);
  nodes_ = gl::createBuffer(n * 4, nullptr, GL_DYNAMIC_STORAGE_BIT);
  nodeTexture_ = gl::createTexture(GL_TEXTURE_BUFFER);
  glTextureBuffer(nodeTexture_.id(), GL_R32UI, nodes_.id());
  material_ = gl::createBuffer(n * 8, nullptr, GL_DYNAMIC_STORAGE_BIT);
  emission_ = gl::createBuffer(n * 4, nullptr, GL_DYNAMIC_STORAGE_BIT);
  lightSlots_ = 0;  // allocateLight() follows, once the leaves are known
}

// The light buffers: a slot for every node (the + side of a two-sided leaf) and,
// past them, `backSlots` for the two-sided leaves' - sides (octree.glsl, leafAxis).
void Octree::allocateLight(uint32_t backSlots) {
  lightSlots_ = capacity_ + backSlots;
  const auto n = static_cast<GLsizeiptr>(lightSlots_);
  radiance_ = gl::createBuffer(n * static_cast<GLsizeiptr>(kRadianceBytes), nullptr,
                               GL_DYNAMIC_STORAGE_BIT);
  if (settings_.keepBounces)
    bounceMean_ = gl::createBuffer(n * static_cast<GLsizeiptr>(kBounceBytes), nullptr,
                                   GL_DYNAMIC_STORAGE_BIT);
  estimate_ = gl::createBuffer(n * 4, nullptr, GL_DYNAMIC_STORAGE_BIT);
  direct_ = gl::createBuffer(n * 4, nullptr, GL_DYNAMIC_STORAGE_BIT);
  previous_ = gl::createBuffer(n * 4, nullptr, GL_DYNAMIC_STORAGE_BIT);
  mean_ = gl::createBuffer(n * 16, nullptr, GL_DYNAMIC_STORAGE_BIT);
  if (!settings_.bvhDefines.empty())
    surface_ = gl::createBuffer(n * static_cast<GLsizeiptr>(kSurfaceBytes), nullptr,
                                GL_DYNAMIC_STORAGE_BIT);
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
  gl::StageScope stage(ctx.timer, Stage::kOctree);
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
  clearBuffer(material_.id(), used * 8);
  clearBuffer(emission_.id(), used * 4);
  sliceStart_.clear();  // no light yet: nothing to refine until inject()

  // Leaves: mark them and copy the resolved voxel into them.
  bind();
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kVoxelListBinding, grid.list());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kVoxelAttribBinding, grid.attributes());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeCounterBinding, counters_.id());
  setPass(static_cast<uint32_t>(stats_.depth), 0, listed);
  dispatch(fill_, listed);
  // The two-sided leaves took their second light slots; room for them, and for
  // re-builds that have a few more.
  uint32_t twoSided = 0;
  glGetNamedBufferSubData(counters_.id(), offsetof(gpu::OctreeCounters, twoSided), sizeof(twoSided),
                          &twoSided);
  stats_.twoSidedLeaves = std::min(twoSided, kMaxTwoSided);
  if (lightSlots_ < capacity_ + stats_.twoSidedLeaves)
    allocateLight(stats_.twoSidedLeaves + stats_.twoSidedLeaves / 16 + 64);
  paramsData_.sides = glm::uvec4(capacity_, 0u, 0u, 0u);
  clearBuffer(radiance_.id(), static_cast<GLsizeiptr>(lightSlots_) * 4);
  // The surfaces under the leaves are found again: the leaves may be others.
  if (surface_.id() != 0)
    clearBuffer(surface_.id(), static_cast<GLsizeiptr>(lightSlots_ * kSurfaceBytes));

  stats_.leaves = listed;
  listBuffer_ = grid.list();
  stats_.levelNodes.clear();
  for (int l = 0; l <= stats_.depth; ++l)
    stats_.levelNodes.push_back(levelStart_[static_cast<size_t>(l) + 1] -
                                levelStart_[static_cast<size_t>(l)]);
  stats_.bytes =
      uint64_t{capacity_} * (4 + kDataBytesPerNode) +
      uint64_t{lightSlots_} * (kRadianceBytes + (settings_.keepBounces ? kBounceBytes : 0) +
                               (surface_.id() != 0 ? kSurfaceBytes : 0));
  stats_.refineBytes = uint64_t{lightSlots_} * kRefineBytes;
  const uint64_t nn = static_cast<uint64_t>(n);
  stats_.denseBytes = nn * nn * nn * (4 + 4 + 8);  // albedo rgba8, normal rgba8, emission rgba16f
  stats_.buildBytes = std::max(stats_.buildBytes, stats_.bytes + stats_.refineBytes);
}

void Octree::inject(gl::FrameContext& ctx, const scene::GpuScene& scene) {
  gl::StageScope stage(ctx.timer, Stage::kInject);
  refinements_ = 0;
  seed_ = settings_.seed;
  // The first estimate: the finite chain of bounces, or with all bounces a chain of
  // kFirstChainBounces that refinement carries on.
  const uint32_t count = setSlice(-1);
  const bool bounced = estimate(scene, count, settings_.injectRays, settings_.bounceRays, false);
  blend(count, 1.0f, bounced);
  raysSoFar_ = settings_.injectRays;
  weightSoFar_ = raysSoFar_ * raysSoFar_ * raysSoFar_ / 3.0;
  makeSlices();
  filter(filter_);
}

// The refinement slices: voxel v goes to slice hash(v) mod S, whatever its place in
// the voxel list (whose order follows thread timing), and each slice's voxels are
// sorted and packed, so a refinement's invocations are all busy and which voxels a
// frame refines, so the image, is the same every run.
void Octree::makeSlices() {
  const uint32_t perFrame = static_cast<uint32_t>(std::max(settings_.refineLeaves, 1));
  slices_ = static_cast<int>(std::max<uint32_t>(1, (stats_.leaves + perFrame - 1) / perFrame));
  std::vector<uint32_t> codes(stats_.leaves);
  if (!codes.empty())
    glGetNamedBufferSubData(listBuffer_, 0, static_cast<GLsizeiptr>(codes.size() * 4),
                            codes.data());
  auto sliceOf = [this](uint32_t code) {
    uint32_t h = code * 0x9e3779b1u;  // an integer mix, so slices spread over space
    h ^= h >> 16;
    h *= 0x85ebca6bu;
    h ^= h >> 13;
    return h % static_cast<uint32_t>(slices_);
  };
  std::sort(codes.begin(), codes.end(), [&](uint32_t a, uint32_t b) {
    const uint32_t sa = sliceOf(a), sb = sliceOf(b);
    return sa != sb ? sa < sb : a < b;
  });
  sliceStart_.assign(static_cast<size_t>(slices_) + 1, 0);
  for (uint32_t code : codes) ++sliceStart_[sliceOf(code) + 1];
  for (size_t k = 1; k < sliceStart_.size(); ++k) sliceStart_[k] += sliceStart_[k - 1];
  sliceList_ = gl::createBuffer(static_cast<GLsizeiptr>(std::max<size_t>(codes.size(), 1) * 4),
                                codes.empty() ? nullptr : codes.data());
  stats_.refineBytes = uint64_t{lightSlots_} * kRefineBytes + uint64_t{stats_.leaves} * 4;
}

bool Octree::refines() const {
  // A finite chain of voxel bounces needs every leaf's previous bounce of the same
  // estimate, which a slice does not have: such chains keep their first estimate.
  return settings_.refineRays > 0 && (allBounces() || settings_.bounces <= 1);
}

void Octree::refine(gl::FrameContext& ctx, const scene::GpuScene& scene) {
  if (!refines() || sliceStart_.empty() || stats_.leaves == 0) return;
  gl::StageScope stage(ctx.timer, Stage::kRefine);
  const int slice = refinements_ % slices_;
  if (slice == 0) {
    // A new cycle: every leaf gets one more estimate, weighing its rays times the
    // square of the rays so far (the integral of t^2: the first estimate counts as
    // its injectRays). With feedback, older estimates saw a voxel light of fewer
    // bounces: equal weights would keep their bias as 1/cycles^(1 - albedo); these
    // fade it as 1/cycles^(3 (1 - albedo)), for at most 9/5 of the variance.
    raysSoFar_ += settings_.refineRays;
    const double w = settings_.refineRays * raysSoFar_ * raysSoFar_;
    weightSoFar_ += w;
    cycleWeight_ = static_cast<float>(w / weightSoFar_);
  }
  seed_ = settings_.seed + 0x9e3779b9u * static_cast<uint32_t>(refinements_ + 1);
  ++refinements_;
  const uint32_t count = setSlice(slice);
  const bool bounced =
      estimate(scene, count, settings_.refineRays, settings_.refineRays, allBounces());
  blend(count, cycleWeight_, bounced);
  filter(filterRadiance_);
}

uint32_t Octree::setSlice(int slice) {
  if (slice < 0) {
    passList_ = listBuffer_;
    paramsData_.slice = glm::uvec4(0u);
    return stats_.leaves;
  }
  passList_ = sliceList_.id();
  const uint32_t first = sliceStart_[static_cast<size_t>(slice)];
  paramsData_.slice = glm::uvec4(first, 0u, 0u, 0u);
  return sliceStart_[static_cast<size_t>(slice) + 1] - first;
}

bool Octree::estimate(const scene::GpuScene& scene, uint32_t count, int rays, int bounceRays,
                      bool feedback) {
  // A finite chain: bounces - 1 voxel bounces; feedback: one, from the running mean.
  // All bounces start from a chain of kFirstChainBounces: refinement then has little
  // bias left to remove, and mostly noise.
  const int voxelBounces = feedback       ? 1
                           : allBounces() ? kFirstChainBounces - 1
                                          : std::max(0, settings_.bounces - 1);
  paramsData_.light =
      glm::uvec4(static_cast<uint32_t>(rays), static_cast<uint32_t>(scene.lightCount()),
                 static_cast<uint32_t>(scene.emitterCount()), 0u);
  bind();
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeRadianceBinding, estimate_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kLightBinding, scene.lights());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kEmitterBinding, scene.emitters());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeLightCdfBinding, scene.emitterCdf());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeDirectBinding, direct_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kVoxelListBinding, passList_);
  // With the BVH, the surfaces under the leaves: the direct light is taken there, and
  // the bounce rays start there.
  if (surface_.id() != 0)
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeSurfaceBinding, surface_.id());
  setPass(static_cast<uint32_t>(stats_.depth), 0, count, voxelBounces > 0 ? 1u : 0u);
  dispatch(inject_, count);
  paramsData_.light.x = static_cast<uint32_t>(bounceRays);
  // All bounces' chain: its first bounce's rays are recorded, and the later bounces
  // read the light of the same slots again instead of tracing rays of their own:
  // Jacobi iterations on one Monte Carlo estimate of the transport matrix, as a
  // radiosity solver iterates its form factors (M. Cohen and J. Wallace, "Radiosity
  // and Realistic Image Synthesis", 1993). Tracing was the chain's cost: the Cornell
  // room's 10 later bounces took 350 of its 650 ms with one new ray a leaf each, and
  // they now read the first bounce's four. Reading one sample of the matrix k times
  // biases only paths that come back to a leaf, and refinement's fresh rays, which
  // outweigh the first estimate, remove it (docs/octree.md).
  // Beyond kMaxReplayRays rays a side the records would outgrow the octree (1,024
  // rays: 16 KiB a leaf); the later bounces then trace a quarter of the rays each.
  const bool replays =
      allBounces() && !feedback && voxelBounces >= 2 && bounceRays <= kMaxReplayRays;
  gl::Buffer replay;
  if (replays) {
    replay = gl::createBuffer(static_cast<GLsizeiptr>(count) * 2 * bounceRays *
                                  static_cast<GLsizeiptr>(sizeof(glm::uvec2)),
                              nullptr);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeReplayBinding, replay.id());
  }
  const auto bytes = static_cast<GLsizeiptr>(stats_.nodes) * 4;
  const auto backBytes = static_cast<GLsizeiptr>(stats_.twoSidedLeaves) * 4;
  for (int b = 1; b <= voxelBounces; ++b) {
    if (feedback) {
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeScratchBinding, radiance_.id());
    } else {
      glCopyNamedBufferSubData(estimate_.id(), previous_.id(), 0, 0, bytes);
      const GLintptr back = static_cast<GLintptr>(capacity_) * 4;  // the - sides
      if (backBytes > 0)
        glCopyNamedBufferSubData(estimate_.id(), previous_.id(), back, back, backBytes);
      glMemoryBarrier(kBarrier);
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeScratchBinding, previous_.id());
    }
    if (b == 2 && allBounces() && !feedback && !replays)
      paramsData_.light.x = static_cast<uint32_t>(std::max(1, bounceRays / 4));
    paramsData_.rays.x = !replays ? gpu::kOctreeRaysTraced
                         : b == 1 ? gpu::kOctreeRaysRecorded
                                  : gpu::kOctreeRaysReplayed;
    setPass(static_cast<uint32_t>(stats_.depth), 0, count, static_cast<uint32_t>(b));
    dispatch(bounce_, count);
  }
  paramsData_.rays.x = gpu::kOctreeRaysTraced;
  return voxelBounces > 0;
}

void Octree::blend(uint32_t count, float weight, bool bounced) {
  bind();
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeScratchBinding, estimate_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeMeanBinding, mean_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kOctreeDirectBinding, direct_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kVoxelListBinding, passList_);
  paramsData_.blend =
      glm::vec4(weight, bounced ? 1.0f : 0.0f, settings_.keepBounces ? 1.0f : 0.0f, 0.0f);
  setPass(static_cast<uint32_t>(stats_.depth), 0, count);
  dispatch(average_, count);
}

// Inner nodes, bottom-up.
void Octree::filter(const gl::Program& program) {
  for (int l = stats_.depth - 1; l >= 0; --l) {
    const uint32_t first = levelStart_[static_cast<size_t>(l)];
    const uint32_t count = levelStart_[static_cast<size_t>(l) + 1] - first;
    setPass(static_cast<uint32_t>(l), first, count);
    dispatch(program, count);
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

std::vector<uint32_t> Octree::readRadiance(int slot) const {
  VOXGI_CHECK(slot == 0 || slot == 1);
  std::vector<uint32_t> out(size_t{stats_.nodes});
  if (slot == 0) {
    glGetNamedBufferSubData(radiance_.id(), 0, static_cast<GLsizeiptr>(out.size() * 4), out.data());
    return out;
  }
  // The - sides: where a two-sided leaf's normal word points (octree.glsl, backSlot).
  std::vector<uint32_t> back(size_t{stats_.twoSidedLeaves});
  if (!back.empty())
    glGetNamedBufferSubData(radiance_.id(), static_cast<GLintptr>(capacity_) * 4,
                            static_cast<GLsizeiptr>(back.size() * 4), back.data());
  const std::vector<uint32_t> material = readMaterial();
  for (size_t node = 0; node < out.size(); ++node) {
    const uint32_t word = material[2 * node + 1];
    const int axis =
        static_cast<int>(std::lround(static_cast<int8_t>(word >> 24) / 127.0 * 4.0)) - 1;
    if (axis >= 0 && (word & 0xFFFFFFu) < back.size()) out[node] = back[word & 0xFFFFFFu];
  }
  return out;
}

std::vector<glm::vec4> Octree::readMean() const {
  std::vector<glm::vec4> out(size_t{stats_.nodes});
  glGetNamedBufferSubData(mean_.id(), 0, static_cast<GLsizeiptr>(out.size() * 16), out.data());
  return out;
}

std::vector<uint32_t> Octree::readMaterial() const {
  std::vector<uint32_t> out(size_t{stats_.nodes} * 2);
  glGetNamedBufferSubData(material_.id(), 0, static_cast<GLsizeiptr>(out.size() * 4), out.data());
  return out;
}

}  // namespace voxgi::voxel
