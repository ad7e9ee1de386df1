#include "support/test_paths.h"

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <vector>

namespace voxgi::test {
namespace fs = std::filesystem;

std::string sourceDir() {
  return VOXGI_SOURCE_DIR;
}
std::string samplesDir() {
  return sourceDir() + "/scenes";
}
std::string testDataDir() {
  return VOXGI_TEST_DATA_DIR;
}
std::string voxgiBinary() {
  return VOXGI_BINARY;
}
std::string cornellRoom() {
  return sourceDir() + "/scenes/cornell_room/cornell_room.gltf";
}

std::string darkPlane() {
  return sourceDir() + "/scenes/dark_plane/dark_plane.gltf";
}

bool toolsRequired() {
  const char* env = std::getenv("VOXGI_REQUIRE_TOOLS");
  return env && std::string(env) == "1";
}

namespace {
// Scratch directories live until the test process exits.
struct ScratchDirs {
  std::vector<fs::path> dirs;
  ~ScratchDirs() {
    for (const auto& p : dirs) {
      std::error_code ec;
      fs::remove_all(p, ec);
    }
  }
};
ScratchDirs gScratch;
}  // namespace

std::string scratchDir() {
  static int counter = 0;
  const fs::path dir = fs::temp_directory_path() /
                       ("voxgi-test-" + std::to_string(getpid()) + "-" + std::to_string(counter++));
  fs::remove_all(dir);
  fs::create_directories(dir);
  gScratch.dirs.push_back(dir);
  return dir.string();
}

CommandResult runCommand(const std::string& commandLine, int timeoutSeconds) {
  CommandResult r;
  const std::string cmd = "timeout " + std::to_string(timeoutSeconds) + " " + commandLine + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
  const int status = pclose(pipe);
  r.exitCode =
      WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
  return r;
}

}  // namespace voxgi::test
