// The per-frame context lives in gl/ (voxel/ passes take it too); the name stays here.
#ifndef VOXGI_RENDER_FRAME_CONTEXT_H
#define VOXGI_RENDER_FRAME_CONTEXT_H

#include "gl/frame_context.h"

#include <glm/glm.hpp>

namespace voxgi::render {
using FrameContext = gl::FrameContext;

// Binds `framebuffer` (HDR colour + depth at the frame size), clears both and sets
// the depth test every opaque pass uses.
inline void beginOpaquePass(const FrameContext& ctx, GLuint framebuffer, const glm::vec4& clear) {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glViewport(0, 0, ctx.width, ctx.height);
  glClearNamedFramebufferfv(framebuffer, GL_COLOR, 0, &clear.x);
  const float one = 1.0f;
  glClearNamedFramebufferfv(framebuffer, GL_DEPTH, 0, &one);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
}
}  // namespace voxgi::render

#endif  // VOXGI_RENDER_FRAME_CONTEXT_H
