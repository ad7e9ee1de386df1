// `voxgi view` end to end in a real GLX window under Xvfb on llvmpipe: a scripted
// run (30 frames, mode keys, exposure keys, screenshots) matches the headless render
// of the same view; a shader broken while the viewer runs is reported with
// file:line, the viewer keeps rendering with the last good program, and recovers
// when the file is restored (or comes back after being deleted); a scene file
// changed under the viewer is reloaded, or reported while the last good scene
// stays; SIGTERM and the quit key end the run cleanly.
#include <gtest/gtest.h>
#include <signal.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "image/image.h"
#include "image/metrics.h"
#include "support/test_paths.h"

namespace voxgi::test {
namespace {
namespace fs = std::filesystem;

#define VOXGI_REQUIRE_XVFB()                                       \
  do {                                                             \
    if (runCommand("sh -c 'command -v xvfb-run'").exitCode != 0) { \
      if (::voxgi::test::toolsRequired())                          \
        FAIL() << "xvfb-run missing (tools/setup installs xvfb)";  \
      GTEST_SKIP() << "xvfb-run not installed";                    \
    }                                                              \
  } while (0)

// `voxgi view ARGS` under xvfb-run, with voxgi's own exit status: xvfb-run, when
// several run at once, can fail to clean up its temporary directory and exit
// non-zero itself, which is not voxgi's doing (its message is dropped too).
CommandResult runViewer(const std::string& args) {
  CommandResult r = runCommand("xvfb-run -a sh -c '" + voxgiBinary() + " view " + args +
                               " 2>&1; echo voxgi-exit $?'");
  const size_t at = r.output.rfind("voxgi-exit ");
  if (at == std::string::npos) return r;  // voxgi never ran: keep xvfb-run's status
  r.exitCode = std::atoi(r.output.c_str() + at + 11);
  r.output.erase(at);
  const std::string noise = "xvfb-run: error: problem while cleaning up temporary directory\n";
  for (size_t n; (n = r.output.find(noise)) != std::string::npos;) r.output.erase(n, noise.size());
  return r;
}

nlohmann::json readJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

std::string readText(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Frame number from a log line "... view: frame N: ...".
int frameOf(const std::string& line) {
  const size_t at = line.find("frame ");
  return at == std::string::npos ? -1 : std::atoi(line.c_str() + at + 6);
}

// A command whose output is read line by line while it runs.
class LiveCommand {
 public:
  explicit LiveCommand(const std::string& commandLine)
      : pipe_(popen(("timeout 120 " + commandLine + " 2>&1").c_str(), "r")) {}
  // A failed assertion leaves the viewer running: stop it rather than wait for the
  // timeout.
  ~LiveCommand() {
    if (!pipe_) return;
    if (pid_ > 0) kill(pid_, SIGTERM);
    pclose(pipe_);
  }
  // Reads the "voxgi-pid N" line the command line prints for the viewer.
  pid_t readPid() {
    std::string line;
    if (waitFor("voxgi-pid", &line)) pid_ = std::atoi(line.c_str() + line.find(' ') + 1);
    return pid_;
  }
  // Reads until a line containing `needle`; false at the end of the output.
  bool waitFor(const std::string& needle, std::string* line = nullptr) {
    char buf[4096];
    while (pipe_ && std::fgets(buf, sizeof(buf), pipe_)) {
      output_ += buf;
      if (std::string(buf).find(needle) != std::string::npos) {
        if (line) *line = buf;
        return true;
      }
    }
    return false;
  }
  // Reads to the end and returns the exit status.
  int finish() {
    waitFor("\x01never");
    const int status = pclose(pipe_);
    pipe_ = nullptr;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  const std::string& output() const { return output_; }

 private:
  FILE* pipe_;
  pid_t pid_ = 0;
  std::string output_;
};

TEST(Viewer, HelpAndUsageErrorsNeedNoDisplay) {
  auto r = runCommand(voxgiBinary() + " view --help");
  EXPECT_EQ(r.exitCode, 0);
  for (const char* needle : {"--keys", "--screenshot", "--frames", "1 2 3 4 5 6", "VOXGI_SHADER"})
    EXPECT_NE(r.output.find(needle), std::string::npos) << needle;
  r = runCommand(voxgiBinary() + " view --keys 3:x");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.output.find("unknown key 'x'"), std::string::npos) << r.output;
  const std::string dir = scratchDir();
  r = runCommand(voxgiBinary() + " view --screenshot " + dir + "/no/such/dir/s.png");
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.output.find("does not exist"), std::string::npos) << r.output;
}

// 30 frames with a switch to points, to a mode this build lacks, and back, two exposure steps
// and two automatic screenshots; the final screenshot equals `voxgi render` of the
// same view, size and exposure.
TEST(Viewer, ScriptedRunMatchesHeadlessRender) {
  VOXGI_REQUIRE_XVFB();
  const std::string dir = scratchDir();
  const auto r = runViewer(std::string(
      "--mode raster --size 160x120 --frames 30 --keys 5:p,6:p,10:2,12:6,15:1,20:+,21:+ "
      "--screenshot-dir " +
      dir + " --screenshot " + dir + "/shot --stats " + dir + "/s.json"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("reserved slot is not in this build"), std::string::npos) << r.output;
  const auto stats = readJson(dir + "/s.json");
  EXPECT_EQ(stats["frames"], 30);
  EXPECT_EQ(stats["ended_by"], "frames");
  EXPECT_EQ(stats["backend"], "glfw");
  EXPECT_EQ(stats["mode"], "raster");
  EXPECT_EQ(stats["mode_switches"], 2);  // to points and back
  EXPECT_EQ(stats["unavailable_mode_requests"], nlohmann::json::array({"reserved"}));
  EXPECT_EQ(stats["exposure"], 2.0);
  EXPECT_EQ(stats["gl_errors"], 0);
  EXPECT_EQ(stats["size"]["width"], 160);
  EXPECT_TRUE(stats["stages"].contains("raster"));
  // Two automatic pairs, distinct, plus the named one.
  std::vector<std::string> shots = stats["screenshots"];
  ASSERT_EQ(shots.size(), 6u);
  for (const std::string& s : shots) EXPECT_TRUE(fs::exists(s)) << s;
  EXPECT_NE(shots[0], shots[2]);
  EXPECT_NE(fs::path(shots[0]).filename().string().find("voxgi-"), std::string::npos);
  EXPECT_EQ(shots[4], dir + "/shot.png");
  EXPECT_EQ(shots[5], dir + "/shot.exr");

  const auto ref =
      runCommand(voxgiBinary() + " render --mode raster --size 160x120 --exposure 2 --out " + dir +
                 "/ref.png --out " + dir + "/ref.exr --quiet");
  ASSERT_EQ(ref.exitCode, 0) << ref.output;
  const image::Image shot = image::readImage(dir + "/shot.png");
  ASSERT_EQ(shot.width, 160);
  ASSERT_EQ(shot.height, 120);
  const auto png = image::compare(shot, image::readImage(dir + "/ref.png"), 1.5 / 255.0);
  EXPECT_LE(png.maxAbs, 1.5 / 255.0);
  const auto exr =
      image::compare(image::readImage(dir + "/shot.exr"), image::readImage(dir + "/ref.exr"), 1e-3);
  EXPECT_LE(exr.meanAbs, 1e-4);
  // The match means something: at exposure 1 the picture is clearly darker.
  const auto dim = image::compare(shot, image::readImage(shots[0]), 1.5 / 255.0);
  EXPECT_GT(dim.meanAbs, 10.0 / 255.0);
}

// The test edits a scratch copy of shaders/ while the viewer runs on it.
TEST(Viewer, BrokenShaderKeepsRunningAndRecovers) {
  VOXGI_REQUIRE_XVFB();
  const std::string dir = scratchDir();
  fs::copy(sourceDir() + "/shaders", dir + "/shaders", fs::copy_options::recursive);
  const std::string frag = dir + "/shaders/render/raster.frag";
  const std::string original = readText(frag);
  const std::string good = "outRadiance = vec4(radiance, 1.0);";
  const size_t at = original.find(good);
  ASSERT_NE(at, std::string::npos);
  const int line = 1 + static_cast<int>(std::count(original.begin(), original.begin() + at, '\n'));
  std::string broken = original;
  broken.replace(at, good.size(), "outRadiance = vec4(radiance, 1.0) +;");

  LiveCommand viewer("xvfb-run -a sh -c 'echo voxgi-pid $$; exec env VOXGI_SHADER_DIR=" + dir +
                     "/shaders " + voxgiBinary() + " view --mode raster --size 96x72 --stats " +
                     dir + "/s.json'");
  std::string failed, recovered;
  const pid_t pid = viewer.readPid();
  ASSERT_GT(pid, 0) << viewer.output();
  ASSERT_TRUE(viewer.waitFor("first frame")) << viewer.output();

  std::ofstream(frag) << broken;
  ASSERT_TRUE(viewer.waitFor("shader reload failed", &failed)) << viewer.output();
  EXPECT_NE(failed.find("raster.frag:" + std::to_string(line) + ":"), std::string::npos) << failed;
  EXPECT_NE(failed.find("last good program keeps running"), std::string::npos) << failed;

  std::ofstream(frag) << original;
  ASSERT_TRUE(viewer.waitFor("program(s)", &recovered)) << viewer.output();
  EXPECT_GT(frameOf(recovered), frameOf(failed)) << "frames rendered between";
  kill(pid, SIGTERM);
  EXPECT_EQ(viewer.finish(), 0) << viewer.output();

  const auto stats = readJson(dir + "/s.json");
  EXPECT_EQ(stats["ended_by"], "signal");
  EXPECT_GT(stats["frames"].get<int>(), frameOf(recovered));
  EXPECT_GE(stats["reloads_failed"].get<int>(), 1);
  EXPECT_GE(stats["reloads_ok"].get<int>(), 1);
  EXPECT_NE(stats["last_reload_error"].get<std::string>().find(
                "raster.frag:" + std::to_string(line) + ":"),
            std::string::npos);
  EXPECT_EQ(stats["gl_errors"], 0);
}

// A shader file deleted while the viewer runs: the reload fails naming the file,
// the last good program keeps rendering, and the file's return is picked up.
TEST(Viewer, DeletedShaderKeepsRunningAndRecovers) {
  VOXGI_REQUIRE_XVFB();
  const std::string dir = scratchDir();
  fs::copy(sourceDir() + "/shaders", dir + "/shaders", fs::copy_options::recursive);
  const std::string frag = dir + "/shaders/render/raster.frag";
  const std::string original = readText(frag);

  LiveCommand viewer("xvfb-run -a sh -c 'echo voxgi-pid $$; exec env VOXGI_SHADER_DIR=" + dir +
                     "/shaders " + voxgiBinary() + " view --mode raster --size 96x72 --stats " +
                     dir + "/s.json'");
  std::string failed, recovered;
  const pid_t pid = viewer.readPid();
  ASSERT_GT(pid, 0) << viewer.output();
  ASSERT_TRUE(viewer.waitFor("first frame")) << viewer.output();

  fs::remove(frag);
  ASSERT_TRUE(viewer.waitFor("shader reload failed", &failed)) << viewer.output();
  EXPECT_NE(failed.find("raster.frag: cannot read shader file"), std::string::npos) << failed;
  EXPECT_NE(failed.find("last good program keeps running"), std::string::npos) << failed;

  std::ofstream(frag) << original;
  ASSERT_TRUE(viewer.waitFor("program(s)", &recovered)) << viewer.output();
  EXPECT_GT(frameOf(recovered), frameOf(failed)) << "frames rendered between";
  kill(pid, SIGTERM);
  EXPECT_EQ(viewer.finish(), 0) << viewer.output();
  const auto stats = readJson(dir + "/s.json");
  EXPECT_GE(stats["reloads_failed"].get<int>(), 1);
  EXPECT_GE(stats["reloads_ok"].get<int>(), 1);
  EXPECT_EQ(stats["gl_errors"], 0);
}

// The scene file changed under the viewer: a broken version is reported and the
// last good scene stays on screen; a good one replaces it; a deleted file is
// reported like a broken one. The viewer renders throughout.
TEST(Viewer, SceneFileChangedUnderIt) {
  VOXGI_REQUIRE_XVFB();
  const std::string dir = scratchDir();
  const std::string valid = testDataDir() + "/malformed/valid";
  const std::string path = dir + "/scene.gltf";
  fs::copy_file(valid + "/quad.gltf", path);

  LiveCommand viewer("xvfb-run -a sh -c 'echo voxgi-pid $$; exec " + voxgiBinary() + " view " +
                     path + " --mode raster --size 96x72 --stats " + dir + "/s.json'");
  std::string line;
  const pid_t pid = viewer.readPid();
  ASSERT_GT(pid, 0) << viewer.output();
  ASSERT_TRUE(viewer.waitFor("first frame")) << viewer.output();

  // Written elsewhere and renamed into place, as editors save.
  auto replace = [&](const std::string& text) {
    std::ofstream(dir + "/next.gltf") << text;
    fs::rename(dir + "/next.gltf", path);
  };
  replace("{ \"asset\": ");
  ASSERT_TRUE(viewer.waitFor("scene reload failed", &line)) << viewer.output();
  EXPECT_NE(line.find(path + ": "), std::string::npos) << line;
  EXPECT_NE(line.find("last good scene stays"), std::string::npos) << line;
  const int brokenAt = frameOf(line);

  replace(readText(valid + "/triangle.gltf"));
  ASSERT_TRUE(viewer.waitFor("reloaded the scene", &line)) << viewer.output();
  EXPECT_NE(line.find("(1 triangles)"), std::string::npos) << line;
  EXPECT_GT(frameOf(line), brokenAt) << "frames rendered between";

  fs::remove(path);
  ASSERT_TRUE(viewer.waitFor("scene reload failed", &line)) << viewer.output();
  EXPECT_NE(line.find("no such file"), std::string::npos) << line;
  kill(pid, SIGTERM);
  EXPECT_EQ(viewer.finish(), 0) << viewer.output();

  const auto stats = readJson(dir + "/s.json");
  EXPECT_EQ(stats["ended_by"], "signal");
  EXPECT_EQ(stats["scene_reloads_ok"], 1);
  EXPECT_EQ(stats["scene_reloads_failed"], 2);
  EXPECT_NE(stats["scene_error"].get<std::string>().find("no such file"), std::string::npos);
  EXPECT_GT(stats["frames"].get<int>(), frameOf(line));
  EXPECT_EQ(stats["gl_errors"], 0);
}

// Sizes beyond what a window or the memory budget can hold: one line, exit 1, no
// X error.
TEST(Viewer, AbsurdSizesAreRefused) {
  VOXGI_REQUIRE_XVFB();
  for (const char* size : {"100000x100000", "16384x16384"}) {
    SCOPED_TRACE(size);
    const auto r = runViewer(std::string("--size ") + size + " --frames 2");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_NE(r.output.find(std::string("size ") + size), std::string::npos) << r.output;
  }
}

// The window resized from outside (as a window manager would): the render targets
// follow the framebuffer, with no GL error.
TEST(Viewer, FollowsWindowResize) {
  VOXGI_REQUIRE_XVFB();
  if (runCommand("sh -c 'command -v xdotool'").exitCode != 0) {
    if (::voxgi::test::toolsRequired()) FAIL() << "xdotool missing (tools/setup installs it)";
    GTEST_SKIP() << "xdotool not installed";
  }
  const std::string dir = scratchDir();
  // The shell resizes the window once the test says so (the file "go"), after the
  // first frame, so the start size is not already the new one.
  LiveCommand viewer("xvfb-run -a sh -c '" + voxgiBinary() + " view --size 120x90 --stats " + dir +
                     "/s.json & v=$!; echo voxgi-pid $v; while [ ! -e " + dir +
                     "/go ]; do sleep 0.05; done; xdotool search --sync --name \"voxgi view\" " +
                     "windowsize 200 100; wait $v'");
  const pid_t pid = viewer.readPid();
  ASSERT_GT(pid, 0) << viewer.output();
  ASSERT_TRUE(viewer.waitFor("first frame")) << viewer.output();
  std::ofstream(dir + "/go") << "";
  ASSERT_TRUE(viewer.waitFor("resized to 200x100")) << viewer.output();
  kill(pid, SIGTERM);
  EXPECT_EQ(viewer.finish(), 0) << viewer.output();
  const auto stats = readJson(dir + "/s.json");
  EXPECT_EQ(stats["size"]["width"], 200);
  EXPECT_EQ(stats["size"]["height"], 100);
  EXPECT_GE(stats["resizes"].get<int>(), 1);
  EXPECT_EQ(stats["gl_errors"], 0);
}

TEST(Viewer, PlaysTheCameraPath) {
  VOXGI_REQUIRE_XVFB();
  const std::string dir = scratchDir();
  const auto r = runViewer(testDataDir() +
                           "/animated/camera_path.gltf --mode raster --size 64x48 --no-panel "
                           "--frames 6 --keys 3:r --stats " +
                           dir + "/s.json");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const auto stats = readJson(dir + "/s.json");
  EXPECT_EQ(stats["frames"], 6);
  EXPECT_EQ(stats["animated"], true);
  EXPECT_EQ(stats["camera_path"], true);
  EXPECT_EQ(stats["following_camera_path"], true);  // no fly input: still on the path
  EXPECT_GT(stats["animation_time"].get<double>(), 0.0);
  EXPECT_EQ(stats["gl_errors"], 0);
  // A still scene has no animation to play.
  const auto still =
      runViewer("--mode raster --size 64x48 --no-panel --frames 2 --stats " + dir + "/still.json");
  ASSERT_EQ(still.exitCode, 0) << still.output;
  EXPECT_EQ(readJson(dir + "/still.json")["animated"], false);
  EXPECT_FALSE(readJson(dir + "/still.json").contains("camera_path"));
}

TEST(Viewer, FlyingLeavesTheCameraPath) {
  VOXGI_REQUIRE_XVFB();
  if (runCommand("sh -c 'command -v xdotool'").exitCode != 0) {
    if (::voxgi::test::toolsRequired()) FAIL() << "xdotool missing (tools/setup installs it)";
    GTEST_SKIP() << "xdotool not installed";
  }
  const std::string dir = scratchDir();
  // W held for half a second once the path plays (the file "go"), the pointer over
  // the window so that it has the keyboard (no window manager under Xvfb).
  LiveCommand viewer("xvfb-run -a sh -c '" + voxgiBinary() + " view " + testDataDir() +
                     "/animated/camera_path.gltf --mode raster --size 64x48 --no-panel --stats " +
                     dir + "/s.json & v=$!; echo voxgi-pid $v; while [ ! -e " + dir +
                     "/go ]; do sleep 0.05; done; xdotool search --sync --name \"voxgi view\" " +
                     "mousemove --window %1 20 20 keydown w sleep 0.5 keyup w; wait $v'");
  const pid_t pid = viewer.readPid();
  ASSERT_GT(pid, 0) << viewer.output();
  ASSERT_TRUE(viewer.waitFor("first frame")) << viewer.output();
  std::ofstream(dir + "/go") << "";
  ASSERT_TRUE(viewer.waitFor("free camera")) << viewer.output();
  kill(pid, SIGTERM);
  EXPECT_EQ(viewer.finish(), 0) << viewer.output();
  const auto stats = readJson(dir + "/s.json");
  EXPECT_EQ(stats["camera_path"], true);
  EXPECT_EQ(stats["following_camera_path"], false);
  EXPECT_EQ(stats["gl_errors"], 0);
}

TEST(Viewer, QuitKeyEndsTheRunCleanly) {
  VOXGI_REQUIRE_XVFB();
  const std::string dir = scratchDir();
  const auto r = runViewer("--size 64x48 --no-panel --keys 4:esc --stats " + dir + "/s.json");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const auto stats = readJson(dir + "/s.json");
  EXPECT_EQ(stats["frames"], 3);
  EXPECT_EQ(stats["ended_by"], "window");
  EXPECT_EQ(stats["gl_errors"], 0);
}

}  // namespace
}  // namespace voxgi::test
