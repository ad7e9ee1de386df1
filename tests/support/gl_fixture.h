// A headless GL 4.5 context per test, with KHR_debug on: any GL error or
// high-severity message during the test fails it (checked in TearDown).
#ifndef VOXGI_TESTS_GL_FIXTURE_H
#define VOXGI_TESTS_GL_FIXTURE_H

#include <gtest/gtest.h>

#include <memory>

#include "gl/context.h"
#include "gl/program_cache.h"

namespace voxgi::test {

// Creates a context for `backend`; returns null (and explains) when the backend
// does not exist on this machine, e.g. OSMesa on Mesa >= 25.1.
std::unique_ptr<gl::Context> makeContext(gl::Backend backend, std::string* why);

class GlTest : public ::testing::Test {
 protected:
  void SetUp() override;
  void TearDown() override;
  std::unique_ptr<gl::Context> context_;
};

// A GlTest with the program cache over the repository's shaders/ (dropped before the
// context goes).
class GlProgramsTest : public GlTest {
 protected:
  void SetUp() override;
  void TearDown() override;
  std::unique_ptr<gl::ProgramCache> programs_;
};

// Parameterised over the headless backends.
class GlBackendTest : public ::testing::TestWithParam<gl::Backend> {
 protected:
  void SetUp() override;
  void TearDown() override;
  std::unique_ptr<gl::Context> context_;
};

std::string backendParamName(const ::testing::TestParamInfo<gl::Backend>& info);

}  // namespace voxgi::test

#endif  // VOXGI_TESTS_GL_FIXTURE_H
