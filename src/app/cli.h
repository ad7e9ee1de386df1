// Command line of the voxgi executable. Parsing never exits; it throws
// UsageError (exit 2) and app/main.cpp decides what to print and return.
#ifndef VOXGI_APP_CLI_H
#define VOXGI_APP_CLI_H

#include <optional>
#include <string>
#include <vector>

#include "app/viewer.h"
#include "core/log.h"
#include "gl/context.h"
#include "render/renderer.h"

namespace voxgi::app {

class UsageError : public Error {
 public:
  using Error::Error;
};

// The frame rate `voxgi view` holds in rtgi unless told otherwise (--target-fps).
constexpr double kViewTargetFps = 30.0;
// The render scale `voxgi view` starts rtgi at on a software GL (--render-scale).
constexpr float kSoftwareRenderScale = 0.5f;

struct RenderOptions {
  std::string scene;  // empty: the built-in Cornell room
  render::RenderSettings render;
  gl::Backend backend = gl::Backend::kEgl;
  int eglDevice = -1;                // gl::ContextOptions::eglDevice (app/environment.h)
  std::vector<std::string> outputs;  // .png and/or .exr
  std::string stats;                 // .json
  std::string maskOutput;            // rtgi work mask: .png or .exr
  int frames = 0;                    // 0 until parsed: the mode's default (render::defaultFrames)
  double time = 0.0;                 // animated scenes: the pose of the first frame, seconds
  double fps = 30.0;                 // animated scenes: frame f shows time + f / fps
  bool loop = false;                 // animated scenes: time wraps around the end (else held)
  bool verbose = false;
  bool quiet = false;
  bool progress = true;  // pathtrace: a progress bar on stderr when it is a terminal
  // Another viewpoint than the file's camera, in the file's coordinates (both set).
  std::optional<glm::vec3> lookFrom, lookAt;
};

struct BenchOptions {
  RenderOptions render;     // mode, size, frames, backend as for render
  std::vector<int> voxels;  // grid resolutions, one row each
  std::string json;         // results file
};

struct CompareOptions {
  std::string test;
  std::string reference;
  bool json = false;
  int blocks = 0;  // > 0: also the block luminance ratios over this many pixels a side
};

struct CheckOptions {
  std::string scene;
};

enum class Command { kHelp, kVersion, kRender, kView, kBench, kCompare, kCheck };

struct Invocation {
  Command command = Command::kHelp;
  RenderOptions render;
  ViewOptions view;
  BenchOptions bench;
  CompareOptions compare;
  CheckOptions check;
  std::string helpTopic;  // "", "render", "view", "bench", "compare" or "check"
};

Invocation parseCommandLine(const std::vector<std::string>& args);

std::string mainHelp();
std::string renderHelp();
std::string viewHelp();
std::string benchHelp();
std::string compareHelp();
std::string checkHelp();
std::string versionText();

// The built-in default scene (scenes/cornell_room/cornell_room.gltf).
std::string defaultScenePath();
// The shader folder: $VOXGI_SHADER_DIR, else the source tree's shaders/.
std::string shaderRoot();

int runRender(const RenderOptions& options);
int runBench(const BenchOptions& options);
int runCompare(const CompareOptions& options);
int runCheck(const CheckOptions& options);

}  // namespace voxgi::app

#endif  // VOXGI_APP_CLI_H
