// The path tracer's CPU device (`--pt-device cpu`): the same transport as the GL
// kernel (render/pathtrace/pathtrace_pass.h describes it), with rays cast by Embree 3
// (Wald et al. 2014, "Embree: A Kernel Framework for Efficient CPU Ray Tracing")
// and pixels spread over TBB worker threads in 16x16 tiles. A tile's paths advance
// together, a bounce at a time, and Embree traces each bounce's rays and shadow
// rays in packets (rtcIntersect8, rtcOccluded16); each path draws the same random
// numbers, in the same order, as it would alone. Shading, light sampling, MIS and the
// random stream are the shared sources that the kernel includes (see
// render/pathtrace/pathtracer.h), so the two devices agree in distribution, and on most
// paths sample for sample.
//
// Acceleration structure: one Embree triangle geometry over the scene's triangles
// in draw order (primitive id = PtScene triangle), built at high quality (SAH
// with spatial splits) and in robust mode, so rays through shared edges and
// vertices of a closed mesh never slip through.
// Accumulation: a double-precision running sum per pixel; each execute() adds
// `spp` passes of one path per pixel, then uploads the mean into the caller's
// RGBA32F texture.
#ifndef VOXGI_RENDER_PATHTRACE_PATHTRACE_CPU_H
#define VOXGI_RENDER_PATHTRACE_PATHTRACE_CPU_H

#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "render/pathtrace/pathtrace_scene.h"
#include "render/pathtrace/pathtracer.h"
#include "scene_shared.h"

struct RTCFilterFunctionNArguments;  // Embree

namespace voxgi::gpu {
struct Bsdf;
struct PtTables;
}  // namespace voxgi::gpu

namespace voxgi::render {

class CpuPathtracer final : public Pathtracer {
 public:
  CpuPathtracer(const scene::Scene& scene, const PathtraceSettings& settings);
  ~CpuPathtracer() override;
  CpuPathtracer(const CpuPathtracer&) = delete;
  CpuPathtracer& operator=(const CpuPathtracer&) = delete;

  void reset() override;
  void setCamera(const scene::Camera& camera) override { camera_ = camera; }
  void execute(gl::FrameContext& ctx, int spp, GLuint hdrTexture,
               const Progress& progress = {}) override;
  void warmUp(gl::FrameContext& ctx, GLuint hdrTexture) override;

  int samplesSoFar() const override { return samples_; }
  uint64_t truncatedPaths() const override { return 0; }
  int emissiveTriangles() const override { return static_cast<int>(pt_.emitters.size()); }
  double bvhBuildMs() const override { return bvhMs_; }
  size_t bvhNodes() const override { return 0; }  // Embree does not report it
  PathtraceDevice device() const override { return PathtraceDevice::kCpu; }
  size_t hostTextureBytes() const override {
    return texels_.size() * sizeof(uint32_t) + textureTable_.size() * sizeof(glm::uvec4);
  }
  int threads() const;

  // The mean of all samples so far, RGBA, rows bottom first (as the GL texture).
  const std::vector<float>& mean() const { return mean_; }
  // Adds `spp` samples per pixel at width x height without any GL (tests, tools).
  void accumulate(int width, int height, int spp, const Progress& progress = {});

 private:
  struct Embree;
  // What a hit reads of its triangle, in one record (128 bytes) rather than
  // scattered over the scene's arrays.
  struct alignas(16) Triangle {
    glm::vec3 v0;
    int32_t material;
    glm::vec3 e1;  // v1 - v0
    float emitterAreaPdf;
    glm::vec3 e2;  // v2 - v0
    glm::vec3 ng;  // normalize(cross(e1, e2)), as the kernel computes it per hit
    glm::vec3 n0, n1, n2;
    glm::vec2 uv0, uv1, uv2;     // corner texture coordinates, channel 0 (scene::Vertex::uv)
    glm::vec2 uvB0, uvB1, uvB2;  // channel 1 (scene::Vertex::uv2)
  };
  struct Hit {
    uint32_t triangle;
    float t;
    glm::vec2 bc;  // barycentrics of v1 and v2
  };
  static constexpr uint32_t kMiss = 0xffffffffu;  // Hit::triangle of a ray that hit nothing
  // A path between its bounces: the wavefront of tracePass() keeps one per pixel
  // of a tile.
  struct Path {
    glm::vec3 o{0.0f}, d{0.0f};  // the ray to trace next
    glm::vec3 throughput{1.0f};
    glm::vec3 result{0.0f};
    float lastPdf = 0.0f;   // solid-angle pdf of the BSDF sample that led here
    bool lastDelta = true;  // camera rays and mirror bounces: emission counts in full
    uint32_t rng = 0;
  };
  // A shadow ray a bounce queued: `light` reaches path `path` unless something lies
  // on the ray within (0, tMax).
  struct ShadowRay {
    glm::vec3 o, d;
    float tMax;
    glm::vec3 light;
    uint32_t path;
  };
  void allocate(int width, int height);
  // The closest hits of the rays of paths[active[i]], in Embree packets.
  void intersect(const Path* paths, const std::vector<uint32_t>& active,
                 std::vector<Hit>* hits) const;
  // Traces the shadow rays in packets and adds the light of those unblocked.
  void castShadows(const std::vector<ShadowRay>& shadows, Path* paths) const;
  // One bounce of path `index` at its hit; false when the path ends there.
  bool bounce(const gpu::PtTables& tables, const Hit& hit, int depth, uint32_t index, Path* path,
              std::vector<ShadowRay>* shadows) const;
  // The steps of bounce(). The surface a path hits, as the kernel shades it.
  struct Surface {
    gpu::GpuMaterial m;   // textured
    glm::vec4 baseColor;  // times the vertex colour
    glm::vec3 p;          // the hit point
    glm::vec3 ng;         // the triangle's normal; after orientSurface, on the ray's side
    glm::vec3 ns;         // the shading normal (orientSurface)
    glm::vec3 wo;         // toward the ray's origin
    bool front = false;   // the ray arrived on ng's side
  };
  Surface surfaceAt(const gpu::PtTables& tables, const Hit& hit, const glm::vec3& d) const;
  // Turns ng and ns to the side the ray arrived from; ns past the silhouette, then
  // normal-mapped.
  void orientSurface(const gpu::PtTables& tables, const Hit& hit, Surface* s) const;
  // Next-event estimation and the punctual lights at s, queued as shadow rays of
  // path `path`.
  void queueDirectLight(const gpu::PtTables& tables, const gpu::Bsdf& bsdf, const Surface& s,
                        const glm::vec3& origin, const glm::vec3& throughput, uint32_t path,
                        uint32_t* rng, std::vector<ShadowRay>* shadows) const;
  // The constructor's steps: triangles_ and the corner arrays; the Embree geometry.
  void buildTriangles(const scene::Scene& scene);
  void attachGeometry(const scene::Scene& scene);
  // The vertex colour at barycentrics (u, v) of triangle t; white without colours.
  glm::vec4 vertexColor(uint32_t t, float u, float v) const;
  void tracePass(int firstSample);
  // Embree's hit filter: drops hits where an alpha mask lets the ray through.
  static void alphaFilter(const ::RTCFilterFunctionNArguments* args);

  const scene::Scene& scene_;
  PathtraceSettings settings_;
  PtScene pt_;
  std::vector<Triangle> triangles_;
  bool textured_ = false;
  bool masked_ = false;        // some material is alpha-masked (and the plan reads masks)
  bool colored_ = false;       // the scene has vertex colours (and the plan reads them)
  bool normalMapped_ = false;  // the scene has normal maps (and the plan reads them)
  // With normalMapped_: per triangle, its corners' tangents (3 entries); else empty.
  std::vector<glm::vec4> cornerTangents_;
  // With colored_: per triangle, its corners' COLOR_0 (3 entries); else empty.
  std::vector<glm::vec4> cornerColors_;
  std::vector<gpu::GpuMaterial> materials_;
  std::vector<gpu::GpuLight> lights_;
  std::vector<glm::uvec4> textureTable_;
  std::vector<uint32_t> texels_;
  std::unique_ptr<Embree> embree_;
  double bvhMs_ = 0.0;
  std::vector<glm::dvec3> sum_;
  std::vector<float> mean_;
  int width_ = 0, height_ = 0;
  int samples_ = 0;
  scene::Camera camera_;
};

}  // namespace voxgi::render

#endif  // VOXGI_RENDER_PATHTRACE_PATHTRACE_CPU_H
