#include "app/viewer.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <deque>
#include <filesystem>
#include <map>

#include <nlohmann/json.hpp>

#include "app/cli.h"
#include "app/fly_camera.h"
#include "app/imgui_layer.h"
#include "app/screenshot.h"
#include "app/stage_report.h"
#include "core/memory.h"
#include "gl/debug.h"
#include "image/image.h"
#include "scene/gltf_loader.h"

namespace voxgi::app {
namespace {

using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

constexpr double kReloadIntervalMs = 250.0;
constexpr double kGraphSeconds = 5.0;
constexpr float kMaxStepSeconds = 0.1f;  // a slow frame must not fling the camera

volatile std::sig_atomic_t gStopSignal = 0;
extern "C" void onStopSignal(int sig) {
  gStopSignal = sig;
}

// SIGINT and SIGTERM end the run like closing the window, for as long as it lives.
class StopSignals {
 public:
  StopSignals() {
    gStopSignal = 0;
    int_ = std::signal(SIGINT, onStopSignal);
    term_ = std::signal(SIGTERM, onStopSignal);
  }
  ~StopSignals() {
    std::signal(SIGINT, int_);
    std::signal(SIGTERM, term_);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

 private:
  void (*int_)(int) = SIG_DFL;
  void (*term_)(int) = SIG_DFL;
};

double msBetween(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// What tells that a file changed: its modification time, and its size, since two
// writes within one tick of the file system's clock (4 ms on Linux at HZ=250) get
// the same time.
struct FileStamp {
  fs::file_time_type time = fs::file_time_type::min();  // min(): missing
  std::uintmax_t size = 0;
  bool operator==(const FileStamp& o) const { return time == o.time && size == o.size; }
};

std::optional<Action> actionForGlfwKey(int key) {
  using K = Action::Kind;
  if (key >= GLFW_KEY_1 && key < GLFW_KEY_1 + kModeSlots) return Action{K::kMode, key - GLFW_KEY_0};
  if (key >= GLFW_KEY_KP_1 && key < GLFW_KEY_KP_1 + kModeSlots)
    return Action{K::kMode, key - GLFW_KEY_KP_0};
  switch (key) {
    case GLFW_KEY_EQUAL:  // the + key without Shift on most layouts
    case GLFW_KEY_KP_ADD:
      return Action{K::kExposureUp};
    case GLFW_KEY_MINUS:
    case GLFW_KEY_KP_SUBTRACT:
      return Action{K::kExposureDown};
    case GLFW_KEY_T:
      return Action{K::kToggleTonemap};
    case GLFW_KEY_R:
      return Action{K::kResetCamera};
    case GLFW_KEY_P:
    case GLFW_KEY_F12:
      return Action{K::kScreenshot};
    case GLFW_KEY_M:
      return Action{K::kToggleMask};
    case GLFW_KEY_N:
      return Action{K::kToggleDenoise};
    case GLFW_KEY_TAB:
    case GLFW_KEY_F1:
      return Action{K::kTogglePanel};
    case GLFW_KEY_ESCAPE:
      return Action{K::kQuit};
    default:
      return std::nullopt;
  }
}

std::string mib(size_t bytes) {
  return strf("%.2f MiB", static_cast<double>(bytes) / (1024.0 * 1024.0));
}

// Scene facts the effect plan is made from (lights by type, emission, textures,
// alpha); the plan itself is the renderer's (scene/effects.h).
struct SceneFacts {
  int directional = 0, point = 0, spot = 0;
  int emissiveMaterials = 0, maskedMaterials = 0, blendedMaterials = 0;
  explicit SceneFacts(const scene::Scene& s) {
    for (const scene::Light& l : s.lights) {
      if (l.type == scene::LightType::kDirectional) ++directional;
      if (l.type == scene::LightType::kPoint) ++point;
      if (l.type == scene::LightType::kSpot) ++spot;
    }
    for (const scene::Material& m : s.materials) {
      if (m.isEmissive()) ++emissiveMaterials;
      if (m.alphaMode == scene::AlphaMode::kMask) ++maskedMaterials;
      if (m.alphaMode == scene::AlphaMode::kBlend) ++blendedMaterials;
    }
  }
};

class Viewer {
 public:
  explicit Viewer(const ViewOptions& o) : options_(o) {}
  int run();

 private:
  struct FrameSample {
    Clock::time_point when;
    double frameMs = 0.0;
    std::vector<gl::StageTime> stages;
  };

  void apply(const Action& a);
  void selectSlot(int slot);
  void checkFiles();
  void checkShaders();
  void checkScene();
  // Returns whether the user moved or turned the camera.
  bool flyCamera(float seconds);
  void animate(double seconds);
  // run()'s steps: refuse bad outputs, load, open the window, start the renderer,
  // loop until an end, then write what was asked for.
  std::optional<ScreenshotPaths> checkOutputs() const;
  void loadScene();
  void openWindow();
  void startRenderer();
  std::string loop();
  // One frame drawn into a w x h window, with its timings recorded.
  void drawFrame(int w, int h);
  int finish(const std::optional<ScreenshotPaths>& named, const std::string& endedBy);

  void drawPanel();
  void drawModes(const render::RenderSettings& rs);
  void drawShaderStatus();
  void drawEffectPlan();
  void drawSceneFacts();
  void drawMemory();
  void drawCamera();
  void drawRunControls();
  void drawKnobs();
  void drawTimings();
  void takeScreenshot(const ScreenshotPaths& paths);
  void writeStats(const std::string& endedBy);

  static void onKey(GLFWwindow* w, int key, int scancode, int action, int mods);

  const ViewOptions& options_;
  std::unique_ptr<gl::Context> context_;
  GLFWwindow* window_ = nullptr;
  std::unique_ptr<scene::Scene> scene_;
  std::unique_ptr<gl::ProgramCache> programs_;
  std::unique_ptr<render::Renderer> renderer_;
  std::unique_ptr<FlyCamera> camera_;
  std::unique_ptr<ImGuiLayer> imgui_;
  std::string scenePath_;
  FileStamp sceneStamp_;  // of the scene on screen

  std::vector<Action> pendingActions_;
  bool panel_ = true;
  int frame_ = 0;  // frames rendered so far
  size_t nextScripted_ = 0;
  Clock::time_point lastReload_, lastFrame_;
  glm::dvec2 lastCursor_{0.0};
  bool looking_ = false;
  // Animation: the scene's clock (seconds, wrapping in Scene::pose), and whether the
  // view follows the file's camera path (until the user flies; r returns to it).
  double animationTime_ = 0.0;
  bool followPath_ = false;

  // What the panel and the stats report.
  std::string modeMessage_;
  std::vector<std::string> unavailableRequests_;
  int modeSwitches_ = 0;
  int resizes_ = 0;
  int reloadsOk_ = 0, reloadsFailed_ = 0;
  std::string shaderError_, lastReloadError_;
  int sceneReloadsOk_ = 0, sceneReloadsFailed_ = 0;
  std::string sceneError_;
  std::vector<std::string> screenshots_;
  std::deque<FrameSample> history_;
  StageTimes times_;
};

void Viewer::onKey(GLFWwindow* w, int key, int, int action, int) {
  auto* self = static_cast<Viewer*>(glfwGetWindowUserPointer(w));
  if (!self || action == GLFW_RELEASE) return;
  if (self->imgui_ && self->imgui_->wantsKeyboard()) return;
  const auto a = actionForGlfwKey(key);
  if (!a) return;
  const bool repeats =
      a->kind == Action::Kind::kExposureUp || a->kind == Action::Kind::kExposureDown;
  if (action == GLFW_REPEAT && !repeats) return;
  self->pendingActions_.push_back(*a);
}

void Viewer::selectSlot(int slot) {
  const char* name = modeForSlot(slot);
  const auto mode = name ? render::parseMode(name) : std::nullopt;
  if (!mode) {
    modeMessage_ = strf("key %d: %s is not in this build (available: %s)", slot,
                        name ? name : "reserved slot", render::availableModes().c_str());
    unavailableRequests_.push_back(name ? name : "reserved");
    logWarning(strf("view: frame %d: %s", frame_, modeMessage_.c_str()));
    return;
  }
  ++modeSwitches_;
  renderer_->setMode(*mode);
  modeMessage_.clear();
  logInfo(strf("view: frame %d: mode %s", frame_, render::modeName(*mode)));
}

void Viewer::apply(const Action& a) {
  using K = Action::Kind;
  switch (a.kind) {
    case K::kMode:
      selectSlot(a.slot);
      break;
    case K::kExposureUp:
    case K::kExposureDown: {
      render::TonemapPass::Settings t = renderer_->tonemapSettings();
      t.exposure = stepExposure(t.exposure, a.kind == K::kExposureUp ? 1 : -1);
      renderer_->setTonemapSettings(t);
      logInfo(strf("view: frame %d: exposure %g", frame_, t.exposure));
      break;
    }
    case K::kToggleTonemap: {
      render::TonemapPass::Settings t = renderer_->tonemapSettings();
      t.op = t.op == render::Tonemap::kClamp ? render::Tonemap::kAces : render::Tonemap::kClamp;
      renderer_->setTonemapSettings(t);
      logInfo(strf("view: frame %d: tonemap %s", frame_, render::tonemapName(t.op)));
      break;
    }
    case K::kResetCamera:
      camera_->reset();
      if (scene_->cameraMoves && !followPath_) {
        followPath_ = true;
        logInfo(strf("view: frame %d: camera follows the scene's camera path", frame_));
      }
      break;
    case K::kScreenshot:
      // The frame on screen is the last one rendered; with none yet, render first.
      if (frame_ == 0) renderer_->renderFrame(camera_->camera());
      takeScreenshot(nextScreenshotPaths(options_.screenshotDir, std::time(nullptr)));
      break;
    case K::kToggleMask:
      renderer_->setShowMask(!renderer_->showMask());
      logInfo(strf("view: frame %d: work mask %s", frame_, renderer_->showMask() ? "on" : "off"));
      break;
    case K::kToggleDenoise:
      if (renderer_->rtgi()) {
        renderer_->setDenoise(!renderer_->rtgi()->settings().denoise);
        logInfo(strf("view: frame %d: denoiser %s", frame_,
                     renderer_->rtgi()->settings().denoise ? "on" : "off"));
      }
      break;
    case K::kTogglePanel:
      panel_ = !panel_;
      break;
    case K::kQuit:
      glfwSetWindowShouldClose(window_, GLFW_TRUE);
      break;
  }
}

void Viewer::checkFiles() {
  const auto now = Clock::now();
  if (msBetween(lastReload_, now) < kReloadIntervalMs) return;
  lastReload_ = now;
  checkScene();
  checkShaders();
}

FileStamp fileStamp(const std::string& path) {
  std::error_code ec;
  FileStamp stamp;
  const fs::file_time_type t = fs::last_write_time(path, ec);
  if (ec) return stamp;
  stamp.time = t;
  const std::uintmax_t size = fs::file_size(path, ec);
  stamp.size = ec ? 0 : size;
  return stamp;
}

// The scene file changed on disk, or went away: load it again. A file that loads
// replaces the scene and keeps the view (camera, mode, size, tonemap); one that
// does not leaves the last good scene on screen, with the error in the log, the
// panel and the stats. Each change is tried once (a half-written file is tried
// again when the write completes and its time or size changes).
void Viewer::checkScene() {
  const FileStamp stamp = fileStamp(scenePath_);
  if (stamp == sceneStamp_) return;
  sceneStamp_ = stamp;
  try {
    auto fresh = std::make_unique<scene::Scene>(scene::loadGltf(scenePath_));
    fresh->loopAnimation = true;  // playback loops
    fresh->pose(animationTime_);
    auto renderer = std::make_unique<render::Renderer>(*programs_, *fresh, renderer_->settings());
    renderer->setTonemapSettings(renderer_->tonemapSettings());
    renderer_ = std::move(renderer);  // the old renderer goes before the scene it reads
    scene_ = std::move(fresh);
    followPath_ = followPath_ && scene_->cameraMoves;
    ++sceneReloadsOk_;
    sceneError_.clear();
    logInfo(strf("view: frame %d: reloaded the scene (%zu triangles)", frame_,
                 scene_->triangleCount()));
  } catch (const Error& e) {
    ++sceneReloadsFailed_;
    sceneError_ = e.what();
    logInfo(strf("view: frame %d: scene reload failed, the last good scene stays: %s", frame_,
                 e.what()));
  }
}

void Viewer::checkShaders() {
  const gl::ProgramCache::ReloadReport r = programs_->reloadChanged();
  if (r.rebuilt == 0 && r.failed == 0) return;
  reloadsOk_ += r.rebuilt;
  reloadsFailed_ += r.failed;
  if (r.failed > 0) {
    shaderError_ = r.error;
    lastReloadError_ = r.error;
    logInfo(strf("view: frame %d: shader reload failed, the last good program keeps running: %s",
                 frame_, r.error.c_str()));
  } else {
    shaderError_.clear();
    logInfo(strf("view: frame %d: reloaded %d program(s)", frame_, r.rebuilt));
  }
  if (r.rebuilt > 0) renderer_->restartAccumulation();
}

// Animated scenes play in real time: meshes, lights and the camera path.
void Viewer::animate(double seconds) {
  if (!scene_->animated()) return;
  animationTime_ += seconds;
  scene_->pose(animationTime_);
  renderer_->posed();
  if (followPath_) camera_->jumpTo(scene_->camera);
}

bool Viewer::flyCamera(float seconds) {
  FlyInput in;
  const bool keyboard = !imgui_->wantsKeyboard();
  auto down = [&](int key) { return keyboard && glfwGetKey(window_, key) == GLFW_PRESS; };
  in.move.x = static_cast<float>(down(GLFW_KEY_D)) - static_cast<float>(down(GLFW_KEY_A));
  in.move.y = static_cast<float>(down(GLFW_KEY_E)) - static_cast<float>(down(GLFW_KEY_Q));
  in.move.z = static_cast<float>(down(GLFW_KEY_W)) - static_cast<float>(down(GLFW_KEY_S));
  if (down(GLFW_KEY_LEFT_SHIFT) || down(GLFW_KEY_RIGHT_SHIFT)) in.speedScale = 4.0f;
  if (down(GLFW_KEY_LEFT_CONTROL) || down(GLFW_KEY_RIGHT_CONTROL)) in.speedScale = 0.25f;
  // Mouse look while the right button is held, or the left one outside the panel.
  glm::dvec2 cursor;
  glfwGetCursorPos(window_, &cursor.x, &cursor.y);
  const bool right = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
  const bool left = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
  const bool look = right || (left && (looking_ || !imgui_->wantsMouse()));
  if (look && looking_) in.look = glm::vec2(cursor - lastCursor_);
  looking_ = look;
  lastCursor_ = cursor;
  return camera_->update(in, seconds);
}

void Viewer::takeScreenshot(const ScreenshotPaths& paths) {
  const int w = renderer_->settings().width, h = renderer_->settings().height;
  const auto display = renderer_->readDisplay();
  image::writePng(paths.png, w, h, display.data());
  const auto linear = renderer_->readLinear();
  image::writeExr(paths.exr, w, h, linear.data());
  screenshots_.push_back(paths.png);
  screenshots_.push_back(paths.exr);
  logInfo(strf("view: wrote %s and %s (%dx%d)", paths.png.c_str(), paths.exr.c_str(), w, h));
}

void Viewer::drawKnobs() {
  for (render::Knob& k : renderer_->knobs()) {
    switch (k.kind) {
      case render::Knob::Kind::kFloat: {
        float v = static_cast<float>(k.get());
        if (ImGui::SliderFloat(k.label.c_str(), &v, static_cast<float>(k.min),
                               static_cast<float>(k.max), "%.3f",
                               k.logarithmic ? ImGuiSliderFlags_Logarithmic : 0))
          k.set(v);
        break;
      }
      case render::Knob::Kind::kInt: {
        int v = static_cast<int>(k.get());
        if (ImGui::SliderInt(k.label.c_str(), &v, static_cast<int>(k.min), static_cast<int>(k.max)))
          k.set(v);
        break;
      }
      case render::Knob::Kind::kChoice: {
        int v = static_cast<int>(k.get());
        std::vector<const char*> items;
        for (const std::string& c : k.choices) items.push_back(c.c_str());
        if (ImGui::Combo(k.label.c_str(), &v, items.data(), static_cast<int>(items.size())))
          k.set(v);
        break;
      }
    }
    if (!k.help.empty() && ImGui::IsItemHovered()) ImGui::SetTooltip("%s", k.help.c_str());
  }
}

void Viewer::drawTimings() {
  if (history_.empty()) return;
  // One plot per stage plus the whole frame, on a shared scale.
  std::vector<Stage> stages;
  std::vector<std::string> names;
  for (const gl::StageTime& s : history_.back().stages) {
    stages.push_back(s.stage);
    names.push_back(stageName(s.stage));
  }
  float top = 1.0f;
  std::vector<std::vector<float>> series(names.size() + 1);
  for (const FrameSample& f : history_) {
    series.back().push_back(static_cast<float>(f.frameMs));
    top = std::max(top, static_cast<float>(f.frameMs));
    for (size_t i = 0; i < stages.size(); ++i) {
      float v = 0.0f;
      for (const gl::StageTime& s : f.stages)
        if (s.stage == stages[i]) v = static_cast<float>(s.gpuMs);
      series[i].push_back(v);
    }
  }
  names.push_back("frame (wall)");
  ImGui::Text("last %.0f s, 0 .. %.1f ms", kGraphSeconds, top);
  ImGui::PushItemWidth(-1.0f);
  for (size_t i = 0; i < names.size(); ++i) {
    const std::string overlay = strf("%s %.2f ms", names[i].c_str(), series[i].back());
    ImGui::PlotLines(("##" + names[i]).c_str(), series[i].data(),
                     static_cast<int>(series[i].size()), 0, overlay.c_str(), 0.0f, top,
                     ImVec2(0.0f, 36.0f));
  }
  ImGui::PopItemWidth();
}

void Viewer::drawModes(const render::RenderSettings& rs) {
  for (int slot = 1; slot <= kModeSlots; ++slot) {
    const char* name = modeForSlot(slot);
    const auto mode = name ? render::parseMode(name) : std::nullopt;
    const std::string label =
        strf("%d %s%s", slot, name ? name : "reserved", mode ? "" : "  (not in this build)");
    if (!mode) ImGui::BeginDisabled();
    if (ImGui::RadioButton(label.c_str(), mode && *mode == rs.mode)) selectSlot(slot);
    if (!mode) ImGui::EndDisabled();
  }
  if (!modeMessage_.empty())
    ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.3f, 1.0f), "%s", modeMessage_.c_str());
}

void Viewer::drawShaderStatus() {
  ImGui::TextWrapped("%s: %zu programs", programs_->root().string().c_str(), programs_->size());
  ImGui::Text("reloads: %d ok, %d failed", reloadsOk_, reloadsFailed_);
  if (!shaderError_.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.4f, 0.4f, 1.0f));
    ImGui::TextWrapped("%s", shaderError_.c_str());
    ImGui::PopStyleColor();
    ImGui::TextDisabled("the last good program keeps running");
  }
}

void Viewer::drawEffectPlan() {
  const scene::EffectPlan& plan = renderer_->effects();
  for (scene::Effect e : scene::kEffects) {
    auto skip = plan.skipped.find(e);
    if (skip == plan.skipped.end())
      ImGui::Text("on   %s", scene::effectName(e));
    else
      ImGui::TextDisabled("off  %s: %s", scene::effectName(e), skip->second.c_str());
  }
  ImGui::TextDisabled("--effects +name,-name overrides; pathtrace renders every effect");
}

void Viewer::drawSceneFacts() {
  const scene::Scene& s = *scene_;
  const SceneFacts f(s);
  ImGui::TextDisabled("what the effect plan is derived from");
  ImGui::Text("%zu triangles, %zu materials, %zu textures", s.triangleCount(), s.materials.size(),
              s.textures.size());
  ImGui::Text("lights: %d directional, %d point, %d spot%s", f.directional, f.point, f.spot,
              s.defaultLight ? " (default light added)" : "");
  ImGui::Text("emissive materials: %d (%d emitter groups)", f.emissiveMaterials,
              renderer_->gpuScene().emitterCount());
  ImGui::Text("alpha: %d masked, %d blended materials", f.maskedMaterials, f.blendedMaterials);
  const glm::vec3 e = s.bounds.extent();
  ImGui::Text("bounds %.3g x %.3g x %.3g", e.x, e.y, e.z);
}

void Viewer::drawMemory() {
  ImGui::Text("process peak resident: %s", mib(peakResidentBytes()).c_str());
  ImGui::Text("GPU scene: %s", mib(renderer_->gpuScene().bytes()).c_str());
  if (const render::GpuBvh* bvh = renderer_->bvh())
    ImGui::Text("GPU BVH and hit shading: %s (%zu triangles)", mib(bvh->gpuBytes()).c_str(),
                bvh->triangleCount());
  const render::Renderer::TextureMemory tm = renderer_->textureMemory();
  ImGui::Text("textures: %s on the GPU, %s on the CPU", mib(tm.gpu()).c_str(),
              mib(tm.cpu()).c_str());
  ImGui::Text("render targets: %s", mib(renderer_->targetBytes()).c_str());
  if (const voxel::VoxelizePass* grid = renderer_->voxelGrid()) {
    const voxel::VoxelGridStats& v = grid->stats();
    ImGui::Text("voxel grid %d^3: %u occupied, %s resident, %s while voxelizing", v.resolution,
                v.occupied, mib(v.bytes).c_str(), mib(v.peakBytes).c_str());
  } else {
    ImGui::Text("voxel structures: none (no mode used so far reads voxels)");
  }
}

void Viewer::drawCamera() {
  const scene::Camera& c = camera_->camera();
  ImGui::Text("position %.3g %.3g %.3g", c.position.x, c.position.y, c.position.z);
  ImGui::Text("forward %.3f %.3f %.3f", c.forward.x, c.forward.y, c.forward.z);
  ImGui::Text("speed %.3g units/s (Shift x4, Ctrl x1/4)", camera_->speed());
  ImGui::TextDisabled("WASD move, Q/E down/up, right mouse look, r reset");
  if (scene_->cameraMoves)
    ImGui::Text(followPath_ ? "following the file's camera path (flying leaves it)"
                            : "free camera (r returns to the camera path)");
}

// Animation clock, frame budget, work mask, denoiser and the screenshot button.
void Viewer::drawRunControls() {
  if (scene_->animated())
    ImGui::Text("animation %.2f s of %.2f s",
                std::fmod(animationTime_, std::max(scene_->animationDuration, 1e-9)),
                scene_->animationDuration);
  if (renderer_->settings().mode == render::Mode::kRtgi) {
    const glm::ivec2 internal = renderer_->internalSize();
    ImGui::Text("render scale %.2f: %dx%d", static_cast<double>(renderer_->settings().renderScale),
                internal.x, internal.y);
    if (renderer_->rtgi())
      ImGui::Text("primary visibility: %s",
                  renderer_->rtgi()->primaryRays() ? "rays (BVH)" : "raster");
  }
  if (renderer_->settings().targetFps > 0.0 && renderer_->rtgi()) {
    ImGui::Text("budget %.1f fps: tracing %.1f%% of pixels", renderer_->settings().targetFps,
                100.0 * renderer_->rtgi()->lastTracedFraction());
    bool show = renderer_->showMask();
    if (ImGui::Checkbox("show work mask (m)", &show)) renderer_->setShowMask(show);
  }
  if (renderer_->rtgi()) {
    bool denoise = renderer_->rtgi()->settings().denoise;
    if (ImGui::Checkbox("denoise (n)", &denoise)) renderer_->setDenoise(denoise);
  }
  if (ImGui::Button("Screenshot (p)")) pendingActions_.push_back({Action::Kind::kScreenshot});
  if (!screenshots_.empty()) {
    ImGui::SameLine();
    ImGui::TextDisabled("%s", fs::path(screenshots_.back()).filename().string().c_str());
  }
}

void Viewer::drawPanel() {
  ImGui::SetNextWindowPos(ImVec2(8.0f, 8.0f), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(360.0f, 0.0f), ImGuiCond_FirstUseEver);
  // Never taller than the window, so nothing is out of reach (it scrolls instead).
  const float maxHeight = std::max(ImGui::GetIO().DisplaySize.y - 16.0f, 100.0f);
  ImGui::SetNextWindowSizeConstraints(ImVec2(200.0f, 100.0f), ImVec2(4096.0f, maxHeight));
  ImGui::Begin("voxgi view (tab hides)");
  const render::RenderSettings& rs = renderer_->settings();
  ImGui::TextWrapped("%s", context_->renderer().c_str());
  ImGui::Text("GL %s, glfw", context_->version().c_str());
  const double lastMs = history_.empty() ? 0.0 : history_.back().frameMs;
  ImGui::Text("%dx%d, %.1f ms per frame", rs.width, rs.height, lastMs);
  ImGui::Text("frame %d, %d accumulated", frame_ + 1, renderer_->accumulatedFrames());

  if (ImGui::CollapsingHeader("Mode (keys 1-6)", ImGuiTreeNodeFlags_DefaultOpen)) drawModes(rs);
  if (ImGui::CollapsingHeader("Knobs", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::Text("size %dx%d (follows the window)", rs.width, rs.height);
    drawKnobs();
    ImGui::TextDisabled("keys: + - exposure, t tonemap");
  }
  if (ImGui::CollapsingHeader("Frame time per stage (GPU)", ImGuiTreeNodeFlags_DefaultOpen))
    drawTimings();
  if (ImGui::CollapsingHeader("Shaders (hot reload)", ImGuiTreeNodeFlags_DefaultOpen))
    drawShaderStatus();
  if (!sceneError_.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.4f, 0.4f, 1.0f));
    ImGui::TextWrapped("%s", sceneError_.c_str());
    ImGui::PopStyleColor();
    ImGui::TextDisabled("the last good scene stays");
  }
  if (ImGui::CollapsingHeader("Effect plan", ImGuiTreeNodeFlags_DefaultOpen)) drawEffectPlan();
  if (ImGui::CollapsingHeader("Scene facts")) drawSceneFacts();
  if (ImGui::CollapsingHeader("Memory")) drawMemory();
  if (ImGui::CollapsingHeader("Camera")) drawCamera();
  drawRunControls();
  ImGui::End();
}

void Viewer::writeStats(const std::string& endedBy) {
  const render::RenderSettings& rs = renderer_->settings();
  nlohmann::ordered_json stats = statsHeaderJson(
      {"view", scenePath_, render::modeName(rs.mode), rs.width, rs.height,
       gl::backendName(context_->backend()), context_->renderer(), context_->version()});
  stats["frames"] = frame_;
  stats["ended_by"] = endedBy;
  stats["frame_ms"] = times_.frameMedian();
  stats["stages"] = times_.json();
  stats["exposure"] = rs.tonemap.exposure;
  stats["tonemap"] = render::tonemapName(rs.tonemap.op);
  stats["resizes"] = resizes_;
  stats["mode_switches"] = modeSwitches_;
  stats["unavailable_mode_requests"] = unavailableRequests_;
  stats["shader_root"] = programs_->root().string();
  stats["reloads_ok"] = reloadsOk_;
  stats["reloads_failed"] = reloadsFailed_;
  stats["last_reload_error"] = lastReloadError_;
  stats["scene_reloads_ok"] = sceneReloadsOk_;
  stats["scene_reloads_failed"] = sceneReloadsFailed_;
  stats["scene_error"] = sceneError_;
  stats["screenshots"] = screenshots_;
  std::map<std::string, std::string> skipped;  // by name, so in name order
  for (const auto& [effect, reason] : renderer_->effects().skipped)
    skipped[scene::effectName(effect)] = reason;
  stats["effects"] = {{"enabled", renderer_->effects().enabledNames()}, {"skipped", skipped}};
  stats["peak_rss_bytes"] = peakResidentBytes();
  stats["gpu_scene_bytes"] = renderer_->gpuScene().bytes();
  if (const render::GpuBvh* bvh = renderer_->bvh()) stats["gpu_bvh_bytes"] = bvh->gpuBytes();
  stats["texture_bytes"] = {{"gpu", renderer_->textureMemory().gpu()},
                            {"cpu", renderer_->textureMemory().cpu()}};
  stats["animated"] = scene_->animated();
  if (scene_->animated()) {
    stats["animation_time"] = animationTime_;
    stats["camera_path"] = scene_->cameraMoves;
    stats["following_camera_path"] = followPath_;
  }
  stats["gl_errors"] = gl::debugErrorCount();
  image::writeText(options_.stats, stats.dump(2) + "\n");
}

// Everything that can be refused without a window is refused first.
std::optional<ScreenshotPaths> Viewer::checkOutputs() const {
  std::optional<ScreenshotPaths> named;
  if (!options_.screenshot.empty()) {
    named = screenshotPathsFor(options_.screenshot);
    image::checkWritable(named->png);
    image::checkWritable(named->exr);
  }
  if (!options_.screenshotDir.empty() && !fs::is_directory(options_.screenshotDir))
    throw Error(options_.screenshotDir + ": not a folder (--screenshot-dir)");
  if (!options_.stats.empty()) image::checkWritable(options_.stats);
  return named;
}

void Viewer::loadScene() {
  scenePath_ = options_.scene.empty() ? defaultScenePath() : options_.scene;
  sceneStamp_ = fileStamp(scenePath_);
  scene_ = std::make_unique<scene::Scene>(scene::loadGltf(scenePath_));
  scene_->loopAnimation = true;  // playback loops
}

void Viewer::openWindow() {
  // X11 keeps a window's sides in 16 bits and truncates larger ones instead of
  // refusing them (the software rasterizer then fails at the first swap, in Xlib);
  // no GL here renders a side over 16384 anyway. Refused before any window opens;
  // sizes within it meet the renderer's memory check.
  constexpr int kMaxWindowSide = 16384;
  if (options_.render.width > kMaxWindowSide || options_.render.height > kMaxWindowSide)
    throw Error(strf("--size %dx%d: larger than the %dx%d window limit", options_.render.width,
                     options_.render.height, kMaxWindowSide, kMaxWindowSide));

  gl::ContextOptions co;
  co.backend = gl::Backend::kGlfw;
  co.width = options_.render.width;
  co.height = options_.render.height;
  co.visible = true;
  co.title = "voxgi view - " + fs::path(scenePath_).filename().string();
  context_ = gl::Context::create(co);
  window_ = static_cast<GLFWwindow*>(context_->nativeWindow());
  glfwSwapInterval(1);
}

// The renderer at the window's size, the fly camera, the key callback and the panel.
void Viewer::startRenderer() {
  render::RenderSettings settings = options_.render;
  glfwGetFramebufferSize(window_, &settings.width, &settings.height);
  settings.width = std::max(settings.width, 1);
  settings.height = std::max(settings.height, 1);
  // Interactive: a path-traced frame adds one sample per pixel to the image while
  // nothing changes, instead of a whole image of --spp samples per frame.
  settings.progressive = true;
  settings.spp = 1;
  settings.voxelChecksum = false;  // not shown
  const char* glRenderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const bool denoiseOff = !options_.denoiseChosen && settings.rtgi.denoise &&
                          render::isSoftwareRenderer(glRenderer ? glRenderer : "");
  if (denoiseOff) settings.rtgi.denoise = false;
  if (!options_.renderScaleChosen)
    settings.renderScale =
        render::isSoftwareRenderer(glRenderer ? glRenderer : "") ? kSoftwareRenderScale : 1.0f;
  programs_ = std::make_unique<gl::ProgramCache>(shaderRoot());
  renderer_ = std::make_unique<render::Renderer>(*programs_, *scene_, settings);
  logInfo("effects: " + renderer_->effects().summary());
  if (denoiseOff)
    logInfo(
        "view: rtgi's denoiser starts off on a software renderer (it costs more than a "
        "frame); n turns it on");
  camera_ = std::make_unique<FlyCamera>(scene_->camera, scene_->bounds, scene_->scale.cameraSpeed);
  followPath_ = scene_->cameraMoves;

  // Our key callback first; the ImGui backend chains to it after its own.
  glfwSetWindowUserPointer(window_, this);
  glfwSetKeyCallback(window_, &Viewer::onKey);
  imgui_ = std::make_unique<ImGuiLayer>(window_);
  panel_ = options_.panel;
  logInfo(strf("view: %s in a %dx%d window on %s; mode %s", scenePath_.c_str(), settings.width,
               settings.height, context_->renderer().c_str(),
               render::modeName(options_.render.mode)));
}

// Frames until a signal, the window closing or --frames; returns which ended it.
std::string Viewer::loop() {
  lastReload_ = lastFrame_ = Clock::now();
  while (true) {
    if (gStopSignal) return "signal";
    if (context_->shouldClose()) return "window";
    if (options_.frames > 0 && frame_ >= options_.frames) return "frames";
    glfwPollEvents();
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    if (w <= 0 || h <= 0) {  // minimised: nothing to draw into
      glfwWaitEventsTimeout(0.1);
      lastFrame_ = Clock::now();
      continue;
    }
    if (w != renderer_->settings().width || h != renderer_->settings().height) {
      renderer_->resize(w, h);
      ++resizes_;
      logInfo(strf("view: frame %d: resized to %dx%d", frame_, w, h));
    }
    while (nextScripted_ < options_.keys.size() && options_.keys[nextScripted_].frame <= frame_ + 1)
      pendingActions_.push_back(options_.keys[nextScripted_++].action);
    for (const Action& a : std::exchange(pendingActions_, {})) apply(a);
    if (context_->shouldClose()) return "window";
    checkFiles();
    drawFrame(w, h);
  }
}

void Viewer::drawFrame(int w, int h) {
  const auto start = Clock::now();
  const double elapsed = msBetween(lastFrame_, start) * 1e-3;
  const float seconds = std::min(static_cast<float>(elapsed), kMaxStepSeconds);
  lastFrame_ = start;
  imgui_->beginFrame();
  // The first frame shows the first pose (t = 0), as `render` does.
  if (frame_ > 0) animate(elapsed);
  if (flyCamera(seconds) && followPath_) {
    followPath_ = false;
    logInfo(strf("view: frame %d: free camera (r returns to the camera path)", frame_));
  }
  renderer_->renderFrame(camera_->camera());
  glBlitNamedFramebuffer(renderer_->displayFramebuffer(), 0, 0, 0, w, h, 0, 0, w, h,
                         GL_COLOR_BUFFER_BIT, GL_NEAREST);
  if (panel_) drawPanel();
  imgui_->endFrame();
  context_->swapBuffers();
  ++frame_;

  const double ms = msBetween(start, Clock::now());
  times_.add(ms, renderer_->lastStages());
  history_.push_back({start, ms, renderer_->lastStages()});
  while (msBetween(history_.front().when, start) > kGraphSeconds * 1000.0) history_.pop_front();
  if (frame_ == 1) {
    pauseHugePages(false);  // started: the frames want them (core/memory.h)
    logInfo(strf("view: first frame in %.1f ms", ms));
  }
}

// The screenshot and stats asked for, the summary line, and the exit status.
int Viewer::finish(const std::optional<ScreenshotPaths>& named, const std::string& endedBy) {
  if (named) {
    if (frame_ == 0) renderer_->renderFrame(camera_->camera());
    takeScreenshot(*named);
  }
  if (!options_.stats.empty()) writeStats(endedBy);
  const int glErrors = gl::debugErrorCount();
  if (!options_.quiet) {
    std::printf("view: %d frames (ended by %s), median %.1f ms; shader reloads %d ok, %d failed\n",
                frame_, endedBy.c_str(), times_.frameMedian(), reloadsOk_, reloadsFailed_);
    if (!options_.stats.empty()) std::printf("wrote %s\n", options_.stats.c_str());
  }
  imgui_.reset();
  if (glErrors > 0) {
    logError(
        strf("%d GL error(s) during the run; first: %s", glErrors, gl::lastDebugError().c_str()));
    return 1;
  }
  return 0;
}

int Viewer::run() {
  const std::optional<ScreenshotPaths> named = checkOutputs();
  loadScene();
  openWindow();
  startRenderer();
  std::optional<StopSignals> signals(std::in_place);
  const std::string endedBy = loop();
  signals.reset();
  return finish(named, endedBy);
}

}  // namespace

int runView(const ViewOptions& options) {
  if (options.verbose) setLogLevel(LogLevel::kDebug);
  if (options.quiet) setLogLevel(LogLevel::kError);
  Viewer viewer(options);
  return viewer.run();
}

}  // namespace voxgi::app
