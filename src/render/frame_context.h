// The per-frame context lives in gl/ (voxel/ passes take it too); the name stays here.
#ifndef VOXGI_RENDER_FRAME_CONTEXT_H
#define VOXGI_RENDER_FRAME_CONTEXT_H

#include "gl/frame_context.h"

namespace voxgi::render {
using FrameContext = gl::FrameContext;
}  // namespace voxgi::render

#endif  // VOXGI_RENDER_FRAME_CONTEXT_H
