#include "scene/scene.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "core/log.h"
#include "scene/emitters.h"
#include "scene_shared.h"

namespace voxgi::scene {

TextureTransform textureTransform(glm::vec2 offset, float rotation, glm::vec2 scale) {
  // T * R * S with R = [cos sin; -sin cos] (the extension's matrix; its rows are
  // u' and v'). Columns: R * S's, then the offset.
  const float c = std::cos(rotation), s = std::sin(rotation);
  TextureTransform t;
  t.columns[0] = glm::vec2(c, -s) * scale.x;
  t.columns[1] = glm::vec2(s, c) * scale.y;
  t.columns[2] = offset;
  return t;
}

float Bounds::diagonal() const {
  return empty() ? 0.0f : glm::length(max - min);
}

glm::mat4 Camera::view() const {
  return glm::lookAt(position, position + forward, up);
}

glm::mat4 Camera::projection(float aspect) const {
  // glm's [0, 1]-depth projection with the planes swapped puts the near one at 1.
  return glm::perspectiveRH_ZO(yfov, aspect, zfar, znear);
}

bool Scene::hasEmission() const {
  for (const Draw& d : draws)
    if (materials[static_cast<size_t>(d.material)].isEmissive()) return true;
  return false;
}

bool Scene::hasSecondUv() const {
  for (const Draw& d : draws)
    if (materials[static_cast<size_t>(d.material)].hasUv2) return true;
  return false;
}

void Scene::finalize() {
  bounds = Bounds{};
  for (const Vertex& v : vertices) bounds.extend(v.position);
  if (!motionBounds.empty()) {
    bounds.extend(motionBounds.min);
    bounds.extend(motionBounds.max);
  }
  if (bounds.empty()) {  // nothing to draw: a unit box around the origin
    bounds.min = glm::vec3(-1.0f);
    bounds.max = glm::vec3(1.0f);
  }
  const float diag = std::max(bounds.diagonal(), 1e-30f);
  scale.cameraSpeed = 0.25f * diag;
  const Bounds grid = voxelBounds();
  const float side = std::max({grid.extent().x, grid.extent().y, grid.extent().z, diag * 1e-3f});
  scale.gridSize = side * 1.02f;  // 1% margin on each side
  scale.gridOrigin = grid.center() - glm::vec3(0.5f * scale.gridSize);
  if (!camera.fromFile) autoFrameCamera();
  fitClipPlanes();
}

// The voxel grid spends its resolution where the scene has detail. A few huge
// triangles (a ground plane of 20 m under objects of 2 m) would otherwise spread the
// grid thin: the grid covers the bounds, clipped to a cube twice the size of the
// small triangles' bounds around their centre. Large triangles are those above 1%
// of the bounds' largest face. Outside the grid rays simply escape: a far floor
// gets its direct light unshadowed, which is what nothing there could shadow.
Bounds Scene::voxelBounds() const {
  const glm::vec3 e = bounds.extent();
  const float largestFace = std::max({e.x * e.y, e.y * e.z, e.x * e.z});
  Bounds detail;
  for (size_t i = 0; i + 2 < indices.size(); i += 3) {
    const glm::vec3 a = vertices[indices[i]].position;
    const glm::vec3 b = vertices[indices[i + 1]].position;
    const glm::vec3 c = vertices[indices[i + 2]].position;
    if (0.5f * glm::length(glm::cross(b - a, c - a)) > 0.01f * largestFace) continue;
    detail.extend(a);
    detail.extend(b);
    detail.extend(c);
  }
  if (!motionBounds.empty()) {
    detail.extend(motionBounds.min);
    detail.extend(motionBounds.max);
  }
  if (detail.empty()) return bounds;
  const glm::vec3 de = detail.extent();
  const float half = std::max({de.x, de.y, de.z});  // the cube is twice the detail's size
  Bounds out;
  out.min = glm::max(bounds.min, detail.center() - glm::vec3(half));
  out.max = glm::min(bounds.max, detail.center() + glm::vec3(half));
  return out;
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

void Scene::lookAt(const glm::vec3& from, const glm::vec3& at) {
  camera.position = from - glm::vec3(origin);
  camera.forward = glm::normalize(at - from);
  camera.up = std::abs(camera.forward.y) > 0.999f ? glm::vec3(0.0f, 0.0f, -1.0f)
                                                  : glm::vec3(0.0f, 1.0f, 0.0f);
  fitClipPlanes();
  poseCamera = false;  // the viewpoint stays put; meshes and lights still move
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

float Scene::emittedLightPerArea() const {
  double emitted = 0.0;
  double area = 0.0;
  for (const Draw& d : draws) {
    const Material& m = materials[static_cast<size_t>(d.material)];
    for (size_t t = 0; t < d.indexCount / 3; ++t) {
      const size_t i = d.firstIndex + t * 3;
      const glm::vec3 a = vertices[indices[i]].position;
      const glm::vec3 b = vertices[indices[i + 1]].position;
      const glm::vec3 c = vertices[indices[i + 2]].position;
      const double triangleArea = 0.5 * static_cast<double>(glm::length(glm::cross(b - a, c - a)));
      area += triangleArea;
      if (!m.isEmissive()) continue;
      const glm::vec3 L = triangleEmission(*this, d, t);
      const double luminance = 0.2126 * L.x + 0.7152 * L.y + 0.0722 * L.z;
      emitted += 3.14159265358979 * luminance * triangleArea * (m.doubleSided ? 2.0 : 1.0);
    }
  }
  return area > 0.0 ? static_cast<float>(emitted / area) : 0.0f;
}

void Scene::addDefaultLightIfUnlit() {
  if (!lights.empty()) return;
  const float emitted = hasEmission() ? emittedLightPerArea() : 0.0f;
  if (emitted >= kLitByEmitters) return;
  Light l;
  l.type = LightType::kDirectional;
  l.name = "default";
  l.intensity = 3.0f;
  l.direction = glm::normalize(glm::vec3(-0.3f, -1.0f, -0.5f));
  lights.push_back(l);
  defaultLight = true;
  logInfo(hasEmission()
              ? strf("%s: no light, and its emitters are too faint to light it (%.3g per unit "
                     "area, below %.3g); added a default directional light",
                     path.c_str(), static_cast<double>(emitted),
                     static_cast<double>(kLitByEmitters))
              : path + ": the scene has no light; added a default directional light");
}

namespace {

glm::dvec4 sample(const AnimationChannel& c, double t) {
  const std::vector<float>& k = c.times;
  const float key = static_cast<float>(t);  // compared in the keys' precision
  if (key <= k.front()) return c.values.front();
  if (key >= k.back()) return c.values.back();
  const size_t i = static_cast<size_t>(std::upper_bound(k.begin(), k.end(), key) - k.begin()) - 1;
  if (c.interpolation == Interpolation::kStep || i + 1 >= k.size()) return c.values[i];
  const double span = static_cast<double>(k[i + 1]) - k[i];
  const double u = span > 0.0 ? (t - k[i]) / span : 0.0;
  if (c.interpolation == Interpolation::kCubicSpline) {
    // glTF 2.0, Appendix C: the Hermite basis, tangents scaled by the interval; a
    // rotation is normalized by pose().
    const double u2 = u * u, u3 = u2 * u;
    return (2.0 * u3 - 3.0 * u2 + 1.0) * c.values[i] +
           span * (u3 - 2.0 * u2 + u) * c.outTangents[i] +
           (-2.0 * u3 + 3.0 * u2) * c.values[i + 1] + span * (u3 - u2) * c.inTangents[i + 1];
  }
  if (c.path == AnimationPath::kRotation) {
    const glm::dvec4 a = c.values[i], b = c.values[i + 1];
    const glm::dquat q =
        glm::slerp(glm::dquat(a.w, a.x, a.y, a.z), glm::dquat(b.w, b.x, b.y, b.z), u);
    return glm::dvec4(q.x, q.y, q.z, q.w);
  }
  return glm::mix(c.values[i], c.values[i + 1], u);
}

glm::dmat4 localTransform(const SceneNode& n) {
  if (n.hasMatrix) return n.matrix;
  return glm::translate(glm::dmat4(1.0), n.translation) * glm::mat4_cast(n.rotation) *
         glm::scale(glm::dmat4(1.0), n.scale);
}

}  // namespace

void Scene::preparePose() {
  PoseChains& pc = poseChains;
  const size_t n = nodes.size();
  pc.animatedSlot.assign(n, -1);
  pc.animatedNodes.clear();
  for (const AnimationChannel& c : animations) {
    int& slot = pc.animatedSlot[static_cast<size_t>(c.node)];
    if (slot >= 0) continue;
    slot = static_cast<int>(pc.animatedNodes.size());
    pc.animatedNodes.push_back(c.node);
  }
  // From the roots down, each node once, its parent before it (the graph is a
  // forest: the loader refused cycles).
  std::vector<std::vector<int>> children(n);
  std::vector<int> pending;
  for (size_t i = 0; i < n; ++i) {
    const int p = nodes[i].parent;
    if (p >= 0)
      children[static_cast<size_t>(p)].push_back(static_cast<int>(i));
    else
      pending.push_back(static_cast<int>(i));
  }
  pc.anchor.assign(n, -1);
  pc.still.assign(n, glm::dmat4(1.0));
  while (!pending.empty()) {
    const auto i = static_cast<size_t>(pending.back());
    pending.pop_back();
    const int p = nodes[i].parent;
    if (pc.animatedSlot[i] >= 0) {
      pc.anchor[i] = static_cast<int>(i);  // composed at each pose; nothing still below it yet
    } else {
      const glm::dmat4 local = localTransform(nodes[i]);
      pc.anchor[i] = p >= 0 ? pc.anchor[static_cast<size_t>(p)] : -1;
      pc.still[i] = p >= 0 ? pc.still[static_cast<size_t>(p)] * local : local;
    }
    for (int c : children[i]) pending.push_back(c);
  }
}

bool Scene::lightsAnimated() const {
  return std::any_of(lights.begin(), lights.end(), [](const Light& l) { return l.moves; });
}

void Scene::pose(double seconds) {
  if (!animated()) return;
  double t = seconds;
  // Looping, a time past the end (in the keys' precision) wraps around; the end
  // itself shows the last pose. Otherwise sample() holds the first and last keys.
  if (loopAnimation && animationDuration > 0.0 &&
      (static_cast<float>(t) > static_cast<float>(animationDuration) || t < 0.0)) {
    t = std::fmod(t, animationDuration);
    if (t < 0.0) t += animationDuration;
  }
  if (poseChains.anchor.size() != nodes.size()) preparePose();
  const PoseChains& pc = poseChains;
  // The animated nodes' transforms at t; every other node keeps its own.
  std::vector<SceneNode> posed(pc.animatedNodes.size());
  for (size_t k = 0; k < posed.size(); ++k)
    posed[k] = nodes[static_cast<size_t>(pc.animatedNodes[k])];
  for (const AnimationChannel& c : animations) {
    const glm::dvec4 v = sample(c, t);
    SceneNode& n = posed[static_cast<size_t>(pc.animatedSlot[static_cast<size_t>(c.node)])];
    if (c.path == AnimationPath::kTranslation) n.translation = glm::dvec3(v);
    if (c.path == AnimationPath::kScale) n.scale = glm::dvec3(v);
    if (c.path == AnimationPath::kRotation)
      n.rotation = glm::normalize(glm::dquat(v.w, v.x, v.y, v.z));
  }
  // World matrices on demand. A node's is its anchor's times the still transforms
  // below it; an animated node's, its parent's times its posed local transform.
  // Each animated node's is composed once: those not yet composed are gathered
  // walking up from anchor to anchor, then composed walking down (no recursion: a
  // valid hierarchy may be tens of thousands of levels deep).
  std::vector<glm::dmat4> animatedWorld(posed.size());
  std::vector<char> done(posed.size(), 0);
  std::vector<int> chain;
  auto anchorWorld = [&](int a) -> const glm::dmat4& {
    chain.clear();
    for (int u = a;
         u >= 0 && !done[static_cast<size_t>(pc.animatedSlot[static_cast<size_t>(u)])];) {
      chain.push_back(u);
      const int parent = nodes[static_cast<size_t>(u)].parent;
      u = parent >= 0 ? pc.anchor[static_cast<size_t>(parent)] : -1;
    }
    for (auto u = chain.rbegin(); u != chain.rend(); ++u) {
      const auto slot = static_cast<size_t>(pc.animatedSlot[static_cast<size_t>(*u)]);
      const int parent = nodes[static_cast<size_t>(*u)].parent;
      glm::dmat4 above(1.0);
      if (parent >= 0) {
        const int pa = pc.anchor[static_cast<size_t>(parent)];
        above = pa >= 0
                    ? animatedWorld[static_cast<size_t>(pc.animatedSlot[static_cast<size_t>(pa)])] *
                          pc.still[static_cast<size_t>(parent)]
                    : pc.still[static_cast<size_t>(parent)];
      }
      animatedWorld[slot] = above * localTransform(posed[slot]);
      done[slot] = 1;
    }
    return animatedWorld[static_cast<size_t>(pc.animatedSlot[static_cast<size_t>(a)])];
  };
  auto worldOf = [&](int i) -> glm::dmat4 {
    const int a = pc.anchor[static_cast<size_t>(i)];
    return a >= 0 ? anchorWorld(a) * pc.still[static_cast<size_t>(i)]
                  : pc.still[static_cast<size_t>(i)];
  };
  for (const AnimatedRange& r : animatedRanges) {
    const glm::dmat4 m = worldOf(r.node);
    const glm::mat3 normalMatrix = glm::mat3(glm::transpose(glm::inverse(glm::dmat3(m))));
    for (size_t i = 0; i < r.localPositions.size(); ++i) {
      Vertex& v = vertices[r.firstVertex + i];
      v.position = glm::vec3(glm::dvec3(m * glm::dvec4(r.localPositions[i], 1.0)) - origin);
      const glm::vec3 n = normalMatrix * r.localNormals[i];
      const float len = glm::length(n);
      v.normal = len > 0.0f ? n / len : glm::vec3(0.0f, 1.0f, 0.0f);
      if (!r.localTangents.empty()) {
        const glm::vec4 lt = r.localTangents[i];
        const glm::vec3 wt = glm::mat3(m) * glm::vec3(lt);
        const float tl = glm::length(wt);
        tangents[r.firstVertex + i] =
            glm::vec4(tl > 0.0f ? wt / tl : glm::vec3(1.0f, 0.0f, 0.0f),
                      glm::determinant(glm::dmat3(m)) < 0.0 ? -lt.w : lt.w);
      }
    }
  }
  // Lights and the camera as the loader places them: at the node's origin, looking
  // (shining) along its -z, the camera's up along its +y. A degenerate pose (a scale
  // of 0 on the way) keeps the previous direction.
  auto direction = [](const glm::dvec3& d, const glm::vec3& previous) {
    const double len = glm::length(d);
    return len > 0.0 && std::isfinite(len) ? glm::vec3(d / len) : previous;
  };
  for (Light& l : lights) {
    if (!l.moves) continue;
    const glm::dmat4 m = worldOf(l.node);
    l.position = glm::vec3(glm::dvec3(m[3]) - origin);
    l.direction = direction(-glm::dvec3(m[2]), l.direction);
  }
  if (cameraMoves && poseCamera) {
    const glm::dmat4 m = worldOf(camera.node);
    camera.position = glm::vec3(glm::dvec3(m[3]) - origin);
    camera.forward = direction(-glm::dvec3(m[2]), camera.forward);
    camera.up = direction(glm::dvec3(m[1]), camera.up);
    if (!bounds.empty()) fitClipPlanes();
  }
}

uint32_t Texture::tableFlags() const {
  auto wrap = [](int w) {
    return w == kWrapClampToEdge      ? gpu::kTextureClampToEdge
           : w == kWrapMirroredRepeat ? gpu::kTextureMirroredRepeat
                                      : gpu::kTextureRepeat;
  };
  return (srgb ? gpu::kTextureSrgb : 0u) |
         (magFilter == kFilterNearest ? gpu::kTextureNearest : 0u) |
         (wrap(wrapS) << gpu::kTextureWrapSShift) | (wrap(wrapT) << gpu::kTextureWrapTShift);
}

}  // namespace voxgi::scene
