#include "scene/scene.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "core/log.h"

namespace voxgi::scene {

float Bounds::diagonal() const {
  return empty() ? 0.0f : glm::length(max - min);
}

glm::mat4 Camera::view() const {
  return glm::lookAt(position, position + forward, up);
}

glm::mat4 Camera::projection(float aspect) const {
  return glm::perspective(yfov, aspect, znear, zfar);
}

bool Scene::hasEmission() const {
  for (const Draw& d : draws)
    if (materials[static_cast<size_t>(d.material)].isEmissive()) return true;
  return false;
}

void Scene::finalize() {
  bounds = Bounds{};
  for (const Vertex& v : vertices) bounds.extend(v.position);
  if (bounds.empty()) {  // nothing to draw: a unit box around the origin
    bounds.min = glm::vec3(-1.0f);
    bounds.max = glm::vec3(1.0f);
  }
  const float diag = std::max(bounds.diagonal(), 1e-30f);
  scale.cameraSpeed = 0.25f * diag;
  const float side =
      std::max({bounds.extent().x, bounds.extent().y, bounds.extent().z, diag * 1e-3f});
  scale.gridSize = side * 1.02f;  // 1% margin on each side
  scale.gridOrigin = bounds.center() - glm::vec3(0.5f * scale.gridSize);
  if (!camera.fromFile) autoFrameCamera();
  fitClipPlanes();
}

void Scene::autoFrameCamera() {
  const glm::vec3 c = bounds.center();
  const float radius = 0.5f * std::max(bounds.diagonal(), 1e-30f);
  const float dist = radius / std::sin(0.5f * camera.yfov);
  camera.position = c + glm::vec3(0.0f, 0.0f, dist);
  camera.forward = glm::vec3(0.0f, 0.0f, -1.0f);
  camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
}

void Scene::fitClipPlanes() {
  scene::fitClipPlanes(&camera, bounds);
}

void fitClipPlanes(Camera* camera, const Bounds& bounds) {
  const float diag = std::max(bounds.diagonal(), 1e-30f);
  const glm::vec3 closest = glm::clamp(camera->position, bounds.min, bounds.max);
  const float toBox = glm::length(closest - camera->position);
  const float toFar = glm::length(bounds.center() - camera->position) + diag;
  camera->zfar = toFar * 1.01f;
  // Near plane as far out as the geometry allows; keeps the depth ratio <= 1e5.
  camera->znear = std::max(0.5f * toBox, camera->zfar * 1e-5f);
  camera->znear = std::min(camera->znear, camera->zfar * 0.5f);
}

void Scene::addDefaultLightIfUnlit() {
  if (!lights.empty() || hasEmission()) return;
  Light l;
  l.type = LightType::kDirectional;
  l.name = "default";
  l.intensity = 3.0f;
  l.direction = glm::normalize(glm::vec3(-0.3f, -1.0f, -0.5f));
  lights.push_back(l);
  defaultLight = true;
  logInfo(path + ": the scene has no light; added a default directional light");
}

}  // namespace voxgi::scene
