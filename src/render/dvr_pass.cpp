#include "render/dvr_pass.h"

#include <cmath>

#include "rtgi_shared.h"

namespace voxgi::render {

DvrPass::DvrPass(gl::ProgramCache& programs, const Settings& settings)
    : settings_(settings), program_(programs.get({{"render/dvr.comp"}, {}})) {
  params_ = gl::createBuffer(sizeof(gpu::RtgiParams), nullptr, GL_DYNAMIC_STORAGE_BIT);
}

void DvrPass::execute(gl::FrameContext& ctx, const voxel::Octree& octree,
                      const scene::Camera& camera, GLuint target) {
  gl::StageScope stage(ctx.timer, Stage::kDvr);
  gpu::RtgiParams p{};
  p.width = static_cast<uint32_t>(ctx.width);
  p.height = static_cast<uint32_t>(ctx.height);
  const float aspect = static_cast<float>(ctx.width) / static_cast<float>(ctx.height);
  const float t = std::tan(camera.yfov * 0.5f);
  const glm::vec3 forward = glm::normalize(camera.forward);
  const glm::vec3 right = glm::normalize(glm::cross(forward, camera.up));
  const glm::vec3 up = glm::cross(right, forward);
  p.camera = glm::vec4(camera.position, 1.0f);
  p.cameraRight = glm::vec4(right * (t * aspect), 0.0f);
  p.cameraUp = glm::vec4(up * t, 0.0f);
  p.cameraForward = glm::vec4(forward, settings_.stopOpacity);
  glNamedBufferSubData(params_.id(), 0, sizeof(p), &p);
  octree.bind();
  glBindBufferBase(GL_UNIFORM_BUFFER, gpu::kRtgiParamsBinding, params_.id());
  glBindImageTexture(gpu::kAccumImage, target, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  glUseProgram(program_.id());
  glDispatchCompute(static_cast<GLuint>((ctx.width + gpu::kRtgiGroupX - 1) / gpu::kRtgiGroupX),
                    static_cast<GLuint>((ctx.height + gpu::kRtgiGroupY - 1) / gpu::kRtgiGroupY), 1);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  glBindImageTexture(gpu::kAccumImage, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
}

}  // namespace voxgi::render
