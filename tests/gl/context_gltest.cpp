// Every headless backend gives a GL 4.5 core context with working KHR_debug.
#include <gtest/gtest.h>

#include "gl/debug.h"
#include "gl/gl.h"
#include "support/gl_fixture.h"

namespace voxgi::test {
namespace {

class ContextTest : public GlBackendTest {};

TEST_P(ContextTest, IsGl45Core) {
  GLint major = 0, minor = 0, mask = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &mask);
  EXPECT_GE(major * 10 + minor, 45);
  EXPECT_TRUE(mask & GL_CONTEXT_CORE_PROFILE_BIT);
  EXPECT_FALSE(context_->renderer().empty());
  EXPECT_EQ(context_->backend(), GetParam());
}

TEST_P(ContextTest, DebugOutputCountsErrors) {
  ASSERT_EQ(gl::debugErrorCount(), 0);
  glEnable(0xFFFF);  // GL_INVALID_ENUM, reported through KHR_debug
  EXPECT_EQ(gl::debugErrorCount(), 1);
  EXPECT_NE(gl::lastDebugError().find("error"), std::string::npos);
  gl::resetDebugErrorCount();  // the fixture fails the test on any error left
}

TEST_P(ContextTest, TimerQueriesGiveSaneTimes) {
  // The first TIME_ELAPSED query on llvmpipe used to report minutes (see
  // src/gl/workarounds.cpp); a query around a clear must take well under a second.
  GLuint tex = 0, fbo = 0, q = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &tex);
  glTextureStorage2D(tex, 1, GL_RGBA8, 64, 64);
  glCreateFramebuffers(1, &fbo);
  glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, tex, 0);
  glCreateQueries(GL_TIME_ELAPSED, 1, &q);
  glBeginQuery(GL_TIME_ELAPSED, q);
  const float c[4] = {1, 0, 0, 1};
  glClearNamedFramebufferfv(fbo, GL_COLOR, 0, c);
  glEndQuery(GL_TIME_ELAPSED);
  GLuint64 ns = 0;
  glGetQueryObjectui64v(q, GL_QUERY_RESULT, &ns);
  EXPECT_LT(ns, 1000000000ull);
  glDeleteQueries(1, &q);
  glDeleteFramebuffers(1, &fbo);
  glDeleteTextures(1, &tex);
}

INSTANTIATE_TEST_SUITE_P(Headless, ContextTest,
                         ::testing::Values(gl::Backend::kEgl, gl::Backend::kOsMesa),
                         backendParamName);

}  // namespace
}  // namespace voxgi::test
