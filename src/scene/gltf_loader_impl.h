// The glTF loader's parts (scene/gltf_*.cpp), and the class they share: one
// Loader reads one file (scene/gltf_loader.h is the interface). Not for use
// outside src/scene/gltf_*.cpp.
#ifndef VOXGI_SCENE_GLTF_LOADER_IMPL_H
#define VOXGI_SCENE_GLTF_LOADER_IMPL_H

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <string_view>

#include <tiny_gltf.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "core/log.h"
#include "scene/emitters.h"
#include "scene/gltf_loader.h"
#include "scene/tangents.h"

namespace voxgi::scene::gltf_detail {

namespace fs = std::filesystem;

// tinygltf takes lengths as unsigned int.
constexpr uint64_t kMaxFileBytes = 0xffffffffu;
constexpr int kMaxJsonDepth = 256;

// The extensions voxgi implements: accepted in extensionsRequired. Any other is
// refused there and warned about in extensionsUsed (Loader::warnIgnored).
inline const std::set<std::string> kSupportedExtensions = {
    "KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_mesh_quantization",
    "KHR_texture_transform"};

// Accessors without a bufferView (zeros) or with a sparse part are copied out dense:
// a small file must not ask for gigabytes.
constexpr size_t kMaxDenseBytes = size_t{256} << 20;

inline bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// The first non-blank line of s (gltf_loader.cpp).
std::string firstLine(const std::string& s);
// glTF's names of a component type and of an accessor type (gltf_accessors.cpp).
const char* componentName(int componentType);
const char* typeName(int type);
// A triangle strip or fan's indices as a triangle list (gltf_accessors.cpp).
std::vector<uint32_t> triangleList(std::vector<uint32_t> idx, int mode);

struct ImageLoaderState {
  int maxSize;
  const tinygltf::Model* model;  // being filled by tinygltf: buffers and views come first
};
// tinygltf's image callback: stb_image into RGBA8 (gltf_materials.cpp).
bool loadImage(tinygltf::Image* image, const int index, std::string* err, std::string*, int, int,
               const unsigned char* bytes, int size, void* user);

// The places in a file that hold one kind of thing voxgi ignores or reads only in
// part, each counted once however often the traversal meets it.
struct Tally {
  std::set<std::string> seen;
  std::string first;  // the first met
  void add(const std::string& where) {
    if (seen.insert(where).second && seen.size() == 1) first = where;
  }
  size_t count() const { return seen.size(); }
  // "materials[2]", or "3 materials (materials[2] first)".
  std::string named(const char* many) const {
    return count() == 1 ? first : strf("%zu %s (%s first)", count(), many, first.c_str());
  }
};

struct IgnoredParts {
  Tally pointsAndLines;  // primitives of points or lines, skipped
  Tally morphed;         // primitives with morph targets, drawn without them
  Tally weightChannels;  // animation channels of morph target weights
  Tally skinned;         // nodes with a mesh and a skin, drawn undeformed
  Tally orthographic;    // orthographic cameras, not used
  Tally laterCameras;    // perspective cameras after the one the view is from
};

class Loader {
 public:
  Loader(const std::string& path, const LoadOptions& opt) : path_(path), opt_(opt) {}
  Scene run();
  Scene runFromMemory(const unsigned char* data, size_t size);

 private:
  [[noreturn]] void fail(const std::string& what) const { throw Error(path_ + ": " + what); }

  // Checked view of an accessor: element i is at data + i * stride.
  struct View {
    const unsigned char* data = nullptr;
    size_t count = 0;
    size_t stride = 0;
    int componentType = 0;
    int type = 0;
    bool normalized = false;
    // An accessor of zeros or with a sparse part: the dense copy `data` points into.
    std::shared_ptr<const std::vector<unsigned char>> dense;
  };

  // The vertex attributes of one primitive, each with POSITION's count.
  struct PrimitiveAttributes {
    View position, normal, color, tangent;
    View uv[2];  // the material's two texture coordinate channels
    bool hasNormals = false, hasColor = false, hasTangent = false;
    bool hasUv[2] = {false, false};
    // The material's texture coordinates: channel 0 (Material::uv) and, where it has
    // one, channel 1 (Material::uv2; otherwise channel 0 again).
    TextureTransform uvMap[2];
    bool normalMapped = false;  // the material has a normal texture
    int normalChannel = 0;      // the channel its normal texture reads
  };

  // gltf_loader.cpp: the file or memory read and parsed by tinygltf, the GLB and JSON checks, notes
  // and warnings
  void readWholeFile(std::vector<unsigned char>* out) const;
  Scene parse(const unsigned char* data, size_t size, const std::string& baseDir,
              bool externalFiles);
  float toFloat(double v, const std::string& what) const;
  glm::vec3 toVec3(const std::vector<double>& v, const std::string& what) const;
  void note_(const std::string& what);
  void warn_(const std::string& what);
  void checkGlbHeader(const unsigned char* h, size_t size) const;
  static uint32_t le32(const unsigned char* p);
  static std::string_view glbJson(const unsigned char* data, size_t size);
  void checkJsonDepth(std::string_view json) const;
  static tinygltf::FsCallbacks noFiles();
  static std::string explainTinygltfError(const std::string& err);

  // gltf_validate.cpp: validity, as the glTF 2.0 spec states it, of the parts voxgi reads
  void validateDocument() const;
  static std::string countOf(size_t n, const char* one, const char* many);
  void checkIndex(int index, size_t size, const std::string& field, const char* one,
                  const char* many) const;
  static bool parseVersion(const std::string& v, int* major, int* minor);
  void checkAsset() const;
  void checkExtensions() const;
  void checkMeshes() const;
  void checkRange(double v, double lo, double hi, const std::string& field) const;
  void checkMaterialFields() const;
  void checkCameras() const;
  void checkLights() const;
  void validateBuffers() const;
  void checkNode(size_t i) const;
  void validateNodeGraph() const;
  void checkScenes(const std::vector<int>& parent) const;

  // gltf_nodes.cpp: nodes and their transforms, animation, the traversal, cameras, lights, meshes
  void readNodesAndAnimations();
  void readNodes();
  AnimationChannel readChannel(const tinygltf::Animation& anim,
                               const tinygltf::AnimationChannel& ch, const std::string& where);
  void readKeyframes(const tinygltf::AnimationSampler& sampler, const std::string& where,
                     AnimationChannel* c);
  void boundMotion();
  glm::dmat4 localMatrix(const tinygltf::Node& node, int index) const;
  void traverse();
  void dropDegenerateInFloat();
  static bool degenerateInFloat(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c);
  void applyOrigin();
  void warnIgnored();
  void addCamera(int index, int node, const glm::dmat4& world);
  void addLight(int index, int node, const glm::dmat4& world);
  void addMesh(int meshIndex, int nodeIndex, const glm::dmat4& world);

  // gltf_accessors.cpp: accessors and their bytes, checked, densified and read
  View accessor(int index, const char* what, std::initializer_list<int> types,
                std::initializer_list<int> componentTypes) const;
  void densify(int index, const char* what, const tinygltf::Accessor& a, size_t elem, int compSize,
               View* v) const;
  void substituteSparse(int index, const tinygltf::Accessor& a, size_t elem, int compSize,
                        unsigned char* dense) const;
  const unsigned char* sparseBytes(const std::string& at, int view, int offset, size_t bytes,
                                   size_t align) const;
  void checkAlignment(int index, const char* what, const tinygltf::Accessor& a,
                      const tinygltf::BufferView& bv, int compSize, size_t stride) const;
  static double rawComponent(const unsigned char* p, int componentType);
  void checkBounds(int index, const char* what, const tinygltf::Accessor& a, const View& v,
                   int nComp, int compSize) const;
  static float readComponent(const unsigned char* p, int componentType, bool normalized);
  View vertexAttribute(int index, const char* role) const;
  bool usesExtension(const char* name) const;
  static glm::vec3 readVec3(const View& v, size_t i);

  // gltf_materials.cpp: materials, textures, texture transforms and samplers
  void readMaterials();
  int texture(int index, bool srgb);
  TextureTransform transform(int texCoord, const tinygltf::ExtensionMap& extensions,
                             const std::string& at);
  void bakeChannels(Material* mat, const std::string& at);
  void readSampler(int index, Texture* t) const;

  // gltf_geometry.cpp: primitives into vertices, indices and draws
  void addPrimitive(int meshIndex, size_t pi, int nodeIndex, const glm::dmat4& world);
  PrimitiveAttributes readAttributes(const tinygltf::Primitive& prim, const std::string& where);
  View colorAttribute(int index, size_t count, const std::string& where) const;
  View tangentAttribute(int index, size_t count, const std::string& where) const;
  std::vector<uint32_t> readIndices(const tinygltf::Primitive& prim, size_t vertexCount,
                                    const std::string& where) const;
  void addVertices(const PrimitiveAttributes& a, size_t base, const glm::dmat4& world,
                   const std::string& where);
  static glm::vec2 readUv(const View& t, size_t i, const TextureTransform& uvMap);
  std::vector<uint32_t> keepNonDegenerate(const std::vector<uint32_t>& idx, size_t base,
                                          bool mirrored, const std::string& where,
                                          std::vector<glm::dvec3>* faceSum);
  void repairNormals(size_t base, const std::vector<glm::dvec3>& faceSum, bool hasNormals,
                     const std::string& where);
  void addAnimatedRange(int nodeIndex, size_t base, size_t count, const glm::dmat4& world,
                        bool mirrored);
  void addDraw(const tinygltf::Primitive& prim, int meshIndex, int nodeIndex, size_t base,
               const std::vector<uint32_t>& kept, const std::string& where);
  void readTangents(const View& t, bool fromFile, int channel, const std::vector<uint32_t>& kept,
                    size_t base, const glm::dmat4& world, bool mirrored);
  void readColors(const View& c, size_t base, const std::string& where);

  std::string path_;
  LoadOptions opt_;
  tinygltf::Model model_;
  Scene scene_;
  int defaultMaterial_ = 0;
  std::map<std::pair<int, bool>, int> textureMap_;  // (glTF texture, sRGB) -> Scene::textures
  bool colorWarned_ = false;
  std::vector<glm::dvec3> world_;  // double-precision world positions, parallel to vertices
  std::vector<char> moving_;       // per node: it or an ancestor is animated
  size_t dropped_ = 0, repaired_ = 0;
  std::vector<std::string> droppedIn_, repairedIn_;
  std::vector<std::string> drawWhere_;  // per draw: "mesh M primitive P"
  // The field that names each textureInfo's set (transform()), and per material
  // those whose sets its two vertex UV channels hold (bakeChannels()).
  std::map<std::string, std::string> texCoordField_;
  std::vector<std::array<std::string, 2>> uvField_;
  bool uvWarned_ = false;  // a material with a third mapping was warned about
  glm::dvec3 cameraWorld_{0.0};
  int camera_ = -1;  // the camera the view is from (cameras[i]); -1: framed
  IgnoredParts ignored_;
  std::vector<glm::dvec3> lightWorld_;
};

}  // namespace voxgi::scene::gltf_detail

#endif  // VOXGI_SCENE_GLTF_LOADER_IMPL_H
