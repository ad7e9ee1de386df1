#include "app/stage_report.h"

#include "core/log.h"
#include "core/statistics.h"

namespace voxgi::app {

void StageTimes::add(double frameMs, const std::vector<gl::StageTime>& stages) {
  frameMs_.push_back(frameMs);
  for (const gl::StageTime& s : stages) {
    if (!stageMs_.count(s.stage)) order_.push_back(s.stage);
    stageMs_[s.stage].push_back(s.gpuMs);
  }
}

double StageTimes::frameMedian() const {
  return voxgi::median(frameMs_);
}

double StageTimes::median(Stage stage) const {
  auto it = stageMs_.find(stage);
  return it == stageMs_.end() ? 0.0 : voxgi::median(it->second);
}

nlohmann::ordered_json StageTimes::json() const {
  nlohmann::ordered_json stages = nlohmann::ordered_json::object();
  for (Stage s : order_) stages[stageName(s)] = median(s);
  return stages;
}

std::string StageTimes::table(const std::string& timingMethod) const {
  std::string out = strf("  %-10s %10s   (%s)\n", "stage", "ms", timingMethod.c_str());
  for (Stage s : order_) out += strf("  %-10s %10.2f\n", stageName(s), median(s));
  return out;
}

std::string StageTimes::columnHeads() const {
  std::string out;
  for (Stage s : order_) out += strf(" %10s", stageName(s));
  return out;
}

std::string StageTimes::columnMedians() const {
  std::string out;
  for (Stage s : order_) out += strf(" %10.1f", median(s));
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
