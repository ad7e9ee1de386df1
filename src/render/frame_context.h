// What opaque passes of render/ do with the per-frame context (gl::FrameContext,
// which voxel/ passes take too).
#ifndef VOXGI_RENDER_FRAME_CONTEXT_H
#define VOXGI_RENDER_FRAME_CONTEXT_H

#include "gl/frame_context.h"

#include <glm/glm.hpp>

namespace voxgi::render {

// Binds `framebuffer` at the frame size, clears its first `colorAttachments` colour
// attachments to `clear` and its depth to 0 (the far plane: depth is reversed, see
// scene::Camera::projection), and sets the depth test every opaque pass uses, with
// clip control's [0, 1] depth range. Passes that draw without a depth test put their
// vertices at depth 0, inside either range.
inline void beginOpaquePass(const gl::FrameContext& ctx, GLuint framebuffer, const glm::vec4& clear,
                            int colorAttachments = 1) {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glViewport(0, 0, ctx.width, ctx.height);
  for (GLint i = 0; i < colorAttachments; ++i)
    glClearNamedFramebufferfv(framebuffer, GL_COLOR, i, &clear.x);
  const float farDepth = 0.0f;
  glClearNamedFramebufferfv(framebuffer, GL_DEPTH, 0, &farDepth);
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
}
}  // namespace voxgi::render

#endif  // VOXGI_RENDER_FRAME_CONTEXT_H
