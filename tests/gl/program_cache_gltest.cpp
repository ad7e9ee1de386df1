// Program cache: #include resolution, file:line error mapping, hot reload that
// rebuilds dependents and keeps the last good program on failure.
#include "gl/program_cache.h"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "core/log.h"
#include "support/gl_fixture.h"
#include "support/test_paths.h"

namespace voxgi::test {
namespace {
namespace fs = std::filesystem;

void writeFile(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
  // Make sure the modification time moves even on coarse file systems.
  static auto stamp = fs::file_time_type::clock::now();
  stamp += std::chrono::seconds(2);
  fs::last_write_time(p, stamp);
}

const char* kCompute =
    "#version 450 core\n"
    "#include \"common.glsl\"\n"
    "layout(local_size_x = 1) in;\n"
    "layout(std430, binding = 0) buffer Out { uint v[]; };\n"
    "void main() { v[0] = kAnswer; }\n";

class ProgramCacheTest : public GlTest {
 protected:
  void SetUp() override {
    GlTest::SetUp();
    root_ = scratchDir();
    writeFile(root_ / "include" / "common.glsl", "const uint kAnswer = 42u;\n");
    writeFile(root_ / "test.comp", kCompute);
  }
  uint32_t run(const gl::Program& p) {
    GLuint buf = 0;
    glCreateBuffers(1, &buf);
    const uint32_t zero = 0;
    glNamedBufferStorage(buf, 4, &zero, 0);
    glUseProgram(p.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buf);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    uint32_t v = 0;
    glGetNamedBufferSubData(buf, 0, 4, &v);
    glDeleteBuffers(1, &buf);
    return v;
  }
  fs::path root_;
};

TEST_F(ProgramCacheTest, ResolvesIncludesAndCaches) {
  gl::ProgramCache cache(root_);
  const gl::Program& p = cache.get({{"test.comp"}, {}});
  EXPECT_EQ(run(p), 42u);
  EXPECT_EQ(&cache.get({{"test.comp"}, {}}), &p);
  EXPECT_NE(&cache.get({{"test.comp"}, {"UNUSED=1"}}), &p);  // defines are part of the key
  EXPECT_EQ(cache.size(), 2u);
}

TEST_F(ProgramCacheTest, ErrorsNameTheIncludedFileAndLine) {
  writeFile(root_ / "include" / "common.glsl", "const uint kAnswer = 42u;\nthis is not glsl;\n");
  gl::ProgramCache cache(root_);
  try {
    cache.get({{"test.comp"}, {}});
    FAIL() << "expected a compile error";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("common.glsl:2"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

TEST_F(ProgramCacheTest, ErrorsInTheMainFileNameItsLine) {
  writeFile(root_ / "test.comp", std::string(kCompute) + "oops\n");
  gl::ProgramCache cache(root_);
  try {
    cache.get({{"test.comp"}, {}});
    FAIL() << "expected a compile error";
  } catch (const Error& e) {
    // Line 6 of test.comp, even though the include expanded above it.
    EXPECT_NE(std::string(e.what()).find("test.comp:6"), std::string::npos) << e.what();
  }
}

TEST_F(ProgramCacheTest, MissingIncludeAndCycleAreClearErrors) {
  writeFile(root_ / "missing.comp", "#version 450 core\n#include \"nowhere.glsl\"\n");
  writeFile(root_ / "include" / "a.glsl", "#include \"b.glsl\"\n");
  writeFile(root_ / "include" / "b.glsl", "#include \"a.glsl\"\n");
  writeFile(root_ / "cycle.comp", "#version 450 core\n#include \"a.glsl\"\n");
  gl::ProgramCache cache(root_);
  try {
    cache.get({{"missing.comp"}, {}});
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing.comp:2: cannot find include \"nowhere.glsl\""),
              std::string::npos)
        << e.what();
  }
  try {
    cache.get({{"cycle.comp"}, {}});
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cycle"), std::string::npos) << e.what();
  }
}

TEST_F(ProgramCacheTest, HotReloadRebuildsDependentsAndKeepsLastGood) {
  gl::ProgramCache cache(root_);
  const gl::Program& p = cache.get({{"test.comp"}, {}});
  ASSERT_EQ(run(p), 42u);
  EXPECT_EQ(cache.reloadChanged().rebuilt, 0);  // nothing changed

  // A change in the include rebuilds the program that includes it.
  writeFile(root_ / "include" / "common.glsl", "const uint kAnswer = 7u;\n");
  auto r = cache.reloadChanged();
  EXPECT_EQ(r.rebuilt, 1);
  EXPECT_EQ(p.generation(), 2);
  EXPECT_EQ(run(p), 7u);

  // A broken edit fails, names file:line, and the last good program keeps running.
  const GLuint good = p.id();
  writeFile(root_ / "include" / "common.glsl", "const uint kAnswer = ;\n");
  r = cache.reloadChanged();
  EXPECT_EQ(r.failed, 1);
  EXPECT_NE(r.error.find("common.glsl:1"), std::string::npos) << r.error;
  EXPECT_EQ(p.id(), good);
  EXPECT_EQ(run(p), 7u);
  EXPECT_EQ(cache.reloadChanged().failed, 0);  // not retried until the file changes again

  // A deleted file is a failure too, and the program survives it.
  fs::remove(root_ / "include" / "common.glsl");
  EXPECT_EQ(cache.reloadChanged().failed, 1);
  EXPECT_EQ(run(p), 7u);

  // Fixing the file recovers without a restart.
  writeFile(root_ / "include" / "common.glsl", "const uint kAnswer = 9u;\n");
  r = cache.reloadChanged();
  EXPECT_EQ(r.rebuilt, 1);
  EXPECT_EQ(run(p), 9u);
}

}  // namespace
}  // namespace voxgi::test
