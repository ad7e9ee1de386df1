// The viewer's fly camera, free of GL and of the window system: WASD moves in the
// view plane, Q/E along the start camera's up, the mouse turns (yaw about that up,
// pitch kept short of the poles). Speed comes from the scene's bounds
// (scene::AutoScale::cameraSpeed), so a room and a city both take a few seconds
// to cross. Until the first input the camera is exactly the start camera (the
// glTF camera, or the framing one), so the viewer's first frame matches `render`.
// Tested by tests/app/fly_camera_test.cpp.
#ifndef VOXGI_APP_FLY_CAMERA_H
#define VOXGI_APP_FLY_CAMERA_H

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace voxgi::app {

struct FlyInput {
  glm::vec3 move{0.0f};     // x right (D - A), y up (E - Q), z forward (W - S); each in [-1, 1]
  glm::vec2 look{0.0f};     // mouse motion in pixels: x right, y down
  float speedScale = 1.0f;  // e.g. 4 with Shift, 0.25 with Ctrl
};

class FlyCamera {
 public:
  static constexpr float kRadiansPerPixel = 0.003f;
  static constexpr float kMaxPitch = 1.5533430f;  // 89 degrees

  FlyCamera(const scene::Camera& start, const scene::Bounds& bounds, float speed);

  // Advances by `seconds`; returns whether the camera changed.
  bool update(const FlyInput& input, float seconds);
  void reset();
  // Puts the camera at `camera` (the pose of the scene's camera path this frame);
  // the next update() moves on from there, and reset() still returns to the start.
  void jumpTo(const scene::Camera& camera) { camera_ = camera; }

  const scene::Camera& camera() const { return camera_; }
  float speed() const { return speed_; }
  // Angle of the view direction above the horizon (the plane normal to up), radians.
  float pitch() const;

 private:
  scene::Camera start_;
  scene::Camera camera_;
  scene::Bounds bounds_;
  float speed_;
};

}  // namespace voxgi::app

#endif  // VOXGI_APP_FLY_CAMERA_H
