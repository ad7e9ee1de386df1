// The scene as every stage sees it: world-space triangles, materials, textures,
// lights and a camera, plus bounds and the quantities auto-scaled from them.
//
// Geometry is baked to world space at load (node transforms applied, normals
// transformed by the inverse transpose); each Draw keeps its node so that later
// stages can tell what moves. Units are whatever the file uses: nothing here
// assumes metres (see Scene::scale()).
#ifndef VOXGI_SCENE_SCENE_H
#define VOXGI_SCENE_SCENE_H

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace voxgi::scene {

struct Vertex {
  glm::vec3 position;
  glm::vec3 normal;
  glm::vec2 uv;   // texture coordinates, channel 0 (Material::uv)
  glm::vec2 uv2;  // channel 1 (Material::uv2); equal to uv where the material has none
};

// A vertex's texture coordinates in channel `channel` (0: uv, 1: uv2).
inline glm::vec2 channelUv(const Vertex& v, int channel) {
  return channel == 1 ? v.uv2 : v.uv;
}

enum class AlphaMode { kOpaque, kMask, kBlend };

// How a texture slot maps the mesh's texture coordinates: the set it reads
// (textureInfo.texCoord, or KHR_texture_transform's override) and the extension's
// affine map uv' = T * R * S * uv, a 2x3 matrix kept as its three columns.
struct TextureTransform {
  glm::vec2 columns[3] = {glm::vec2(1.0f, 0.0f), glm::vec2(0.0f, 1.0f), glm::vec2(0.0f)};
  int texCoord = 0;  // TEXCOORD_<texCoord>
  glm::vec2 apply(glm::vec2 uv) const { return columns[0] * uv.x + columns[1] * uv.y + columns[2]; }
  bool operator==(const TextureTransform& o) const {
    return texCoord == o.texCoord && columns[0] == o.columns[0] && columns[1] == o.columns[1] &&
           columns[2] == o.columns[2];
  }
  bool operator!=(const TextureTransform& o) const { return !(*this == o); }
};

// KHR_texture_transform's matrix: translation by `offset`, rotation by `rotation`
// radians (counter-clockwise in UV space, as the extension writes its matrix) and
// scale, applied in the order scale, rotation, translation.
TextureTransform textureTransform(glm::vec2 offset, float rotation, glm::vec2 scale);

struct Material {
  std::string name;
  glm::vec4 baseColor{1.0f};  // linear
  float metallic = 1.0f;      // glTF defaults
  float roughness = 1.0f;
  glm::vec3 emission{0.0f};           // emissiveFactor x KHR_materials_emissive_strength (radiance)
  int baseColorTexture = -1;          // index into Scene::textures (sRGB)
  int emissiveTexture = -1;           // sRGB; multiplies emission
  int metallicRoughnessTexture = -1;  // linear; blue x metallic, green x roughness
  int normalTexture = -1;             // linear; tangent-space normal map (normalTexture)
  float normalScale = 1.0f;           // normalTexture.scale: scales the map's x and y
  int occlusionTexture = -1;          // linear; red channel: ambient occlusion (raster only)
  float occlusionStrength = 1.0f;     // occlusionTexture.strength: 0 none, 1 the full map
  // What each of the textures above reads. The loader resolves them into two
  // baked channels, Vertex::uv and Vertex::uv2 (see `uv`, `uv2`), so renderers read
  // those alone, each texture the channel its *Channel field names.
  TextureTransform baseColorUv, emissiveUv, metallicRoughnessUv, normalUv, occlusionUv;
  // The sets and transforms baked into the vertices of the primitives drawn with
  // this material: channel 0 (Vertex::uv) holds the first distinct mapping of its
  // textures (the base colour's, else the first texture's in the order above),
  // channel 1 (Vertex::uv2) the second one, when there is one (hasUv2).
  TextureTransform uv, uv2;
  bool hasUv2 = false;
  // The channel (0 or 1) each texture reads; a third distinct mapping reads 0.
  int baseColorChannel = 0, emissiveChannel = 0, metallicRoughnessChannel = 0, normalChannel = 0,
      occlusionChannel = 0;
  bool doubleSided = false;
  AlphaMode alphaMode = AlphaMode::kOpaque;
  float alphaCutoff = 0.5f;
  bool isEmissive() const { return emission.x > 0.0f || emission.y > 0.0f || emission.z > 0.0f; }
  bool hasTexture() const {
    return baseColorTexture >= 0 || emissiveTexture >= 0 || metallicRoughnessTexture >= 0 ||
           normalTexture >= 0 || occlusionTexture >= 0;
  }
};

// glTF sampler values, which are the OpenGL enums of the same names.
constexpr int kWrapRepeat = 10497;
constexpr int kWrapClampToEdge = 33071;
constexpr int kWrapMirroredRepeat = 33648;
constexpr int kFilterNearest = 9728;
constexpr int kFilterLinear = 9729;
constexpr int kFilterNearestMipmapNearest = 9984;
constexpr int kFilterLinearMipmapNearest = 9985;
constexpr int kFilterNearestMipmapLinear = 9986;
constexpr int kFilterLinearMipmapLinear = 9987;

struct Texture {
  std::string name;
  int width = 0, height = 0;
  std::vector<uint8_t> rgba8;  // 4 channels, rows top first
  bool srgb = true;  // colour (base colour, emission); false: data (metallic-roughness, normal)
  // The texture's glTF sampler. Without one, or where it leaves a field out: repeat,
  // bilinear magnification and trilinear minification.
  int wrapS = kWrapRepeat, wrapT = kWrapRepeat;  // kWrap*
  int magFilter = kFilterLinear;                 // kFilterNearest or kFilterLinear
  int minFilter = kFilterLinearMipmapLinear;     // any kFilter*
  // The texture table's flags for the shared texture reads (texture_shared.h): sRGB,
  // each axis's wrap mode, nearest magnification (kTexture* in scene_shared.h).
  uint32_t tableFlags() const;
};

enum class LightType { kDirectional, kPoint, kSpot };

// KHR_lights_punctual, read radiometrically: intensity is W/sr for point and spot
// (candela in the file) and W/m^2 for directional (lux in the file).
struct Light {
  LightType type = LightType::kPoint;
  glm::vec3 color{1.0f};
  float intensity = 1.0f;
  float range = 0.0f;  // 0: infinite
  glm::vec3 position{0.0f};
  glm::vec3 direction{0.0f, 0.0f, -1.0f};  // the way light travels
  float innerConeAngle = 0.0f;
  float outerConeAngle = 0.7853981634f;
  std::string name;
  int node = -1;       // the glTF node that places it
  bool moves = false;  // that node or an ancestor is animated: Scene::pose() moves it
};

struct Camera {
  glm::vec3 position{0.0f, 0.0f, 3.0f};
  glm::vec3 forward{0.0f, 0.0f, -1.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float yfov = 0.6981317f;  // 40 degrees
  float znear = 0.01f;
  float zfar = 100.0f;
  bool fromFile = false;
  int node = -1;  // the glTF node of a camera from the file
  glm::mat4 view() const;
  // Reversed depth (Lapidous and Jiao 1999; Reed 2015, "Depth precision
  // visualized"): clip-space depth runs from 1 at the near plane to 0 at the far one,
  // for clip control's [0, 1] range (render/frame_context.h). A float depth buffer
  // then holds about the same relative precision, 2^-24, at every distance: with the
  // usual mapping, at 1e5 times the near plane's distance it resolved only 15 cm in
  // 23 m, and walls behind a 15 cm wall showed through it.
  glm::mat4 projection(float aspect) const;
};

struct Bounds {
  glm::vec3 min{1e30f};
  glm::vec3 max{-1e30f};
  bool empty() const { return min.x > max.x; }
  void extend(const glm::vec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
  glm::vec3 center() const { return 0.5f * (min + max); }
  glm::vec3 extent() const { return max - min; }
  float diagonal() const;
};

// Near and far planes for `camera` from its distance to `bounds` (the far plane
// beyond the farthest corner, the near plane as far out as the geometry allows).
void fitClipPlanes(Camera* camera, const Bounds& bounds);

// A contiguous run of indices drawn with one material.
struct Draw {
  uint32_t firstIndex = 0;
  uint32_t indexCount = 0;
  int material = 0;
  int node = -1;
  int mesh = -1;
  // With an emissive texture: per triangle, the mean of that texture (linear) over
  // the triangle; what emitter sampling weighs it by (scene/emitters.h,
  // measureEmissiveTextures). Empty otherwise.
  std::vector<glm::vec3> emissiveMean;
};

// The glTF node hierarchy, kept for animation; transforms in double precision.
struct SceneNode {
  int parent = -1;
  bool hasMatrix = false;  // a node given by a matrix is not animated
  glm::dmat4 matrix{1.0};
  glm::dvec3 translation{0.0};
  glm::dquat rotation{1.0, 0.0, 0.0, 0.0};
  glm::dvec3 scale{1.0};
};

enum class AnimationPath { kTranslation, kRotation, kScale };

// glTF's sampler interpolations: LINEAR (rotations slerp), STEP, and CUBICSPLINE (a
// cubic Hermite spline through the keyframes with the file's tangents).
enum class Interpolation { kLinear, kStep, kCubicSpline };

// One glTF animation channel: keyframes of one node's translation, rotation or scale.
struct AnimationChannel {
  int node = -1;
  AnimationPath path = AnimationPath::kTranslation;
  Interpolation interpolation = Interpolation::kLinear;
  std::vector<float> times;
  std::vector<glm::dvec4> values;  // xyz, or a quaternion as (x, y, z, w)
  // CUBICSPLINE only: each keyframe's in-tangent and out-tangent (per second of the
  // keyframe interval's parameter, as the file stores them).
  std::vector<glm::dvec4> inTangents, outTangents;
};

// Vertices that move: their node or one of its ancestors is animated.
struct AnimatedRange {
  uint32_t firstVertex = 0;
  int node = -1;
  std::vector<glm::dvec3> localPositions;
  std::vector<glm::vec3> localNormals;
  // With Scene::tangents: the tangents in the node's space (w: handedness).
  std::vector<glm::vec4> localTangents;
};

// Quantities derived from the bounds so that nothing assumes a unit.
struct AutoScale {
  float cameraSpeed = 1.0f;    // units per second for the fly camera
  glm::vec3 gridOrigin{0.0f};  // voxel grid: a cube fitted to voxelBounds() with a margin
  float gridSize = 1.0f;
};

struct Scene {
  std::string path;
  // Positions (vertices, camera, lights) are relative to `origin`, the centre of the
  // file's geometry in its own world frame, composed in double precision: a scene
  // far from its file's origin keeps its float precision.
  glm::dvec3 origin{0.0};
  std::vector<Vertex> vertices;
  // COLOR_0, linear RGBA, parallel to `vertices`; it multiplies the material's base
  // colour. Empty when no primitive has vertex colours (the common case costs
  // nothing); otherwise primitives without COLOR_0 get white.
  std::vector<glm::vec4> colors;
  // Tangents for normal maps, world space, parallel to `vertices`: xyz the unit
  // tangent (the direction u grows in), w the handedness (+1 or -1): the bitangent
  // is w * cross(normal, tangent). From the file's TANGENT, or generated with the
  // MikkTSpace algorithm (scene/tangents.h). Empty when no drawn primitive has a
  // normal-mapped material; otherwise other primitives get (1, 0, 0, 1).
  std::vector<glm::vec4> tangents;
  std::vector<uint32_t> indices;
  std::vector<Draw> draws;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<Light> lights;
  Camera camera;
  Bounds bounds;
  AutoScale scale;
  bool defaultLight =
      false;  // nothing in the file lights it: one was added (addDefaultLightIfUnlit)
  // Animation: nodes, channels and the vertex ranges they move. Bounds (and so the
  // voxel grid) cover every pose of the animation.
  std::vector<SceneNode> nodes;
  std::vector<AnimationChannel> animations;
  std::vector<AnimatedRange> animatedRanges;
  // The file's camera moves: its node or an ancestor is animated (a camera path).
  bool cameraMoves = false;
  // pose() moves the camera along its path; false keeps it where it was set
  // (render --look-from).
  bool poseCamera = true;
  double animationDuration = 0.0;  // seconds: the last key of any channel
  // pose() after the end: false holds the last pose (an offline render's default,
  // as Blender and Cesium's clampAnimations do), true wraps around (the viewer's
  // playback, render --loop).
  bool loopAnimation = false;
  Bounds motionBounds;  // union of the animated vertices over all poses
  // What pose() composes, made on its first call (PoseChains in scene.cpp): per
  // node, its nearest animated ancestor or itself, and the still transforms between.
  struct PoseChains {
    std::vector<int> anchor;         // the nearest animated node up the path, or -1
    std::vector<glm::dmat4> still;   // the local transforms below the anchor, composed
    std::vector<int> animatedSlot;   // per node: its place among the animated ones, or -1
    std::vector<int> animatedNodes;  // the nodes channels move
  };
  PoseChains poseChains;
  std::vector<std::string> warnings;
  std::vector<std::string> notes;  // information the loader printed (a file without scenes)

  size_t triangleCount() const { return indices.size() / 3; }
  bool hasVertexColors() const { return !colors.empty(); }
  bool hasNormalMaps() const { return !tangents.empty(); }
  // Something moves: a mesh, the camera or a light.
  bool animated() const { return meshesAnimated() || cameraMoves || lightsAnimated(); }
  bool meshesAnimated() const { return !animatedRanges.empty(); }
  bool lightsAnimated() const;
  // Moves the animated vertices, lights and (with poseCamera) the camera to their
  // pose at `seconds`, through the node hierarchy; the camera's clip planes are
  // refitted to the bounds. A no-op for a still scene. Times are compared with the
  // keys in the keys' own (float) precision: a frame time a hair past a float key
  // time is at that key.
  void pose(double seconds);
  // Makes poseChains from the nodes and channels (pose() does on its first call).
  void preparePose();
  bool hasEmission() const;
  // A drawn material has a second texture-coordinate channel (Material::hasUv2).
  bool hasSecondUv() const;

  // Recomputes bounds, auto-scale and (unless the file had one) the framing camera.
  void finalize();
  // Sets near/far planes from the camera position and the bounds.
  void fitClipPlanes();
  // Puts the camera at `from`, looking at `at` (the file's coordinates, before the
  // origin shift; distinct points), up along +y (-z looking straight up or down),
  // refits the clip planes and keeps the camera there through pose() (render
  // --look-from/--look-at).
  void lookAt(const glm::vec3& from, const glm::vec3& at);
  // Adds a directional light when there is no punctual light and the emitters, if
  // any, are too faint to light the scene (emittedLightPerArea below
  // kLitByEmitters), so an unlit file never renders black by surprise: a model whose
  // only emission is a glowing detail (DamagedHelmet's lamps, WaterBottle's label)
  // is lit as one with none.
  void addDefaultLightIfUnlit();
  // The light the emitters send out (exitance pi L, luminance, times area, both
  // faces of a double-sided one), over the area of every surface of the scene: the
  // mean irradiance they would give the scene's surfaces if all of it landed there.
  // Scale-free: a radiance.
  float emittedLightPerArea() const;
  // The default light (intensity 3) gives a closed object a mean irradiance of 3/4
  // (a sphere's projected area is a quarter of its surface); emitters light the
  // scene from 1/30 of that. The samples: the validation set's darkest scene,
  // dark_plane (a lamp over a wide plane), 0.062; DamagedHelmet 0.0058;
  // WaterBottle 0.00013; scenes lit by their lamps 0.36-1.03.
  static constexpr float kLitByEmitters = 0.75f / 30.0f;
  // Frames the bounds from the front (+z side), looking along -z.
  void autoFrameCamera();
  // Where the voxel grid goes: the bounds, less the reach of a few huge triangles.
  Bounds voxelBounds() const;
};

}  // namespace voxgi::scene

#endif  // VOXGI_SCENE_SCENE_H
