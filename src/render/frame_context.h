// What opaque passes of render/ do with the per-frame context (gl::FrameContext,
// which voxel/ passes take too).
#ifndef VOXGI_RENDER_FRAME_CONTEXT_H
#define VOXGI_RENDER_FRAME_CONTEXT_H

#include "gl/frame_context.h"

#include <glm/glm.hpp>

namespace voxgi::render {

// Binds `framebuffer` at the frame size, clears its first `colorAttachments` colour
// attachments to `clear` and its depth to 1, and sets the depth test every opaque
// pass uses.
inline void beginOpaquePass(const gl::FrameContext& ctx, GLuint framebuffer, const glm::vec4& clear,
                            int colorAttachments = 1) {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glViewport(0, 0, ctx.width, ctx.height);
  for (GLint i = 0; i < colorAttachments; ++i)
    glClearNamedFramebufferfv(framebuffer, GL_COLOR, i, &clear.x);
  const float one = 1.0f;
  glClearNamedFramebufferfv(framebuffer, GL_DEPTH, 0, &one);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
}
}  // namespace voxgi::render

#endif  // VOXGI_RENDER_FRAME_CONTEXT_H
