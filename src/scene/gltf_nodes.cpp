// The glTF loader: nodes and their transforms, animation, the traversal of the
// scene, cameras, lights, and what is read with a warning or not at all.
#include "scene/gltf_loader_impl.h"

namespace voxgi::scene::gltf_detail {

namespace {

// How a file renders without an optional extension voxgi does not implement.
std::string renderedWithout(const std::string& extension) {
  if (extension == "KHR_draco_mesh_compression" || extension == "EXT_meshopt_compression")
    return "the uncompressed geometry is drawn";
  if (extension == "KHR_texture_basisu" || extension == "EXT_texture_webp" ||
      extension == "EXT_texture_avif")
    return "textures read their PNG or JPEG source";
  if (extension == "KHR_materials_variants") return "the default materials are drawn";
  if (extension == "EXT_mesh_gpu_instancing") return "each mesh is drawn once, at its node";
  if (extension.find("_materials_") != std::string::npos) return "materials render without it";
  if (extension.find("_lights_") != std::string::npos) return "its lights are not drawn";
  return "the file renders without it";
}

}  // namespace

void Loader::readNodesAndAnimations() {
  readNodes();
  const size_t n = model_.nodes.size();
  std::vector<char> animated(n, 0);
  for (size_t a = 0; a < model_.animations.size(); ++a) {
    const auto& anim = model_.animations[a];
    for (size_t ci = 0; ci < anim.channels.size(); ++ci) {
      const std::string where = strf("animation %zu channel %zu", a, ci);
      if (anim.channels[ci].target_path == "weights") {
        ignored_.weightChannels.add(where);
        continue;
      }
      AnimationChannel c = readChannel(anim, anim.channels[ci], where);
      scene_.animationDuration =
          std::max(scene_.animationDuration, static_cast<double>(c.times.back()));
      animated[static_cast<size_t>(c.node)] = 1;
      scene_.animations.push_back(std::move(c));
    }
  }
  // A node moves if it or an ancestor is animated (the graph is a forest here):
  // marked from the roots down, each node once, its parent before it.
  moving_.assign(n, 0);
  std::vector<size_t> pending;
  for (size_t i = 0; i < n; ++i)
    if (scene_.nodes[i].parent < 0) pending.push_back(i);
  while (!pending.empty()) {
    const size_t i = pending.back();
    pending.pop_back();
    const int p = scene_.nodes[i].parent;
    moving_[i] = animated[i] || (p >= 0 && moving_[static_cast<size_t>(p)]);
    for (int c : model_.nodes[i].children) pending.push_back(static_cast<size_t>(c));
  }
}

// Parents and local transforms: a matrix, or translation, rotation and scale.
void Loader::readNodes() {
  const size_t n = model_.nodes.size();
  scene_.nodes.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const auto& node = model_.nodes[i];
    SceneNode& sn = scene_.nodes[i];
    for (int c : node.children) scene_.nodes[static_cast<size_t>(c)].parent = static_cast<int>(i);
    if (!node.matrix.empty()) {
      sn.hasMatrix = true;
      sn.matrix = localMatrix(node, static_cast<int>(i));
      continue;
    }
    if (node.translation.size() == 3)
      sn.translation = glm::dvec3(node.translation[0], node.translation[1], node.translation[2]);
    if (node.rotation.size() == 4)
      sn.rotation = glm::normalize(
          glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]));
    if (node.scale.size() == 3) sn.scale = glm::dvec3(node.scale[0], node.scale[1], node.scale[2]);
  }
}

// A translation, rotation or scale channel, its target node and sampler checked.
AnimationChannel Loader::readChannel(const tinygltf::Animation& anim,
                                     const tinygltf::AnimationChannel& ch,
                                     const std::string& where) {
  AnimationChannel c;
  if (ch.target_path == "translation")
    c.path = AnimationPath::kTranslation;
  else if (ch.target_path == "rotation")
    c.path = AnimationPath::kRotation;
  else if (ch.target_path == "scale")
    c.path = AnimationPath::kScale;
  else
    fail(where + ": unknown target path '" + ch.target_path + "'");
  if (ch.target_node < 0 || static_cast<size_t>(ch.target_node) >= model_.nodes.size())
    fail(strf("%s: node %d does not exist", where.c_str(), ch.target_node));
  if (scene_.nodes[static_cast<size_t>(ch.target_node)].hasMatrix)
    fail(strf("%s: node %d has a matrix and cannot be animated", where.c_str(), ch.target_node));
  if (ch.sampler < 0 || static_cast<size_t>(ch.sampler) >= anim.samplers.size())
    fail(strf("%s: sampler %d does not exist", where.c_str(), ch.sampler));
  const auto& sampler = anim.samplers[static_cast<size_t>(ch.sampler)];
  c.node = ch.target_node;
  if (sampler.interpolation == "STEP") c.interpolation = Interpolation::kStep;
  if (sampler.interpolation == "CUBICSPLINE") c.interpolation = Interpolation::kCubicSpline;
  readKeyframes(sampler, where, &c);
  return c;
}

// The sampler's keyframe times and values into c; a cubic spline's output holds
// (in-tangent, value, out-tangent) per keyframe.
void Loader::readKeyframes(const tinygltf::AnimationSampler& sampler, const std::string& where,
                           AnimationChannel* c) {
  const bool cubic = c->interpolation == Interpolation::kCubicSpline;
  const View in = accessor(sampler.input, "animation input", {TINYGLTF_TYPE_SCALAR},
                           {TINYGLTF_COMPONENT_TYPE_FLOAT});
  const int type = c->path == AnimationPath::kRotation ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3;
  const View out =
      accessor(sampler.output, "animation output", {type}, {TINYGLTF_COMPONENT_TYPE_FLOAT});
  const size_t per = cubic ? 3 : 1;
  if (out.count != in.count * per) fail(where + ": input and output counts differ");
  const auto element = [&](size_t i) {
    const unsigned char* q = out.data + i * out.stride;
    glm::dvec4 v(0.0);
    for (int comp = 0; comp < (type == TINYGLTF_TYPE_VEC4 ? 4 : 3); ++comp)
      v[comp] = readComponent(q + 4 * static_cast<size_t>(comp), out.componentType, false);
    if (!std::isfinite(v.x + v.y + v.z + v.w)) fail(where + ": NaN or Inf keyframe value");
    return v;
  };
  for (size_t k = 0; k < in.count; ++k) {
    const float t = readComponent(in.data + k * in.stride, in.componentType, false);
    if (!std::isfinite(t) || (k > 0 && t < c->times.back()))
      fail(where + ": keyframe times must be finite and increasing");
    c->times.push_back(t);
    c->values.push_back(element(k * per + (cubic ? 1 : 0)));
    if (!cubic) continue;
    c->inTangents.push_back(element(k * per));
    c->outTangents.push_back(element(k * per + 2));
  }
}

// The bounds cover every pose: sampled at each keyframe and 64 steps between.
void Loader::boundMotion() {
  std::vector<double> times;
  for (const AnimationChannel& c : scene_.animations)
    times.insert(times.end(), c.times.begin(), c.times.end());
  for (int k = 0; k <= 64; ++k) times.push_back(scene_.animationDuration * k / 64.0);
  for (double t : times) {
    scene_.pose(t);
    for (const AnimatedRange& r : scene_.animatedRanges)
      for (size_t i = 0; i < r.localPositions.size(); ++i)
        scene_.motionBounds.extend(scene_.vertices[r.firstVertex + i].position);
  }
}

// Transforms are composed in double precision: a scene placed 10^4 units from
// the origin keeps its detail (positions are stored relative to Scene::origin).
glm::dmat4 Loader::localMatrix(const tinygltf::Node& node, int index) const {
  glm::dmat4 m(1.0);
  auto checked = [&](const std::vector<double>& v, const std::string& what) {
    for (double x : v) toFloat(x, what);  // refuses NaN, Inf and beyond-float values
    return glm::dvec3(v[0], v[1], v[2]);
  };
  if (!node.matrix.empty()) {
    if (node.matrix.size() != 16) fail(strf("node %d: matrix must have 16 numbers", index));
    for (int i = 0; i < 16; ++i) {
      toFloat(node.matrix[static_cast<size_t>(i)], strf("node %d: matrix", index));
      glm::value_ptr(m)[i] = node.matrix[static_cast<size_t>(i)];
    }
  } else {
    if (node.translation.size() == 3)
      m = glm::translate(m, checked(node.translation, strf("node %d: translation", index)));
    if (node.rotation.size() == 4) {
      const std::string what = strf("node %d: rotation", index);
      for (double x : node.rotation) toFloat(x, what);
      glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
      if (!(glm::length(q) > 0.0)) fail(what + ": zero quaternion");
      m = m * glm::mat4_cast(glm::normalize(q));
    }
    if (node.scale.size() == 3)
      m = glm::scale(m, checked(node.scale, strf("node %d: scale", index)));
  }
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) fail(strf("node %d: transform has NaN or Inf", index));
  return m;
}

void Loader::traverse() {
  std::vector<int> roots;
  if (!model_.scenes.empty()) {
    const size_t s = model_.defaultScene >= 0 ? static_cast<size_t>(model_.defaultScene) : 0;
    roots = model_.scenes[s].nodes;
  } else {
    // Valid glTF: with no scenes, every root node (no node's child) is drawn.
    std::vector<bool> child(model_.nodes.size(), false);
    for (const auto& n : model_.nodes)
      for (int c : n.children) child[static_cast<size_t>(c)] = true;
    for (size_t i = 0; i < model_.nodes.size(); ++i)
      if (!child[i]) roots.push_back(static_cast<int>(i));
    note_(strf("no scenes: rendering all %s (the nodes that are no node's child)",
               countOf(roots.size(), "root node", "root nodes").c_str()));
  }
  // Depth first, each node's children in order, on a stack of its own: a valid
  // hierarchy may be tens of thousands of levels deep.
  struct Pending {
    int node;
    glm::dmat4 parent;
  };
  std::vector<Pending> pending;
  for (auto r = roots.rbegin(); r != roots.rend(); ++r) pending.push_back({*r, glm::dmat4(1.0)});
  while (!pending.empty()) {
    const Pending next = pending.back();
    pending.pop_back();
    const int index = next.node;
    const auto& node = model_.nodes[static_cast<size_t>(index)];
    const glm::dmat4 world = next.parent * localMatrix(node, index);
    if (node.mesh != -1) {
      if (node.mesh < 0 || static_cast<size_t>(node.mesh) >= model_.meshes.size())
        fail(strf("node %d: mesh %d does not exist", index, node.mesh));
      if (node.skin != -1) ignored_.skinned.add(strf("nodes[%d]", index));
      addMesh(node.mesh, index, world);
    }
    if (node.camera != -1) addCamera(node.camera, index, world);
    auto le = node.extensions.find("KHR_lights_punctual");
    if (le != node.extensions.end() && le->second.Has("light"))
      addLight(le->second.Get("light").GetNumberAsInt(), index, world);
    for (auto c = node.children.rbegin(); c != node.children.rend(); ++c)
      pending.push_back({*c, world});
  }
  applyOrigin();
  dropDegenerateInFloat();
}

// A triangle can have area in double precision and none in the float positions
// the GPU gets (corners a few ulps apart, or collinear up to rounding): its normal
// there, normalize(cross(e1, e2)), would be NaN or rounding noise. Such triangles
// (the float cross product below the float range, or under 1e-6 of |e1| |e2|: an
// angle under ~1e-6 rad) are dropped from static draws; animated ones are re-posed
// every frame and keep theirs.
void Loader::dropDegenerateInFloat() {
  std::vector<uint32_t> indices;
  std::vector<Draw> draws;
  indices.reserve(scene_.indices.size());
  for (size_t di = 0; di < scene_.draws.size(); ++di) {
    Draw d = scene_.draws[di];
    const bool moving = moving_[static_cast<size_t>(d.node)] != 0;
    const auto first = static_cast<uint32_t>(indices.size());
    size_t degenerate = 0;
    for (uint32_t i = d.firstIndex; i < d.firstIndex + d.indexCount; i += 3) {
      const uint32_t a = scene_.indices[i], b = scene_.indices[i + 1], c = scene_.indices[i + 2];
      if (!moving && degenerateInFloat(scene_.vertices[a].position, scene_.vertices[b].position,
                                       scene_.vertices[c].position)) {
        ++degenerate;
        continue;
      }
      indices.insert(indices.end(), {a, b, c});
    }
    if (degenerate) {
      dropped_ += degenerate;
      if (std::find(droppedIn_.begin(), droppedIn_.end(), drawWhere_[di]) == droppedIn_.end())
        droppedIn_.push_back(drawWhere_[di]);
    }
    d.firstIndex = first;
    d.indexCount = static_cast<uint32_t>(indices.size()) - first;
    if (d.indexCount > 0) draws.push_back(d);
  }
  scene_.indices.swap(indices);
  scene_.draws.swap(draws);
}

bool Loader::degenerateInFloat(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  const glm::vec3 e1 = b - a, e2 = c - a;
  const glm::vec3 n = glm::cross(e1, e2);
  const float n2 = glm::dot(n, n);
  if (!(n2 >= std::numeric_limits<float>::min()) || !std::isfinite(n2)) return true;
  const double bound =
      1e-12 * static_cast<double>(glm::dot(e1, e1)) * static_cast<double>(glm::dot(e2, e2));
  return static_cast<double>(n2) <= bound;
}

// Moves everything to be relative to the centre of the geometry's bounds
// (computed in double), then stores it in float.
void Loader::applyOrigin() {
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (const glm::dvec3& p : world_) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const glm::dvec3 origin = world_.empty() ? glm::dvec3(0.0) : 0.5 * (lo + hi);
  scene_.origin = origin;
  for (size_t i = 0; i < world_.size(); ++i) {
    const glm::dvec3 rel = world_[i] - origin;
    scene_.vertices[i].position = glm::vec3(rel);
    if (!finite(scene_.vertices[i].position))
      fail(strf("vertex %zu lies beyond the float range after its node transforms", i));
  }
  scene_.camera.position = glm::vec3(cameraWorld_ - origin);
  for (size_t i = 0; i < scene_.lights.size(); ++i)
    scene_.lights[i].position = glm::vec3(lightWorld_[i] - origin);
}

// --- read with a warning, or not read -------------------------------------------
// One line per kind and file, however many places share it: optional extensions
// voxgi does not implement, extra scenes, skins, morph targets, points
// and lines, cameras not used.
void Loader::warnIgnored() {
  for (const std::string& e : model_.extensionsUsed)
    if (!kSupportedExtensions.count(e))
      warn_("extension " + e + " is not supported; " + renderedWithout(e));
  if (model_.scenes.size() > 1)
    warn_(strf("%zu scenes: only scenes[%d] is drawn (%s)", model_.scenes.size(),
               std::max(model_.defaultScene, 0),
               model_.defaultScene >= 0 ? "the default" : "the first; the file names no default"));
  const IgnoredParts& i = ignored_;
  if (i.skinned.count())
    warn_(i.skinned.named("nodes") +
          ": skins are not applied; the meshes are drawn undeformed, as stored");
  if (i.morphed.count())
    warn_(i.morphed.named("primitives") +
          ": morph targets are not applied; the base geometry is drawn");
  if (i.weightChannels.count())
    warn_(i.weightChannels.named("channels") + ": morph target weights are not animated; skipped");
  if (i.pointsAndLines.count())
    warn_(i.pointsAndLines.named("primitives") + ": points and lines are not rendered; skipped");
  const std::string view =
      camera_ >= 0 ? strf("the view is from cameras[%d]", camera_) : "framing the scene instead";
  if (i.orthographic.count())
    warn_(i.orthographic.named("cameras") + ": orthographic cameras are not used; " + view);
  if (i.laterCameras.count())
    warn_(i.laterCameras.named("cameras") + ": only the first perspective camera is used; " + view);
}

void Loader::addCamera(int index, int node, const glm::dmat4& world) {
  if (index < 0 || static_cast<size_t>(index) >= model_.cameras.size())
    fail(strf("node %d: camera %d does not exist", node, index));
  const auto& c = model_.cameras[static_cast<size_t>(index)];
  if (c.type != "perspective") {
    ignored_.orthographic.add(strf("cameras[%d]", index));
    return;
  }
  if (scene_.camera.fromFile) {  // the first perspective camera wins
    if (index != camera_) ignored_.laterCameras.add(strf("cameras[%d]", index));
    return;
  }
  camera_ = index;
  Camera cam;
  cameraWorld_ = glm::dvec3(world[3]);
  cam.forward = glm::vec3(glm::normalize(-glm::dvec3(world[2])));
  cam.up = glm::vec3(glm::normalize(glm::dvec3(world[1])));
  cam.yfov = toFloat(c.perspective.yfov, strf("camera %d: yfov", index));
  if (!finite(cam.forward) || !finite(cam.up) || !(cam.yfov > 1e-4f && cam.yfov < 3.1f))
    fail(strf("camera %d: degenerate transform or yfov", index));
  cam.fromFile = true;
  cam.node = node;
  scene_.camera = cam;
  scene_.cameraMoves = moving_[static_cast<size_t>(node)] != 0;
}

void Loader::addLight(int index, int node, const glm::dmat4& world) {
  if (index < 0 || static_cast<size_t>(index) >= model_.lights.size())
    fail(strf("node %d: light %d does not exist", node, index));
  const auto& l = model_.lights[static_cast<size_t>(index)];
  Light light;
  light.name = l.name;
  const std::string what = strf("light %d", index);
  if (l.type == "directional")
    light.type = LightType::kDirectional;
  else if (l.type == "point")
    light.type = LightType::kPoint;
  else if (l.type == "spot")
    light.type = LightType::kSpot;
  else
    fail(strf("light %d: unknown type '%s'", index, l.type.c_str()));
  if (l.color.size() == 3) light.color = toVec3(l.color, what + ": color");
  light.intensity = toFloat(l.intensity, what + ": intensity");
  light.range = toFloat(l.range, what + ": range");
  lightWorld_.push_back(glm::dvec3(world[3]));
  light.direction = glm::vec3(glm::normalize(-glm::dvec3(world[2])));
  light.innerConeAngle = toFloat(l.spot.innerConeAngle, what + ": innerConeAngle");
  light.outerConeAngle = toFloat(l.spot.outerConeAngle, what + ": outerConeAngle");
  if (!finite(light.color) || !std::isfinite(light.intensity) || !finite(light.direction))
    fail(strf("light %d: NaN or Inf parameter", index));
  if (light.outerConeAngle <= light.innerConeAngle)
    light.outerConeAngle = light.innerConeAngle + 1e-3f;
  light.node = node;
  light.moves = moving_[static_cast<size_t>(node)] != 0;
  scene_.lights.push_back(light);
}

void Loader::addMesh(int meshIndex, int nodeIndex, const glm::dmat4& world) {
  const auto& mesh = model_.meshes[static_cast<size_t>(meshIndex)];
  for (size_t pi = 0; pi < mesh.primitives.size(); ++pi)
    addPrimitive(meshIndex, pi, nodeIndex, world);
}

}  // namespace voxgi::scene::gltf_detail
