// What every pass receives: the programs, the timer, the output size and the
// per-frame uniform block (camera), already filled by the renderer.
#ifndef VOXGI_GL_FRAME_CONTEXT_H
#define VOXGI_GL_FRAME_CONTEXT_H

#include "gl/program_cache.h"
#include "gl/stage_timer.h"

namespace voxgi::gl {

struct FrameContext {
  ProgramCache& programs;
  StageTimer& timer;
  int width = 0;
  int height = 0;
  GLuint frameUniforms = 0;  // GpuFrame, std140
};

}  // namespace voxgi::gl

#endif  // VOXGI_GL_FRAME_CONTEXT_H
