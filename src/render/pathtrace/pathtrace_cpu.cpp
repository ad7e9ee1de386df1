#include "render/pathtrace/pathtrace_cpu.h"

#include <embree3/rtcore.h>
#include <tbb/blocked_range2d.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "core/log.h"
#include "gpu_scene/gpu_scene.h"
#include "pathtrace_shading.h"

namespace voxgi::render {

// The Embree device and scene, and the TBB arena that bounds the worker threads.
struct CpuPathtracer::Embree {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::unique_ptr<tbb::task_arena> arena;
  ~Embree() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

void embreeError(void* /*user*/, RTCError code, const char* message) {
  logWarning(
      strf("pathtrace cpu: Embree error %d: %s", static_cast<int>(code), message ? message : ""));
}

void checkDevice(RTCDevice device, const char* what) {
  const RTCError e = rtcGetDeviceError(device);
  if (e != RTC_ERROR_NONE)
    throw Error(strf("pathtrace cpu: Embree failed to %s (error %d)", what, static_cast<int>(e)));
}

}  // namespace

CpuPathtracer::CpuPathtracer(const scene::Scene& scene, const PathtraceSettings& settings)
    : scene_(scene),
      settings_(settings),
      pt_(buildPtScene(scene, ptReadsTextures(scene, settings.textures))),
      textured_(ptReadsTextures(scene, settings.textures)),
      colored_(settings.colors && scene.hasVertexColors()),
      normalMapped_(settings.normalMaps && scene.hasNormalMaps() &&
                    ptReadsTextures(scene, settings.textures)),
      materials_(scene::GpuScene::packMaterials(scene)),
      lights_(scene::GpuScene::packLights(scene)),
      embree_(std::make_unique<Embree>()),
      camera_(scene.camera) {
  if (textured_) buildPtTextures(scene, &textureTable_, &texels_);
  buildTriangles(scene);
  const int threads =
      settings_.threads > 0 ? settings_.threads : tbb::this_task_arena::max_concurrency();
  embree_->arena = std::make_unique<tbb::task_arena>(threads);

  const auto start = std::chrono::steady_clock::now();
  embree_->device = rtcNewDevice(nullptr);
  if (!embree_->device)
    throw Error(strf("pathtrace cpu: Embree could not create a device (error %d)",
                     static_cast<int>(rtcGetDeviceError(nullptr))));
  rtcSetDeviceErrorFunction(embree_->device, embreeError, nullptr);
  embree_->scene = rtcNewScene(embree_->device);
  rtcSetSceneFlags(embree_->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(embree_->scene, RTC_BUILD_QUALITY_HIGH);
  if (!pt_.triangles.empty()) attachGeometry(scene);
  embree_->arena->execute([&] { rtcCommitScene(embree_->scene); });
  checkDevice(embree_->device, "build the BVH");
  bvhMs_ =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  logDebug(
      strf("pathtrace cpu: Embree BVH of %zu triangles in %.1f ms; %zu emissive triangles, "
           "%d threads",
           pt_.triangles.size(), bvhMs_, pt_.emitters.size(), threads));
}

void CpuPathtracer::buildTriangles(const scene::Scene& scene) {
  triangles_.resize(pt_.triangles.size());
  for (size_t t = 0; t < triangles_.size(); ++t) {
    const BvhTriangle& tri = pt_.triangles[t];
    const uint32_t first = pt_.firstIndex[t];
    const scene::Vertex& a = scene.vertices[scene.indices[first]];
    const scene::Vertex& b = scene.vertices[scene.indices[first + 1]];
    const scene::Vertex& c = scene.vertices[scene.indices[first + 2]];
    Triangle& r = triangles_[t];
    r.v0 = tri.v0;
    r.material = pt_.material[t];
    r.e1 = tri.v1 - tri.v0;
    r.emitterAreaPdf = pt_.emitterAreaPdf[t];
    r.e2 = tri.v2 - tri.v0;
    r.ng = glm::normalize(glm::cross(r.e1, r.e2));
    r.n0 = a.normal;
    r.n1 = b.normal;
    r.n2 = c.normal;
    r.uv0 = a.uv;
    r.uv1 = b.uv;
    r.uv2 = c.uv;
    r.uvB0 = a.uv2;
    r.uvB1 = b.uv2;
    r.uvB2 = c.uv2;
  }
  if (colored_) {
    cornerColors_.resize(3 * triangles_.size());
    for (size_t t = 0; t < triangles_.size(); ++t)
      for (size_t k = 0; k < 3; ++k)
        cornerColors_[3 * t + k] = scene.colors[scene.indices[pt_.firstIndex[t] + k]];
  }
  if (normalMapped_) {
    cornerTangents_.resize(3 * triangles_.size());
    for (size_t t = 0; t < triangles_.size(); ++t)
      for (size_t k = 0; k < 3; ++k)
        cornerTangents_[3 * t + k] = scene.tangents[scene.indices[pt_.firstIndex[t] + k]];
  }
}

void CpuPathtracer::attachGeometry(const scene::Scene& scene) {
  const size_t count = pt_.triangles.size();
  RTCGeometry geometry = rtcNewGeometry(embree_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * count));
  auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), count));
  checkDevice(embree_->device, "allocate the triangle buffers");
  for (size_t t = 0; t < count; ++t) {
    const BvhTriangle& tri = pt_.triangles[t];
    const glm::vec3 corners[3] = {tri.v0, tri.v1, tri.v2};
    for (int c = 0; c < 3; ++c) {
      const size_t k = 3 * t + static_cast<size_t>(c);
      vertices[3 * k] = corners[c].x;
      vertices[3 * k + 1] = corners[c].y;
      vertices[3 * k + 2] = corners[c].z;
      indices[k] = static_cast<uint32_t>(k);
    }
  }
  masked_ = ptReadsAlphaMasks(scene, settings_.alpha);
  if (masked_) {
    rtcSetGeometryUserData(geometry, this);
    rtcSetGeometryIntersectFilterFunction(geometry, alphaFilter);
    rtcSetGeometryOccludedFilterFunction(geometry, alphaFilter);
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(embree_->scene, geometry);
  rtcReleaseGeometry(geometry);
}

CpuPathtracer::~CpuPathtracer() = default;

void CpuPathtracer::alphaFilter(const RTCFilterFunctionNArguments* args) {
  const auto* self = static_cast<const CpuPathtracer*>(args->geometryUserPtr);
  const gpu::PtTables tables{self->pt_.emitters.data(), self->texels_.data()};
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const Triangle& t = self->triangles_[RTCHitN_primID(args->hit, args->N, i)];
    gpu::GpuMaterial m = self->materials_[static_cast<size_t>(t.material)];
    const float u = RTCHitN_u(args->hit, args->N, i), v = RTCHitN_v(args->hit, args->N, i);
    if (self->colored_)
      m.baseColor *= self->vertexColor(RTCHitN_primID(args->hit, args->N, i), u, v);
    const glm::vec2 uv = (1.0f - u - v) * t.uv0 + u * t.uv1 + v * t.uv2;
    const glm::uvec4 texture = self->textured_ && (m.flags & gpu::kMaterialHasTexture) != 0u
                                   ? self->textureTable_[m.texture]
                                   : glm::uvec4(0u);
    const float threshold = gpu::alphaHash(RTCHitN_primID(args->hit, args->N, i), glm::vec2(u, v));
    if (!gpu::alphaStops(tables, m, self->textured_, texture, uv, threshold)) args->valid[i] = 0;
  }
}

glm::vec4 CpuPathtracer::vertexColor(uint32_t t, float u, float v) const {
  if (!colored_) return glm::vec4(1.0f);
  const glm::vec4* c = cornerColors_.data() + 3 * static_cast<size_t>(t);
  return (1.0f - u - v) * c[0] + u * c[1] + v * c[2];
}

int CpuPathtracer::threads() const {
  return embree_->arena->max_concurrency();
}

namespace {

// Embree's packets: 8 rays for closest hits, 16 for shadow rays, the widths that
// trace a tile's rays fastest (docs/pathtracer.md, "What limits throughput").
constexpr int kHitPacket = 8;
constexpr int kShadowPacket = 16;

RTCIntersectContext incoherentContext() {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  return context;
}

// Lane k of an Embree packet: the ray from o along d over (0, tMax).
template <typename Packet>
void setLane(Packet* ray, int k, const glm::vec3& o, const glm::vec3& d, float tMax) {
  ray->org_x[k] = o.x;
  ray->org_y[k] = o.y;
  ray->org_z[k] = o.z;
  ray->tnear[k] = 0.0f;
  ray->dir_x[k] = d.x;
  ray->dir_y[k] = d.y;
  ray->dir_z[k] = d.z;
  ray->time[k] = 0.0f;
  ray->tfar[k] = tMax;
  ray->mask[k] = 0xffffffffu;
  ray->id[k] = 0;
  ray->flags[k] = 0;
}

}  // namespace

void CpuPathtracer::intersect(const Path* paths, const std::vector<uint32_t>& active,
                              std::vector<Hit>* hits) const {
  RTCIntersectContext context = incoherentContext();
  hits->resize(active.size());
  for (size_t first = 0; first < active.size(); first += kHitPacket) {
    const int lanes = static_cast<int>(std::min<size_t>(kHitPacket, active.size() - first));
    alignas(32) int valid[kHitPacket];
    alignas(32) RTCRayHit8 packet;
    for (int k = 0; k < kHitPacket; ++k) {
      valid[k] = k < lanes ? -1 : 0;
      const Path& p = paths[active[first + static_cast<size_t>(k < lanes ? k : 0)]];
      setLane(&packet.ray, k, p.o, p.d, std::numeric_limits<float>::infinity());
      packet.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
      packet.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect8(valid, embree_->scene, &context, &packet);
    for (int k = 0; k < lanes; ++k) {
      Hit& hit = (*hits)[first + static_cast<size_t>(k)];
      hit.triangle = packet.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID ? kMiss : packet.hit.primID[k];
      hit.t = packet.ray.tfar[k];
      hit.bc = glm::vec2(packet.hit.u[k], packet.hit.v[k]);
    }
  }
}

void CpuPathtracer::castShadows(const std::vector<ShadowRay>& shadows, Path* paths) const {
  RTCIntersectContext context = incoherentContext();
  for (size_t first = 0; first < shadows.size(); first += kShadowPacket) {
    const int lanes = static_cast<int>(std::min<size_t>(kShadowPacket, shadows.size() - first));
    alignas(64) int valid[kShadowPacket];
    alignas(64) RTCRay16 packet;
    for (int k = 0; k < kShadowPacket; ++k) {
      const ShadowRay& r = shadows[first + static_cast<size_t>(k < lanes ? k : 0)];
      // A ray with no length left after the offsets is not blocked.
      valid[k] = k < lanes && r.tMax > 0.0f ? -1 : 0;
      setLane(&packet, k, r.o, r.d, valid[k] != 0 ? r.tMax : 0.0f);
    }
    rtcOccluded16(valid, embree_->scene, &context, &packet);
    // In queue order, so that each path adds its lights in the order it drew them.
    for (int k = 0; k < lanes; ++k) {
      const ShadowRay& r = shadows[first + static_cast<size_t>(k)];
      if (valid[k] == 0 || packet.tfar[k] >= 0.0f) paths[r.path].result += r.light;  // -inf: hit
    }
  }
}

// One bounce of a path, step for step as the loop body of radiance() in
// shaders/render/pathtrace.comp after its ray was traced: emission, next-event
// estimation (queued as shadow rays), the BSDF sample and Russian roulette.
bool CpuPathtracer::bounce(const gpu::PtTables& tables, const Hit& hit, int depth, uint32_t index,
                           Path* path, std::vector<ShadowRay>* shadows) const {
  using namespace gpu;
  Path& p = *path;
  if (hit.triangle == kMiss) return false;  // black background
  const float eps = pt_.epsilon;
  const bool lightsByNee = settings_.nextEventEstimation && !pt_.emitters.empty();
  Surface s = surfaceAt(tables, hit, p.d);
  const vec3 emission(s.m.emission);
  if (emission != vec3(0.0f) && (s.front || (s.m.flags & kMaterialDoubleSided) != 0u)) {
    float w = 1.0f;
    const float areaPdf = triangles_[hit.triangle].emitterAreaPdf;
    if (!p.lastDelta && lightsByNee && areaPdf > 0.0f)
      w = emissionMisWeight(p.lastPdf, areaPdf, hit.t, abs(dot(s.ng, p.d)));
    p.result += p.throughput * emission * w;
  }
  if (depth == settings_.maxDepth) return false;

  orientSurface(tables, hit, &s);
  const vec3 wo = -p.d;
  const Bsdf bsdf = makeBsdf(vec3(s.baseColor), s.m.metallic, s.m.roughness, dot(s.ns, wo));
  if (bsdf.kind != kBsdfGgx && bsdf.base == vec3(0.0f)) return false;  // reflects nothing

  const vec3 origin = s.p + s.ng * eps;
  if (bsdf.kind == kBsdfMirror) {
    p.d = reflect(p.d, s.ns);
    if (dot(p.d, s.ng) <= 0.0f) return false;
    p.throughput *= bsdf.base;
    p.lastDelta = true;
  } else {
    queueDirectLight(tables, bsdf, s, origin, p.throughput, index, &p.rng, shadows);
    vec3 wi;
    if (!sampleBsdf(bsdf, s.ns, wo, p.rng, wi) || dot(wi, s.ng) <= 0.0f) return false;
    const vec3 f = evalBsdf(bsdf, s.ns, wo, wi, p.lastPdf);
    if (!(p.lastPdf > 0.0f)) return false;
    p.throughput *= f / p.lastPdf;
    p.d = wi;
    p.lastDelta = false;
  }
  p.o = origin;
  // Russian roulette from rrDepth on, as Mitsuba does it.
  if (depth >= settings_.rrDepth) {
    const float q = min(max(p.throughput.r, max(p.throughput.g, p.throughput.b)), 0.95f);
    if (!(pcgNext01(p.rng) < q)) return false;
    p.throughput /= q;
  }
  return true;
}

CpuPathtracer::Surface CpuPathtracer::surfaceAt(const gpu::PtTables& tables, const Hit& hit,
                                                const glm::vec3& d) const {
  using namespace gpu;
  const Triangle& T = triangles_[hit.triangle];
  const vec2 bc = hit.bc;
  Surface s;
  s.m = textured_ ? texturedMaterial(tables, materials_[static_cast<size_t>(T.material)],
                                     (1.0f - bc.x - bc.y) * T.uv0 + bc.x * T.uv1 + bc.y * T.uv2,
                                     (1.0f - bc.x - bc.y) * T.uvB0 + bc.x * T.uvB1 + bc.y * T.uvB2)
                  : materials_[static_cast<size_t>(T.material)];
  s.baseColor = colored_ ? s.m.baseColor * vertexColor(hit.triangle, bc.x, bc.y) : s.m.baseColor;
  s.p = T.v0 + bc.x * T.e1 + bc.y * T.e2;
  s.ng = T.ng;
  s.front = dot(s.ng, d) < 0.0f;
  s.wo = -d;
  return s;
}

void CpuPathtracer::orientSurface(const gpu::PtTables& tables, const Hit& hit, Surface* s) const {
  using namespace gpu;
  const Triangle& T = triangles_[hit.triangle];
  const vec2 bc = hit.bc;
  // Shade on the side the ray arrived from.
  vec3 ns = normalize((1.0f - bc.x - bc.y) * T.n0 + bc.x * T.n1 + bc.y * T.n2);
  if (!s->front) {
    s->ng = -s->ng;
    ns = -ns;
  }
  const vec3 wo = s->wo;
  if (dot(ns, wo) <= 0.0f || !(dot(ns, ns) > 0.5f)) ns = s->ng;  // past the silhouette
  if (normalMapped_ && (s->m.flags & kMaterialHasNormalTexture) != 0u) {
    // The normal map, then the back-facing rule (normal_map_shared.h), as the GL
    // device does; light below ng is rejected below.
    const vec4* c = cornerTangents_.data() + 3 * static_cast<size_t>(hit.triangle);
    vec4 tangent = (1.0f - bc.x - bc.y) * c[0] + bc.x * c[1] + bc.y * c[2];
    if (!s->front) tangent.w = -tangent.w;
    ns = bendShadingNormal(
        mappedNormal(tables, s->m, ns, tangent,
                     (1.0f - bc.x - bc.y) * T.uv0 + bc.x * T.uv1 + bc.y * T.uv2,
                     (1.0f - bc.x - bc.y) * T.uvB0 + bc.x * T.uvB1 + bc.y * T.uvB2),
        wo);
  }
  s->ns = ns;
}

void CpuPathtracer::queueDirectLight(const gpu::PtTables& tables, const gpu::Bsdf& bsdf,
                                     const Surface& s, const glm::vec3& origin,
                                     const glm::vec3& throughput, uint32_t path, uint32_t* rng,
                                     std::vector<ShadowRay>* shadows) const {
  using namespace gpu;
  const float eps = pt_.epsilon;
  const auto emitterCount = static_cast<uint>(pt_.emitters.size());
  const vec3 wo = s.wo;
  if (settings_.nextEventEstimation && emitterCount > 0) {
    const float u0 = pcgNext01(*rng);
    const float u1 = pcgNext01(*rng);
    const float u2 = pcgNext01(*rng);
    const EmitterSample ls = sampleEmitter(tables, s.p, emitterCount, u0, u1, u2);
    if (ls.pdfLight > 0.0f) {
      float pdfBsdf = 0.0f;
      const vec3 f = evalBsdf(bsdf, s.ns, wo, ls.wi, pdfBsdf);
      // The shadow ray leaves from the offset origin, so it aims at the sampled
      // point from there: a ray parallel to ls.wi would meet the emitter's surface
      // short of tMax wherever that surface is inclined to it.
      const vec3 toLight = s.p + ls.wi * ls.dist - origin;
      const float shadowDist = length(toLight);
      const float tMax = shadowDist * (1.0f - 1e-4f) - eps;
      if (f != vec3(0.0f) && dot(s.ng, ls.wi) > 0.0f)
        shadows->push_back(
            {origin, toLight / shadowDist, tMax,
             throughput * f * ls.radiance * (powerHeuristic(ls.pdfLight, pdfBsdf) / ls.pdfLight),
             path});
    }
  }
  for (const GpuLight& light : lights_) {
    const PunctualSample ls = samplePunctual(light, s.p);
    if (ls.radiance == vec3(0.0f) || dot(s.ng, ls.wi) <= 0.0f) continue;
    float pdf = 0.0f;
    const vec3 f = evalBsdf(bsdf, s.ns, wo, ls.wi, pdf);
    if (f == vec3(0.0f)) continue;
    shadows->push_back(
        {origin, ls.wi, ls.dist * (1.0f - 1e-4f) - eps, throughput * f * ls.radiance, path});
  }
}

void CpuPathtracer::allocate(int width, int height) {
  if (width == width_ && height == height_) return;
  width_ = width;
  height_ = height;
  const size_t n = static_cast<size_t>(width) * static_cast<size_t>(height);
  sum_.assign(n, glm::dvec3(0.0));
  mean_.assign(4 * n, 0.0f);
  reset();
}

void CpuPathtracer::reset() {
  samples_ = 0;
  std::fill(sum_.begin(), sum_.end(), glm::dvec3(0.0));
}

// One path per pixel, sample index firstSample, added to the running sums. Each
// tile's paths advance together, a bounce at a time, so that Embree traces their
// rays in packets; every path draws the same random numbers as alone.
void CpuPathtracer::tracePass(int firstSample) {
  const scene::Camera& cam = camera_;
  const float aspect = static_cast<float>(width_) / static_cast<float>(height_);
  const float tanHalf = std::tan(0.5f * cam.yfov);
  const glm::vec3 forward = glm::normalize(cam.forward);
  const glm::vec3 right0 = glm::normalize(glm::cross(forward, cam.up));
  const glm::vec3 up = glm::cross(right0, forward) * tanHalf;
  const glm::vec3 right = right0 * (tanHalf * aspect);
  const uint32_t seedHash = gpu::pcgHash(settings_.seed);
  const auto sample = static_cast<uint32_t>(firstSample);
  const gpu::PtTables tables{pt_.emitters.data(), texels_.data(), textureTable_.data()};
  constexpr int kTile = 16;
  embree_->arena->execute([&] {
    tbb::parallel_for(
        tbb::blocked_range2d<int>(0, height_, kTile, 0, width_, kTile),
        [&](const tbb::blocked_range2d<int>& r) {
          Path paths[kTile * kTile];
          uint32_t pixels[kTile * kTile];
          std::vector<uint32_t> active, next;
          std::vector<Hit> hits;
          std::vector<ShadowRay> shadows;
          for (int y = r.rows().begin(); y != r.rows().end(); ++y)
            for (int x = r.cols().begin(); x != r.cols().end(); ++x) {
              const auto pixelIndex = static_cast<uint32_t>(y * width_ + x);
              const auto i = static_cast<uint32_t>(active.size());
              Path& p = paths[i];
              p = Path{};
              p.rng = gpu::pcgHash(gpu::pcgHash(seedHash + pixelIndex) + sample);
              // Box filter: a uniform point in the pixel's footprint; y grows upwards.
              const float jx = gpu::pcgNext01(p.rng);
              const float jy = gpu::pcgNext01(p.rng);
              const glm::vec2 ndc =
                  (glm::vec2(static_cast<float>(x), static_cast<float>(y)) + glm::vec2(jx, jy)) /
                      glm::vec2(static_cast<float>(width_), static_cast<float>(height_)) * 2.0f -
                  1.0f;
              p.o = cam.position;
              p.d = glm::normalize(forward + ndc.x * right + ndc.y * up);
              pixels[i] = pixelIndex;
              active.push_back(i);
            }
          const auto count = active.size();
          for (int depth = 1; depth <= settings_.maxDepth && !active.empty(); ++depth) {
            intersect(paths, active, &hits);
            next.clear();
            shadows.clear();
            for (size_t k = 0; k < active.size(); ++k)
              if (bounce(tables, hits[k], depth, active[k], &paths[active[k]], &shadows))
                next.push_back(active[k]);
            castShadows(shadows, paths);
            std::swap(active, next);
          }
          for (size_t i = 0; i < count; ++i) sum_[pixels[i]] += glm::dvec3(paths[i].result);
        },
        tbb::simple_partitioner());
  });
}

void CpuPathtracer::accumulate(int width, int height, int spp, const Progress& progress) {
  allocate(width, height);
  const int target = samples_ + spp;
  const int first = samples_;
  while (samples_ < target) {
    tracePass(samples_);
    ++samples_;
    if (progress) progress(samples_ - first, spp);
  }
  const double inv = samples_ > 0 ? 1.0 / samples_ : 0.0;
  for (size_t i = 0; i < sum_.size(); ++i) {
    const glm::dvec3 m = sum_[i] * inv;
    mean_[4 * i] = static_cast<float>(m.r);
    mean_[4 * i + 1] = static_cast<float>(m.g);
    mean_[4 * i + 2] = static_cast<float>(m.b);
    mean_[4 * i + 3] = 1.0f;
  }
}

void CpuPathtracer::execute(gl::FrameContext& ctx, int spp, GLuint hdrTexture,
                            const Progress& progress) {
  gl::StageScope stage(ctx.timer, Stage::kPathtrace);
  accumulate(ctx.width, ctx.height, spp, progress);
  glTextureSubImage2D(hdrTexture, 0, 0, 0, ctx.width, ctx.height, GL_RGBA, GL_FLOAT, mean_.data());
}

void CpuPathtracer::warmUp(gl::FrameContext& ctx, GLuint /*hdrTexture*/) {
  allocate(ctx.width, ctx.height);  // the BVH is built; nothing to compile
}

}  // namespace voxgi::render
