// `voxgi view`: the interactive viewer. A GLFW window (GL 4.5 core) shows the
// renderer's display target at the window's framebuffer size, with a Dear ImGui
// panel on top: the current mode and its knobs, the scene's facts, a per-stage
// frame-time graph, the GL renderer, memory, and the shader hot-reload state.
//
// Per frame: poll input -> scripted keys -> shader reload check (every 250 ms) ->
// fly camera -> renderer.renderFrame(camera) -> blit to the window -> panel ->
// swap. A minimised window (framebuffer 0x0) renders nothing and waits for events;
// a resized one re-creates the render targets; closing the window, Esc, SIGINT or
// SIGTERM end the run cleanly (screenshot and stats still written).
#ifndef VOXGI_APP_VIEWER_H
#define VOXGI_APP_VIEWER_H

#include <string>
#include <vector>

#include "app/viewer_input.h"
#include "render/renderer.h"

namespace voxgi::app {

struct ViewOptions {
  std::string scene;              // empty: the built-in Cornell room
  render::RenderSettings render;  // width x height: the window at start
  int frames = 0;                 // 0: until the window is closed
  std::string screenshot;         // written at the end of the run (see app/screenshot.h)
  std::string screenshotDir;      // where the screenshot key writes; empty: the current folder
  std::vector<ScriptedKey> keys;  // --keys
  std::string stats;              // .json, written at exit
  bool panel = true;
  // --denoise given: otherwise the denoiser starts on only on a hardware GL (on a
  // software one it costs more than the frame budget: docs/rtgi.md, "Denoiser").
  bool denoiseChosen = false;
  // --render-scale given: otherwise rtgi renders at half the window's size on a
  // software GL, where the per-pixel stages alone outlast the frame budget
  // (docs/rtgi.md, "Render scale"), and at its full size on a hardware one.
  bool renderScaleChosen = false;
  bool verbose = false;
  bool quiet = false;
};

int runView(const ViewOptions& options);

}  // namespace voxgi::app

#endif  // VOXGI_APP_VIEWER_H
