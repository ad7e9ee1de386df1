// What every pass receives: the programs, the timer, the output size and the
// per-frame uniform block (camera), already filled by the renderer.
#ifndef VOXGI_RENDER_FRAME_CONTEXT_H
#define VOXGI_RENDER_FRAME_CONTEXT_H

#include "gl/program_cache.h"
#include "gl/stage_timer.h"

namespace voxgi::render {

struct FrameContext {
  gl::ProgramCache& programs;
  gl::StageTimer& timer;
  int width = 0;
  int height = 0;
  GLuint frameUniforms = 0;  // GpuFrame, std140
};

}  // namespace voxgi::render

#endif  // VOXGI_RENDER_FRAME_CONTEXT_H
