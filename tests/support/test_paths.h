// Where tests find their inputs and the executable under test.
#ifndef VOXGI_TESTS_TEST_PATHS_H
#define VOXGI_TESTS_TEST_PATHS_H

#include <string>

namespace voxgi::test {

std::string sourceDir();    // the repository root
std::string samplesDir();   // scenes/ (the built-in scenes and the glTF samples)
std::string testDataDir();  // tests/data
std::string voxgiBinary();  // build/voxgi
std::string cornellRoom();  // scenes/cornell_room/cornell_room.gltf
std::string darkPlane();    // scenes/dark_plane/dark_plane.gltf
// A fresh empty directory under the system temp dir, removed at exit.
std::string scratchDir();

// The tools a test drives (xvfb-run, xdotool): where VOXGI_REQUIRE_TOOLS=1 (tools/test
// sets it after installing them) their absence fails the test, elsewhere it skips.
bool toolsRequired();

struct CommandResult {
  int exitCode = -1;
  std::string output;  // stdout and stderr together
};
// Runs a shell command line (with a timeout) and captures its output.
CommandResult runCommand(const std::string& commandLine, int timeoutSeconds = 120);

}  // namespace voxgi::test

#endif  // VOXGI_TESTS_TEST_PATHS_H
