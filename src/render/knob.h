// A setting a pass exposes to an interactive front end (the viewer's panel) without
// depending on any UI library: a label, a kind, a range, and get/set functions.
// A pass lists its knobs in appendKnobs(); the renderer collects those of the
// current mode and the tonemap, so a new mode brings its own controls with it.
#ifndef VOXGI_RENDER_KNOB_H
#define VOXGI_RENDER_KNOB_H

#include <functional>
#include <string>
#include <vector>

namespace voxgi::render {

struct Knob {
  enum class Kind { kFloat, kInt, kChoice };
  std::string label;
  Kind kind = Kind::kFloat;
  double min = 0.0;  // kFloat, kInt
  double max = 1.0;
  bool logarithmic = false;          // kFloat: a slider in log space (exposure, step sizes)
  std::vector<std::string> choices;  // kChoice: get/set use the index
  std::string help;                  // one line, shown as a tooltip
  std::function<double()> get;
  std::function<void(double)> set;
};

}  // namespace voxgi::render

#endif  // VOXGI_RENDER_KNOB_H
