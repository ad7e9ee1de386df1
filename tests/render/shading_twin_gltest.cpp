// The shading sources that both path tracer devices share (brdf_shared.h,
// sampling_shared.h, pathtrace_shading.h) agree between their GLSL build (run by
// llvmpipe) and their C++ build, on random inputs: every function, through
// tests/render/shading_twin.h. A formula that one build reads differently (an
// integer division, a double literal, a GLSL built-in with other semantics than
// GLM's) shows up as a disagreement on most cases; only rounding may differ.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "gl/program_cache.h"
#include "gpu_scene/gpu_scene.h"
#include "render/pathtrace/pathtrace_scene.h"
#include "render/shading_twin.h"
#include "support/gl_fixture.h"
#include "support/test_paths.h"

namespace voxgi::test {
namespace {

using gpu::kTwinInputs;
using gpu::kTwinOutputs;

glm::vec3 unitVector(std::mt19937& rng) {
  std::normal_distribution<float> g;
  glm::vec3 v(g(rng), g(rng), g(rng));
  return glm::normalize(v);
}

TEST_F(GlTest, SharedShadingAgreesBetweenGlslAndCpp) {
  constexpr int kCases = 4096;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  std::vector<glm::vec4> inputs;
  for (int i = 0; i < kCases; ++i) {
    const glm::vec3 n = unitVector(rng);
    glm::vec3 wo = unitVector(rng);
    if (glm::dot(wo, n) < 0.0f) wo = -wo;
    // A quarter Lambert, a quarter mirror, the rest the glTF BRDF.
    float metallic = u01(rng), roughness = u01(rng);
    if (i % 4 == 0) metallic = 0.0f, roughness = 1.0f;
    if (i % 4 == 1) metallic = 1.0f, roughness = 0.0f;
    inputs.push_back(glm::vec4(n, metallic));
    inputs.push_back(glm::vec4(wo, roughness));
    inputs.push_back(glm::vec4(unitVector(rng), u01(rng)));
    inputs.push_back(glm::vec4(u01(rng), u01(rng), u01(rng), u01(rng)));
    inputs.push_back(glm::vec4(4.0f * u01(rng) - 2.0f, 4.0f * u01(rng) - 2.0f,
                               4.0f * u01(rng) - 2.0f, std::bit_cast<float>(uint32_t(rng()))));
  }
  // Three emissive triangles of unequal power, through the real table builder.
  scene::Scene s;
  s.path = "twin";
  const glm::vec3 corners[3][3] = {{{-1, 3, -1}, {1, 3, -1}, {0, 3, 1}},
                                   {{3, -1, 0}, {3, 1, 0}, {3, 0, 2}},
                                   {{0, -3, 0}, {0.2f, -3, 0}, {0, -3, 0.1f}}};
  for (int t = 0; t < 3; ++t) {
    scene::Material m;
    m.emission = glm::vec3(1.0f + t, 2.0f, 0.5f * t + 0.1f);
    m.doubleSided = t == 1;
    s.materials.push_back(m);
    for (const glm::vec3& c : corners[t]) {
      s.indices.push_back(static_cast<uint32_t>(s.vertices.size()));
      s.vertices.push_back({c, glm::vec3(0, 1, 0), glm::vec2(0.0f)});
    }
    s.draws.push_back({static_cast<uint32_t>(3 * t), 3, t, -1, -1});
  }
  s.finalize();
  const render::PtScene pt = render::buildPtScene(s);
  ASSERT_EQ(pt.emitters.size(), 3u);
  // A point, a spot and a directional light.
  for (scene::LightType type :
       {scene::LightType::kPoint, scene::LightType::kSpot, scene::LightType::kDirectional}) {
    scene::Light l;
    l.type = type;
    l.color = glm::vec3(1.0f, 0.5f, 0.25f);
    l.intensity = 3.0f;
    l.range = type == scene::LightType::kPoint ? 4.0f : 0.0f;
    l.position = glm::vec3(0.5f, 1.0f, -0.5f);
    l.direction = glm::normalize(glm::vec3(0.2f, -1.0f, 0.1f));
    l.innerConeAngle = 0.3f;
    l.outerConeAngle = 0.9f;
    s.lights.push_back(l);
  }
  const std::vector<gpu::GpuLight> lights = scene::GpuScene::packLights(s);
  // A 5 x 3 texture of random texels; each case reads it with other flags (sRGB,
  // filter, wrap modes: shading_twin.h).
  std::vector<uint32_t> texels;
  for (int i = 0; i < 15; ++i) texels.push_back(static_cast<uint32_t>(rng()));
  const glm::uvec4 texture(0u, 5u, 3u, 0u);

  // GL.
  gl::ProgramCache programs(sourceDir() + "/shaders");
  const GLuint program = programs.get({{"../tests/render/shading_twin.comp"}, {}}).id();
  auto buffer = [](const void* data, size_t bytes) {
    return gl::createBuffer(static_cast<GLsizeiptr>(bytes), data);
  };
  const gl::Buffer in = buffer(inputs.data(), inputs.size() * sizeof(glm::vec4));
  const gl::Buffer em = buffer(pt.emitters.data(), pt.emitters.size() * sizeof(gpu::GpuPtEmissive));
  const gl::Buffer tx = buffer(texels.data(), texels.size() * sizeof(uint32_t));
  const gl::Buffer li = buffer(lights.data(), lights.size() * sizeof(gpu::GpuLight));
  const gl::Buffer out =
      gl::createBuffer(static_cast<GLsizeiptr>(kCases * kTwinOutputs * sizeof(glm::vec4)), nullptr);
  glUseProgram(program);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, in.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, em.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, tx.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, li.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, out.id());
  glUniform4ui(0, kCases, 3u, 3u, 0u);
  glUniform4ui(1, texture.x, texture.y, texture.z, texture.w);
  glDispatchCompute((kCases + 63) / 64, 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  std::vector<glm::vec4> gpuOut(kCases * kTwinOutputs);
  glGetNamedBufferSubData(out.id(), 0, static_cast<GLsizeiptr>(gpuOut.size() * sizeof(glm::vec4)),
                          gpuOut.data());
  glUseProgram(0);

  // C++, and the comparison: per output, the share of cases where every component
  // agrees within 1e-4 relative (1e-5 absolute near 0); hashes bit for bit.
  const gpu::PtTables tables{pt.emitters.data(), texels.data()};
  std::vector<int> agree(kTwinOutputs, 0);
  int hashesEqual = 0;
  for (int i = 0; i < kCases; ++i) {
    const glm::vec4* a = &inputs[static_cast<size_t>(i) * kTwinInputs];
    glm::vec4 r[kTwinOutputs];
    gpu::twinCase(tables, a[0], a[1], a[2], a[3], a[4], 3u, lights[static_cast<size_t>(i % 3)],
                  texture, r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8], r[9], r[10]);
    const glm::vec4* g = &gpuOut[static_cast<size_t>(i) * kTwinOutputs];
    if (std::bit_cast<uint32_t>(r[0].x) == std::bit_cast<uint32_t>(g[0].x) &&
        std::bit_cast<uint32_t>(r[0].w) == std::bit_cast<uint32_t>(g[0].w))
      ++hashesEqual;
    for (uint32_t k = 0; k < kTwinOutputs; ++k) {
      bool same = true;
      for (int c = (k == 0 ? 1 : 0); c < (k == 0 ? 3 : 4); ++c) {
        const float x = r[k][c], y = g[k][c];
        if (std::isnan(x) || std::isnan(y)) {
          same = same && std::isnan(x) && std::isnan(y);
          continue;
        }
        same = same && std::abs(x - y) <= 1e-4f * std::max(std::abs(x), std::abs(y)) + 1e-5f;
      }
      if (same) ++agree[k];
    }
  }
  EXPECT_EQ(hashesEqual, kCases) << "the PCG hash and stream must agree bit for bit";
  const char* names[kTwinOutputs] = {"pcg",
                                     "basis+cosine",
                                     "vndf+lobe chance",
                                     "evalBsdf",
                                     "sampleBsdf",
                                     "emitter direction+pdf",
                                     "emitter L+dist",
                                     "punctual",
                                     "texture",
                                     "luminance+MIS+GGX terms",
                                     "F0+specular rule"};
  for (uint32_t k = 0; k < kTwinOutputs; ++k) {
    const double share = static_cast<double>(agree[k]) / kCases;
    std::printf("%-26s %5.1f%% of %d cases agree\n", names[k], 100.0 * share, kCases);
    // Every case, every output: within the tolerance above (none differs today).
    EXPECT_EQ(agree[k], kCases) << names[k];
  }
}

}  // namespace
}  // namespace voxgi::test
