// Where tests find their inputs and the executable under test.
#ifndef VOXGI_TESTS_TEST_PATHS_H
#define VOXGI_TESTS_TEST_PATHS_H

#include <string>

namespace voxgi::test {

std::string sourceDir();    // the repository root
std::string samplesDir();   // ../shared/scenes (the glTF samples)
std::string testDataDir();  // tests/data
std::string voxgiBinary();  // build/voxgi
std::string cornellRoom();  // scenes/cornell_room/cornell_room.gltf
std::string darkPlane();    // scenes/dark_plane/dark_plane.gltf
// A fresh empty directory under the system temp dir, removed at exit.
std::string scratchDir();

// Skips the test when the samples are absent, unless VOXGI_REQUIRE_SAMPLES=1 (CI),
// where their absence fails it.
#define VOXGI_REQUIRE_SAMPLES()                                                    \
  do {                                                                             \
    if (!::voxgi::test::samplesPresent()) {                                        \
      if (::voxgi::test::samplesRequired())                                        \
        FAIL() << "samples missing: " << ::voxgi::test::samplesDir();              \
      GTEST_SKIP() << "glTF samples not found at " << ::voxgi::test::samplesDir(); \
    }                                                                              \
  } while (0)
bool samplesPresent();
bool samplesRequired();

struct CommandResult {
  int exitCode = -1;
  std::string output;  // stdout and stderr together
};
// Runs a shell command line (with a timeout) and captures its output.
CommandResult runCommand(const std::string& commandLine, int timeoutSeconds = 120);

}  // namespace voxgi::test

#endif  // VOXGI_TESTS_TEST_PATHS_H
