#include "app/stage_report.h"

#include "core/log.h"
#include "core/statistics.h"

namespace voxgi::app {

void StageTimes::add(double frameMs, const std::vector<gl::StageTime>& stages) {
  frameMs_.push_back(frameMs);
  for (const gl::StageTime& s : stages) {
    if (!stageMs_.count(s.name)) order_.push_back(s.name);
    stageMs_[s.name].push_back(s.gpuMs);
  }
}

double StageTimes::frameMedian() const {
  return voxgi::median(frameMs_);
}

double StageTimes::median(const std::string& stage) const {
  auto it = stageMs_.find(stage);
  return it == stageMs_.end() ? 0.0 : voxgi::median(it->second);
}

nlohmann::ordered_json StageTimes::json() const {
  nlohmann::ordered_json stages = nlohmann::ordered_json::object();
  for (const std::string& name : order_) stages[name] = median(name);
  return stages;
}

std::string StageTimes::table(const std::string& timingMethod) const {
  std::string out = strf("  %-10s %10s   (%s)\n", "stage", "ms", timingMethod.c_str());
  for (const std::string& name : order_)
    out += strf("  %-10s %10.2f\n", name.c_str(), median(name));
  return out;
}

std::string StageTimes::columnHeads() const {
  std::string out;
  for (const std::string& name : order_) out += strf(" %10s", name.c_str());
  return out;
}

std::string StageTimes::columnMedians() const {
  std::string out;
  for (const std::string& name : order_) out += strf(" %10.1f", median(name));
  return out;
}

nlohmann::ordered_json statsHeaderJson(const StatsHeader& h) {
  nlohmann::ordered_json out;
  out["voxgi_version"] = VOXGI_VERSION;
  if (!h.command.empty()) out["command"] = h.command;
  out["scene"] = h.scene;
  out["mode"] = h.mode;
  out["size"] = {{"width", h.width}, {"height", h.height}};
  out["backend"] = h.backend;
  out["renderer"] = h.renderer;
  out["gl_version"] = h.glVersion;
  return out;
}

}  // namespace voxgi::app
