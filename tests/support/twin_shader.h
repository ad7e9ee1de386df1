// The GL half of a twin test: a compute shader of 64-wide groups
// (tests/render/*_twin.comp) run once per case, reading the given SSBOs at bindings
// 0, 1, ... and writing one T per case to the SSBO bound after them; uniform 0 holds
// the case count. Needs a current context (GlTest).
#ifndef VOXGI_TESTS_TWIN_SHADER_H
#define VOXGI_TESTS_TWIN_SHADER_H

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "gl/handles.h"
#include "gl/program_cache.h"
#include "support/test_paths.h"

namespace voxgi::test {

struct TwinInput {
  const void* data;
  size_t bytes;
};

template <typename T, typename Allocator>
TwinInput twinInput(const std::vector<T, Allocator>& v) {
  return {v.data(), v.size() * sizeof(T)};
}

// `shader`: relative to tests/render.
template <typename T>
std::vector<T> runTwinShader(const std::string& shader, const std::vector<TwinInput>& inputs,
                             uint32_t cases) {
  gl::ProgramCache programs(sourceDir() + "/shaders");
  const GLuint program = programs.get({{"../tests/render/" + shader}, {}}).id();
  std::vector<gl::Buffer> buffers;
  for (const TwinInput& in : inputs)
    buffers.push_back(gl::createBuffer(static_cast<GLsizeiptr>(in.bytes), in.data));
  const auto outBytes = static_cast<GLsizeiptr>(cases * sizeof(T));
  const gl::Buffer out = gl::createBuffer(outBytes, nullptr);
  glUseProgram(program);
  GLuint binding = 0;
  for (const gl::Buffer& b : buffers) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding++, b.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, out.id());
  glUniform1ui(0, cases);
  glDispatchCompute((cases + 63) / 64, 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  std::vector<T> result(cases);
  glGetNamedBufferSubData(out.id(), 0, outBytes, result.data());
  glUseProgram(0);
  return result;
}

}  // namespace voxgi::test

#endif  // VOXGI_TESTS_TWIN_SHADER_H
