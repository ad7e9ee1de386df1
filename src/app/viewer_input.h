// What the viewer's keys do, free of GL and of the window system, so that the
// scripted form (`voxgi view --keys "10:2,20:+"`) and the keyboard share one table.
//   1..6   mode slot: 1 raster, 2 points, 3 dvr, 4 rtgi, 5 pathtrace, 6 reserved
//   + -    exposure up / down half a stop          t    tonemap operator clamp <-> aces
//   r      camera back to the start                p    screenshot (PNG + EXR)
//   tab    panel on / off                          esc  quit
//   m      show the rtgi work mask (with --target-fps) instead of the image
//   n      rtgi denoiser on / off (--denoise)
// Tested by tests/app/viewer_input_test.cpp.
#ifndef VOXGI_APP_VIEWER_INPUT_H
#define VOXGI_APP_VIEWER_INPUT_H

#include <optional>
#include <string>
#include <vector>

namespace voxgi::app {

constexpr int kModeSlots = 6;
// The mode name behind slot 1..6 in the fixed documented order, whether or not this
// build has it; null for the reserved slot 6.
const char* modeForSlot(int slot);

struct Action {
  enum class Kind {
    kMode,
    kExposureUp,
    kExposureDown,
    kToggleTonemap,
    kResetCamera,
    kScreenshot,
    kTogglePanel,
    kToggleMask,
    kToggleDenoise,
    kQuit
  };
  Kind kind = Kind::kMode;
  int slot = 0;  // kMode: 1..6
  bool operator==(const Action&) const = default;
};

// "1".."6", "+", "-", "t", "r", "p", "m", "n", "tab", "esc"; nullopt for anything else.
std::optional<Action> actionForKeyName(const std::string& name);
std::string keyName(const Action& a);

// Exposure after one step up or down: half a stop, i.e. a factor of 2^(1/2).
float stepExposure(float exposure, int halfStops);

struct ScriptedKey {
  int frame = 0;  // 1-based: applied before frame `frame` is rendered
  Action action;
};
// Parses "FRAME:KEY[,FRAME:KEY...]" (frames ascending or not; sorted, stable).
// Throws voxgi::Error naming the bad entry.
std::vector<ScriptedKey> parseKeyScript(const std::string& script);

}  // namespace voxgi::app

#endif  // VOXGI_APP_VIEWER_INPUT_H
