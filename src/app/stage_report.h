// Per-stage timings of a run of frames, and the parts of the stats file and the
// console table that `render`, `bench` and `view` share.
#ifndef VOXGI_APP_STAGE_REPORT_H
#define VOXGI_APP_STAGE_REPORT_H

#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gl/stage_timer.h"

namespace voxgi::app {

// Each frame's wall-clock time and each stage's GPU time, stages in the order
// they were first seen; reports medians, as the machines are noisy. Stages are
// written by their names (stageName) in the JSON, the table and the columns.
class StageTimes {
 public:
  void add(double frameMs, const std::vector<gl::StageTime>& stages);

  const std::vector<double>& frameMs() const { return frameMs_; }
  double frameMedian() const;
  const std::vector<Stage>& order() const { return order_; }
  bool has(Stage stage) const { return stageMs_.count(stage) > 0; }
  double median(Stage stage) const;

  // {"stage": median GPU ms, ...} in first-seen order.
  nlohmann::ordered_json json() const;
  // One line per stage, "  name  ms", below a heading that names the timing method.
  std::string table(const std::string& timingMethod) const;
  // Stage names, then medians, as columns of a row per run (`bench`).
  std::string columnHeads() const;
  std::string columnMedians() const;

 private:
  std::vector<double> frameMs_;
  std::map<Stage, std::vector<double>> stageMs_;
  std::vector<Stage> order_;
};

// What a stats file says first: which build ran which scene, how and where.
struct StatsHeader {
  std::string command;  // empty: not written
  std::string scene;
  std::string mode;
  int width = 0, height = 0;
  std::string backend, renderer, glVersion;
};
nlohmann::ordered_json statsHeaderJson(const StatsHeader& h);

}  // namespace voxgi::app

#endif  // VOXGI_APP_STAGE_REPORT_H
