#include "app/fly_camera.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/quaternion.hpp>

namespace voxgi::app {

FlyCamera::FlyCamera(const scene::Camera& start, const scene::Bounds& bounds, float speed)
    : start_(start), camera_(start), bounds_(bounds), speed_(speed) {}

float FlyCamera::pitch() const {
  const float s = glm::dot(glm::normalize(camera_.forward), glm::normalize(camera_.up));
  return std::asin(std::clamp(s, -1.0f, 1.0f));
}

bool FlyCamera::update(const FlyInput& in, float seconds) {
  const bool moves = in.move != glm::vec3(0.0f) && seconds > 0.0f;
  const bool turns = in.look != glm::vec2(0.0f);
  if (!moves && !turns) return false;
  const glm::vec3 up = glm::normalize(camera_.up);
  glm::vec3 forward = glm::normalize(camera_.forward);
  if (turns) {
    // Yaw about up (mouse right turns right), then pitch about the camera's right
    // (mouse down looks down), clamped so forward never reaches up or down.
    const float yaw = -in.look.x * kRadiansPerPixel;
    forward = glm::angleAxis(yaw, up) * forward;
    const float current = pitch();
    const float target = std::clamp(current - in.look.y * kRadiansPerPixel, -kMaxPitch, kMaxPitch);
    const glm::vec3 right = glm::normalize(glm::cross(forward, up));
    forward = glm::normalize(glm::angleAxis(target - current, right) * forward);
  }
  camera_.forward = forward;
  if (moves) {
    const glm::vec3 right = glm::normalize(glm::cross(forward, up));
    const glm::vec3 step = right * in.move.x + up * in.move.y + forward * in.move.z;
    camera_.position += step * (speed_ * in.speedScale * seconds);
    scene::fitClipPlanes(&camera_, bounds_);
  }
  return true;
}

void FlyCamera::reset() {
  camera_ = start_;
}

}  // namespace voxgi::app
