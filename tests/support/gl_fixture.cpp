#include "support/gl_fixture.h"

#include <cstdlib>

#include "core/log.h"
#include "gl/debug.h"
#include "support/test_paths.h"

namespace voxgi::test {

std::unique_ptr<gl::Context> makeContext(gl::Backend backend, std::string* why) {
  gl::ContextOptions o;
  o.backend = backend;
  o.debug = true;
  try {
    auto ctx = gl::Context::create(o);
    gl::resetDebugErrorCount();
    return ctx;
  } catch (const Error& e) {
    *why = e.what();
    return nullptr;
  }
}

namespace {
// OSMesa may legitimately be absent (Mesa >= 25.1); EGL must exist everywhere we test.
void open(gl::Backend backend, std::unique_ptr<gl::Context>* ctx) {
  std::string why;
  *ctx = makeContext(backend, &why);
  if (!*ctx) {
    if (backend == gl::Backend::kOsMesa && std::getenv("VOXGI_REQUIRE_OSMESA") == nullptr)
      GTEST_SKIP() << "OSMesa unavailable: " << why;
    FAIL() << "no GL context: " << why;
  }
}
void checkErrors() {
  EXPECT_EQ(gl::debugErrorCount(), 0) << "GL debug errors; last: " << gl::lastDebugError();
}
}  // namespace

void GlTest::SetUp() {
  open(gl::Backend::kEgl, &context_);
}
void GlTest::TearDown() {
  if (context_) checkErrors();
  context_.reset();
}
void GlBackendTest::SetUp() {
  open(GetParam(), &context_);
}
void GlBackendTest::TearDown() {
  if (context_) checkErrors();
  context_.reset();
}

std::string backendParamName(const ::testing::TestParamInfo<gl::Backend>& info) {
  return gl::backendName(info.param);
}

void GlProgramsTest::SetUp() {
  GlTest::SetUp();
  programs_ = std::make_unique<gl::ProgramCache>(sourceDir() + "/shaders");
}

void GlProgramsTest::TearDown() {
  programs_.reset();
  GlTest::TearDown();
}

}  // namespace voxgi::test
