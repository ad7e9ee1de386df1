// Move-only RAII owners of GL object names, created with DSA (glCreate*).
// A default-constructed handle owns nothing (id 0); destruction deletes the object.
// They must be destroyed while the context that made them is current.
#ifndef VOXGI_GL_HANDLES_H
#define VOXGI_GL_HANDLES_H

#include <utility>

#include "gl/gl.h"

namespace voxgi::gl {

template <typename Traits>
class Object {
 public:
  Object() = default;
  explicit Object(GLuint adopt) : id_(adopt) {}
  ~Object() { reset(); }
  Object(Object&& o) noexcept : id_(std::exchange(o.id_, 0)) {}
  Object& operator=(Object&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, 0);
    }
    return *this;
  }
  Object(const Object&) = delete;
  Object& operator=(const Object&) = delete;

  GLuint id() const { return id_; }
  explicit operator bool() const { return id_ != 0; }
  void reset() {
    if (id_) Traits::destroy(id_);
    id_ = 0;
  }

 private:
  GLuint id_ = 0;
};

struct BufferTraits {
  static void destroy(GLuint id) { glDeleteBuffers(1, &id); }
};
struct TextureTraits {
  static void destroy(GLuint id) { glDeleteTextures(1, &id); }
};
struct FramebufferTraits {
  static void destroy(GLuint id) { glDeleteFramebuffers(1, &id); }
};
struct RenderbufferTraits {
  static void destroy(GLuint id) { glDeleteRenderbuffers(1, &id); }
};
struct VertexArrayTraits {
  static void destroy(GLuint id) { glDeleteVertexArrays(1, &id); }
};
struct QueryTraits {
  static void destroy(GLuint id) { glDeleteQueries(1, &id); }
};
struct ProgramTraits {
  static void destroy(GLuint id) { glDeleteProgram(id); }
};
struct ShaderTraits {
  static void destroy(GLuint id) { glDeleteShader(id); }
};
struct SamplerTraits {
  static void destroy(GLuint id) { glDeleteSamplers(1, &id); }
};

using Buffer = Object<BufferTraits>;
using Texture = Object<TextureTraits>;
using Framebuffer = Object<FramebufferTraits>;
using Renderbuffer = Object<RenderbufferTraits>;
using VertexArray = Object<VertexArrayTraits>;
using Query = Object<QueryTraits>;
using ProgramObject = Object<ProgramTraits>;
using ShaderObject = Object<ShaderTraits>;
using Sampler = Object<SamplerTraits>;

inline Buffer createBuffer() {
  GLuint id = 0;
  glCreateBuffers(1, &id);
  return Buffer(id);
}
// Immutable storage filled with `data` (may be null).
inline Buffer createBuffer(GLsizeiptr size, const void* data, GLbitfield flags = 0) {
  Buffer b = createBuffer();
  glNamedBufferStorage(b.id(), size > 0 ? size : 4, data, flags);
  return b;
}
inline Texture createTexture(GLenum target) {
  GLuint id = 0;
  glCreateTextures(target, 1, &id);
  return Texture(id);
}
// A width x height 2D texture of one level, read texel by texel (nearest): an image
// a compute stage writes and the next reads.
inline Texture createImage2D(GLenum format, int width, int height) {
  Texture t = createTexture(GL_TEXTURE_2D);
  glTextureStorage2D(t.id(), 1, format, width, height);
  glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  return t;
}
inline Framebuffer createFramebuffer() {
  GLuint id = 0;
  glCreateFramebuffers(1, &id);
  return Framebuffer(id);
}
inline VertexArray createVertexArray() {
  GLuint id = 0;
  glCreateVertexArrays(1, &id);
  return VertexArray(id);
}
inline Query createQuery(GLenum target) {
  GLuint id = 0;
  glCreateQueries(target, 1, &id);
  return Query(id);
}
inline Sampler createSampler() {
  GLuint id = 0;
  glCreateSamplers(1, &id);
  return Sampler(id);
}

}  // namespace voxgi::gl

#endif  // VOXGI_GL_HANDLES_H
