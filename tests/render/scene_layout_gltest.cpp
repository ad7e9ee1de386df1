// The std430/std140 layouts that GLSL gives shaders/include/scene_shared.h agree
// with the C++ side of the same header.
#include <gtest/gtest.h>

#include <cstddef>

#include "gl/program_cache.h"
#include "scene_shared.h"
#include "support/gl_fixture.h"
#include "support/test_paths.h"

namespace voxgi::test {
namespace {

class SceneLayoutTest : public GlTest {
 protected:
  GLint query(GLuint program, GLenum iface, const char* name, GLenum prop) {
    const GLuint index = glGetProgramResourceIndex(program, iface, name);
    EXPECT_NE(index, GL_INVALID_INDEX) << name;
    if (index == GL_INVALID_INDEX) return -1;
    GLint v = -1;
    glGetProgramResourceiv(program, iface, index, 1, &prop, 1, nullptr, &v);
    return v;
  }
};

TEST_F(SceneLayoutTest, StorageAndUniformLayoutsMatchCpp) {
  gl::ProgramCache cache(sourceDir() + "/shaders");
  const GLuint p = cache.get({{"render/raster.vert", "render/raster.frag"}, {}}).id();
  const GLenum bv = GL_BUFFER_VARIABLE;
  EXPECT_EQ(query(p, bv, "materials[0].baseColor", GL_TOP_LEVEL_ARRAY_STRIDE),
            static_cast<GLint>(sizeof(gpu::GpuMaterial)));
  EXPECT_EQ(query(p, bv, "materials[0].metallic", GL_OFFSET),
            static_cast<GLint>(offsetof(gpu::GpuMaterial, metallic)));
  EXPECT_EQ(query(p, bv, "materials[0].flags", GL_OFFSET),
            static_cast<GLint>(offsetof(gpu::GpuMaterial, flags)));
  EXPECT_EQ(query(p, bv, "materials[0].occlusionStrength", GL_OFFSET),
            static_cast<GLint>(offsetof(gpu::GpuMaterial, occlusionStrength)));
  EXPECT_EQ(query(p, bv, "lights[0].positionType", GL_TOP_LEVEL_ARRAY_STRIDE),
            static_cast<GLint>(sizeof(gpu::GpuLight)));
  EXPECT_EQ(query(p, bv, "lights[0].cone", GL_OFFSET),
            static_cast<GLint>(offsetof(gpu::GpuLight, cone)));
  EXPECT_EQ(query(p, bv, "emitters[0].a", GL_TOP_LEVEL_ARRAY_STRIDE),
            static_cast<GLint>(sizeof(gpu::GpuEmitter)));
  EXPECT_EQ(query(p, bv, "emitters[0].radiance", GL_OFFSET),
            static_cast<GLint>(offsetof(gpu::GpuEmitter, radiance)));
  EXPECT_EQ(query(p, GL_UNIFORM, "frame.cameraPosition", GL_OFFSET),
            static_cast<GLint>(offsetof(gpu::GpuFrame, cameraPosition)));
  EXPECT_EQ(query(p, GL_UNIFORM, "frame.counts", GL_OFFSET),
            static_cast<GLint>(offsetof(gpu::GpuFrame, counts)));
}

}  // namespace
}  // namespace voxgi::test
