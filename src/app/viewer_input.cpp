#include "app/viewer_input.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "core/log.h"

namespace voxgi::app {

const char* modeForSlot(int slot) {
  static const char* const kNames[kModeSlots] = {"raster", "points",    "dvr",
                                                 "rtgi",   "pathtrace", nullptr};
  return slot >= 1 && slot <= kModeSlots ? kNames[slot - 1] : nullptr;
}

std::optional<Action> actionForKeyName(const std::string& name) {
  using K = Action::Kind;
  if (name.size() == 1 && name[0] >= '1' && name[0] <= '0' + kModeSlots)
    return Action{K::kMode, name[0] - '0'};
  if (name == "+") return Action{K::kExposureUp};
  if (name == "-") return Action{K::kExposureDown};
  if (name == "t") return Action{K::kToggleTonemap};
  if (name == "r") return Action{K::kResetCamera};
  if (name == "p") return Action{K::kScreenshot};
  if (name == "m") return Action{K::kToggleMask};
  if (name == "n") return Action{K::kToggleDenoise};
  if (name == "tab") return Action{K::kTogglePanel};
  if (name == "esc") return Action{K::kQuit};
  return std::nullopt;
}

std::string keyName(const Action& a) {
  switch (a.kind) {
    case Action::Kind::kMode:
      return std::to_string(a.slot);
    case Action::Kind::kExposureUp:
      return "+";
    case Action::Kind::kExposureDown:
      return "-";
    case Action::Kind::kToggleTonemap:
      return "t";
    case Action::Kind::kResetCamera:
      return "r";
    case Action::Kind::kScreenshot:
      return "p";
    case Action::Kind::kToggleMask:
      return "m";
    case Action::Kind::kToggleDenoise:
      return "n";
    case Action::Kind::kTogglePanel:
      return "tab";
    case Action::Kind::kQuit:
      return "esc";
  }
  return "?";
}

float stepExposure(float exposure, int halfStops) {
  // In stops, rounded to the half stop, so that + then - returns exactly.
  const float stops = std::round(2.0f * std::log2(exposure)) * 0.5f;
  return std::exp2(stops + 0.5f * static_cast<float>(halfStops));
}

std::vector<ScriptedKey> parseKeyScript(const std::string& script) {
  std::vector<ScriptedKey> out;
  size_t pos = 0;
  while (pos <= script.size()) {
    const size_t comma = std::min(script.find(',', pos), script.size());
    const std::string entry = script.substr(pos, comma - pos);
    pos = comma + 1;
    if (entry.empty()) {
      if (comma == script.size() && !out.empty()) break;
      throw Error("--keys: empty entry in '" + script + "' (expected FRAME:KEY,...)");
    }
    const size_t colon = entry.find(':');
    if (colon == std::string::npos)
      throw Error("--keys: '" + entry + "' is not FRAME:KEY (e.g. 10:2)");
    int frame = 0;
    const char* first = entry.data();
    const char* last = entry.data() + colon;
    const auto r = std::from_chars(first, last, frame);
    if (r.ec != std::errc() || r.ptr != last || frame < 1)
      throw Error("--keys: '" + entry + "': the frame must be a whole number from 1");
    const std::string key = entry.substr(colon + 1);
    const auto action = actionForKeyName(key);
    if (!action)
      throw Error("--keys: '" + entry + "': unknown key '" + key +
                  "' (1-6, +, -, t, r, p, m, tab, esc)");
    out.push_back({frame, *action});
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const ScriptedKey& a, const ScriptedKey& b) { return a.frame < b.frame; });
  return out;
}

}  // namespace voxgi::app
