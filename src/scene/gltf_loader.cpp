#include "scene/gltf_loader.h"

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

#include <stb_image.h>
#include <tiny_gltf.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "core/log.h"
#include "scene/emitters.h"
#include "scene/tangents.h"

namespace voxgi::scene {
namespace {

namespace fs = std::filesystem;

// tinygltf takes lengths as unsigned int.
constexpr uint64_t kMaxFileBytes = 0xffffffffu;
constexpr int kMaxJsonDepth = 256;

// The extensions voxgi implements: accepted in extensionsRequired. Any other is
// refused there and warned about in extensionsUsed (Loader::warnIgnored).
const std::set<std::string> kSupportedExtensions = {
    "KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_mesh_quantization",
    "KHR_texture_transform"};

// Accessors without a bufferView (zeros) or with a sparse part are copied out dense:
// a small file must not ask for gigabytes.
constexpr size_t kMaxDenseBytes = size_t{256} << 20;

std::string firstLine(const std::string& s) {
  size_t b = s.find_first_not_of(" \n\r\t");
  if (b == std::string::npos) return "";
  size_t e = s.find('\n', b);
  std::string l = s.substr(b, e == std::string::npos ? std::string::npos : e - b);
  while (!l.empty() && (l.back() == '\r' || l.back() == ' ')) l.pop_back();
  return l;
}

struct ImageLoaderState {
  int maxSize;
  const tinygltf::Model* model;  // being filled by tinygltf: buffers and views come first
};

// Width and height from a PNG's IHDR chunk (stb refuses to even report sizes over
// 2^24 pixels a side, which would hide the real reason).
bool pngSize(const unsigned char* b, int size, int* w, int* h) {
  static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (size < 24 || std::memcmp(b, sig, 8) != 0 || std::memcmp(b + 12, "IHDR", 4) != 0) return false;
  auto be32 = [](const unsigned char* p) {
    return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | uint32_t{p[3]};
  };
  const uint32_t uw = be32(b + 16), uh = be32(b + 20);
  *w = uw > 0x7fffffffu ? 0x7fffffff : static_cast<int>(uw);
  *h = uh > 0x7fffffffu ? 0x7fffffff : static_cast<int>(uh);
  return true;
}

// Decodes with stb_image into RGBA8, refusing absurd sizes before allocating.
bool loadImage(tinygltf::Image* image, const int index, std::string* err, std::string*, int, int,
               const unsigned char* bytes, int size, void* user) {
  const auto* state = static_cast<const ImageLoaderState*>(user);
  // tinygltf hands over &buffer[view.byteOffset] without checking the view: check it
  // here, before anything reads those bytes.
  if (image->bufferView >= 0) {
    const auto& views = state->model->bufferViews;
    const auto& view = views[static_cast<size_t>(image->bufferView)];
    const size_t have = state->model->buffers[static_cast<size_t>(view.buffer)].data.size();
    if (view.byteOffset > have || view.byteLength > have - view.byteOffset) {
      if (err)
        *err += strf("bufferView %d: bytes [%zu, %zu) of image %d exceed buffer %d of %zu bytes\n",
                     image->bufferView, view.byteOffset, view.byteOffset + view.byteLength, index,
                     view.buffer, have);
      return false;
    }
  }
  const std::string name = !image->uri.empty() && image->uri.rfind("data:", 0) != 0 ? image->uri
                           : !image->name.empty()                                   ? image->name
                                                                                    : "embedded";
  int w = 0, h = 0, comp = 0;
  if (pngSize(bytes, size, &w, &h) && (w > state->maxSize || h > state->maxSize)) {
    if (err)
      *err += strf("image %d (%s): %dx%d exceeds the %dx%d texture limit\n", index, name.c_str(), w,
                   h, state->maxSize, state->maxSize);
    return false;
  }
  if (!stbi_info_from_memory(bytes, size, &w, &h, &comp)) {
    if (err)
      *err += strf("image %d (%s): not a decodable PNG/JPEG (%s)\n", index, name.c_str(),
                   stbi_failure_reason());
    return false;
  }
  if (w <= 0 || h <= 0 || w > state->maxSize || h > state->maxSize) {
    if (err)
      *err += strf("image %d (%s): %dx%d exceeds the %dx%d texture limit\n", index, name.c_str(), w,
                   h, state->maxSize, state->maxSize);
    return false;
  }
  unsigned char* data = stbi_load_from_memory(bytes, size, &w, &h, &comp, 4);
  if (!data) {
    if (err)
      *err +=
          strf("image %d (%s): decode failed (%s)\n", index, name.c_str(), stbi_failure_reason());
    return false;
  }
  image->width = w;
  image->height = h;
  image->component = 4;
  image->bits = 8;
  image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  image->image.assign(data, data + static_cast<size_t>(w) * static_cast<size_t>(h) * 4);
  stbi_image_free(data);
  return true;
}

const char* componentName(int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return "BYTE";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return "UNSIGNED_BYTE";
    case TINYGLTF_COMPONENT_TYPE_SHORT:
      return "SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return "UNSIGNED_SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      return "UNSIGNED_INT";
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return "FLOAT";
    default:
      return "unknown";
  }
}

const char* typeName(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return "SCALAR";
    case TINYGLTF_TYPE_VEC2:
      return "VEC2";
    case TINYGLTF_TYPE_VEC3:
      return "VEC3";
    case TINYGLTF_TYPE_VEC4:
      return "VEC4";
    case TINYGLTF_TYPE_MAT2:
      return "MAT2";
    case TINYGLTF_TYPE_MAT3:
      return "MAT3";
    case TINYGLTF_TYPE_MAT4:
      return "MAT4";
    default:
      return "unknown";
  }
}

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// A triangle strip or fan's indices as a triangle list (a list as it is), cut to
// whole triangles. Strips alternate the winding of their odd triangles back.
std::vector<uint32_t> triangleList(std::vector<uint32_t> idx, int mode) {
  if (mode != TINYGLTF_MODE_TRIANGLES) {
    std::vector<uint32_t> list;
    for (size_t i = 2; i < idx.size(); ++i) {
      if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        if (i % 2 == 0)
          list.insert(list.end(), {idx[i - 2], idx[i - 1], idx[i]});
        else
          list.insert(list.end(), {idx[i - 1], idx[i - 2], idx[i]});
      } else {
        list.insert(list.end(), {idx[0], idx[i - 1], idx[i]});
      }
    }
    idx.swap(list);
  }
  idx.resize(idx.size() / 3 * 3);
  return idx;
}

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

class Loader {
 public:
  Loader(const std::string& path, const LoadOptions& opt) : path_(path), opt_(opt) {}

  // From a file: read whole, then parsed as from memory with external URIs
  // resolved next to it.
  Scene run() {
    std::error_code ec;
    if (!fs::exists(path_, ec)) fail("no such file");
    if (fs::is_directory(path_, ec)) fail("is a directory, not a glTF file");
    std::vector<unsigned char> bytes;
    readWholeFile(&bytes);
    std::string baseDir = fs::path(path_).parent_path().string();
    return parse(bytes.data(), bytes.size(), baseDir.empty() ? "." : baseDir, true);
  }

  // From memory: the same checks; no other file is ever opened.
  Scene runFromMemory(const unsigned char* data, size_t size) {
    return parse(data, size, "", false);
  }

 private:
  void readWholeFile(std::vector<unsigned char>* out) const {
    std::ifstream in(path_, std::ios::binary);
    if (!in) fail(std::string("cannot open: ") + std::strerror(errno));
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    if (size < 0) fail("cannot read (not a seekable file)");
    if (static_cast<uint64_t>(size) > kMaxFileBytes)
      fail(strf("%lld bytes: larger than the %llu-byte limit of a glTF file here",
                static_cast<long long>(size), static_cast<unsigned long long>(kMaxFileBytes)));
    out->resize(static_cast<size_t>(size));
    in.seekg(0);
    if (size > 0 && !in.read(reinterpret_cast<char*>(out->data()), size))
      fail(std::string("read failed: ") + std::strerror(errno));
  }

  Scene parse(const unsigned char* data, size_t size, const std::string& baseDir,
              bool externalFiles) {
    if (size > kMaxFileBytes)
      fail(strf("%zu bytes: larger than the %llu-byte limit of a glTF file here", size,
                static_cast<unsigned long long>(kMaxFileBytes)));
    const std::string ext = fs::path(path_).extension().string();
    std::string lower = ext;
    std::transform(lower.begin(), lower.end(), lower.begin(), ::tolower);
    if (lower != ".glb" && lower != ".gltf")
      fail("unknown scene format '" + ext + "' (expected .gltf or .glb)");
    if (size == 0) fail("empty file (0 bytes)");
    tinygltf::TinyGLTF gltf;
    ImageLoaderState state{opt_.maxTextureSize, &model_};
    gltf.SetImageLoader(loadImage, &state);
    if (!externalFiles) gltf.SetFsCallbacks(noFiles());
    std::string err, warn;
    bool ok = false;
    const auto length = static_cast<unsigned int>(size);
    if (lower == ".glb") {
      checkGlbHeader(data, size);
      checkJsonDepth(glbJson(data, size));
      ok = gltf.LoadBinaryFromMemory(&model_, &err, &warn, data, length, baseDir);
    } else {
      checkJsonDepth(std::string_view(reinterpret_cast<const char*>(data), size));
      ok = gltf.LoadASCIIFromString(&model_, &err, &warn, reinterpret_cast<const char*>(data),
                                    length, baseDir);
    }
    if (!ok) fail(explainTinygltfError(err));
    if (!warn.empty()) {
      // tinygltf keeps going when an external image is missing: remember which.
      logDebug(path_ + ": tinygltf: " + firstLine(warn));
    }

    validateDocument();

    scene_.path = path_;
    readMaterials();
    readNodesAndAnimations();
    traverse();
    warnIgnored();
    // One line each, however many primitives share the problem.
    if (dropped_)
      warn_(strf("dropped %zu degenerate triangles: zero area or collinear (%s%s)", dropped_,
                 droppedIn_.front().c_str(),
                 droppedIn_.size() > 1
                     ? strf(" and %zu more primitives", droppedIn_.size() - 1).c_str()
                     : ""));
    if (repaired_)
      warn_(strf("repaired %zu zero or NaN normals (%s%s)", repaired_, repairedIn_.front().c_str(),
                 repairedIn_.size() > 1
                     ? strf(" and %zu more primitives", repairedIn_.size() - 1).c_str()
                     : ""));
    if (scene_.meshesAnimated()) boundMotion();
    if (scene_.animated()) scene_.pose(0.0);  // the first pose, not the rest pose
    if (scene_.draws.empty()) warn_("no triangles to draw");
    measureEmissiveTextures(&scene_);
    scene_.finalize();
    if (opt_.addDefaultLight) scene_.addDefaultLightIfUnlit();
    return std::move(scene_);
  }

  [[noreturn]] void fail(const std::string& what) const { throw Error(path_ + ": " + what); }

  // double -> float without undefined behaviour: NaN, Inf and values beyond the
  // float range are refused with `what` named.
  float toFloat(double v, const std::string& what) const {
    if (!std::isfinite(v) || std::abs(v) > static_cast<double>(std::numeric_limits<float>::max()))
      fail(what + ": NaN or Inf, or beyond the float range");
    return static_cast<float>(v);
  }
  glm::vec3 toVec3(const std::vector<double>& v, const std::string& what) const {
    return glm::vec3(toFloat(v[0], what), toFloat(v[1], what), toFloat(v[2], what));
  }
  void note_(const std::string& what) {
    logInfo(path_ + ": " + what);
    scene_.notes.push_back(what);
  }
  void warn_(const std::string& what) {
    logWarning(path_ + ": " + what);
    scene_.warnings.push_back(what);
  }

  // A GLB's 12-byte header: magic "glTF", version 2, total length = file size.
  void checkGlbHeader(const unsigned char* h, size_t size) const {
    if (size < 12) fail(strf("truncated GLB: %zu bytes, shorter than the 12-byte header", size));
    if (std::memcmp(h, "glTF", 4) != 0) fail("not a GLB file (bad magic)");
    const uint32_t version = le32(h + 4);
    const uint32_t length = le32(h + 8);
    if (version != 2) fail(strf("GLB version %u is not supported (expected 2)", version));
    if (length > size)
      fail(strf("truncated GLB: header says %u bytes, the file has %zu", length, size));
  }

  static uint32_t le32(const unsigned char* p) {
    return p[0] | (p[1] << 8) | (p[2] << 16) | (uint32_t{p[3]} << 24);
  }

  // The JSON chunk of a GLB whose header passed checkGlbHeader (empty when the
  // chunk is malformed: tinygltf says why).
  static std::string_view glbJson(const unsigned char* data, size_t size) {
    if (size < 20) return {};
    const uint32_t length = le32(data + 12);
    if (length > size - 20) return {};
    return std::string_view(reinterpret_cast<const char*>(data + 20), length);
  }

  // tinygltf turns "extras" and "extensions" into its Value tree recursively, one
  // stack frame per level: a file nested thousands deep would overflow the stack.
  // No glTF needs more than a few dozen levels.
  void checkJsonDepth(std::string_view json) const {
    int depth = 0;
    bool inString = false;
    for (size_t i = 0; i < json.size(); ++i) {
      const char c = json[i];
      if (inString) {
        if (c == '\\')
          ++i;
        else if (c == '"')
          inString = false;
      } else if (c == '"') {
        inString = true;
      } else if (c == '[' || c == '{') {
        if (++depth > kMaxJsonDepth)
          fail(strf("JSON nested deeper than %d levels (at byte %zu)", kMaxJsonDepth, i));
      } else if (c == ']' || c == '}') {
        --depth;
      }
    }
  }

  // File callbacks for loading from memory: every external URI is refused.
  static tinygltf::FsCallbacks noFiles() {
    tinygltf::FsCallbacks fs{};
    fs.FileExists = [](const std::string&, void*) { return false; };
    fs.ExpandFilePath = [](const std::string& p, void*) { return p; };
    fs.ReadWholeFile = [](std::vector<unsigned char>*, std::string* err, const std::string& p,
                          void*) {
      if (err) *err += "external file '" + p + "' is not read when loading from memory\n";
      return false;
    };
    fs.WriteWholeFile = [](std::string*, const std::string&, const std::vector<unsigned char>&,
                           void*) { return false; };
    return fs;
  }

  // tinygltf's messages, made one line and specific where they are not.
  static std::string explainTinygltfError(const std::string& err) {
    std::string line = firstLine(err.empty() ? "malformed glTF" : err);
    if (line.find("\"asset\" object not found") != std::string::npos ||
        line.find("\"version\" not found") != std::string::npos)
      return "missing \"asset\" or \"asset.version\" (required by glTF 2.0)";
    if (line.find("Failed to decode 'uri'") != std::string::npos &&
        line.find(" in Buffer") != std::string::npos)
      return "a buffer's data URI is not valid base64 or its size differs from byteLength";
    if (line.find("Invalid glTF binary") != std::string::npos) return "invalid GLB chunk layout";
    // Embedded data never belongs in a one-line message.
    const size_t data = line.find("data:");
    if (data != std::string::npos) {
      const size_t end = line.find_first_of(" '\"", data);
      line.replace(data, end == std::string::npos ? std::string::npos : end - data, "data:...");
    }
    if (line.size() > 300) line = line.substr(0, 300) + "...";
    return line;
  }

  void readNodesAndAnimations() {
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
  void readNodes() {
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
      if (node.scale.size() == 3)
        sn.scale = glm::dvec3(node.scale[0], node.scale[1], node.scale[2]);
    }
  }

  // A translation, rotation or scale channel, its target node and sampler checked.
  AnimationChannel readChannel(const tinygltf::Animation& anim,
                               const tinygltf::AnimationChannel& ch, const std::string& where) {
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
  void readKeyframes(const tinygltf::AnimationSampler& sampler, const std::string& where,
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
  void boundMotion() {
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

  // --- validity, as the glTF 2.0 spec states it, of the parts voxgi reads ---------
  // Those parts: asset, extensionsRequired, scene and scenes, every node (hierarchy,
  // transform, mesh, camera, light), every mesh's primitives (mode, indices,
  // material, attribute references), the accessors of POSITION, NORMAL, the TEXCOORD_n read,
  // indices and animation samplers, every bufferView and buffer, every material's
  // fields that the renderer uses, the textures and images those materials
  // reference, every camera and every KHR_lights_punctual light. Anything else
  // (textures no material uses, normal maps, skins, morph targets) is not read and
  // not checked. Each problem is one line naming the field, e.g.
  // "nodes[3].mesh 7 points nowhere (5 meshes)".
  void validateDocument() const {
    checkAsset();
    checkExtensions();
    validateBuffers();
    validateNodeGraph();
    checkMeshes();
    checkMaterialFields();
    checkCameras();
    checkLights();
  }

  static std::string countOf(size_t n, const char* one, const char* many) {
    return strf("%zu %s", n, n == 1 ? one : many);
  }

  // An index into an array of `size` elements, `field` naming where it was found.
  void checkIndex(int index, size_t size, const std::string& field, const char* one,
                  const char* many) const {
    if (index < 0 || static_cast<size_t>(index) >= size)
      fail(strf("%s %d points nowhere (%s)", field.c_str(), index,
                countOf(size, one, many).c_str()));
  }

  // "2.0" -> 2, 0; false unless the text is MAJOR.MINOR in digits.
  static bool parseVersion(const std::string& v, int* major, int* minor) {
    const size_t dot = v.find('.');
    auto digits = [](const std::string& s) {
      return !s.empty() && s.size() < 9 &&
             std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
    };
    if (dot == std::string::npos || !digits(v.substr(0, dot)) || !digits(v.substr(dot + 1)))
      return false;
    *major = std::stoi(v.substr(0, dot));
    *minor = std::stoi(v.substr(dot + 1));
    return true;
  }

  void checkAsset() const {
    int major = 0, minor = 0;
    const std::string& v = model_.asset.version;
    if (!parseVersion(v, &major, &minor))
      fail("asset.version \"" + v + "\": not a MAJOR.MINOR version");
    if (major != 2) fail("asset.version \"" + v + "\": only glTF 2.x is supported");
    const std::string& mv = model_.asset.minVersion;
    if (mv.empty()) return;
    if (!parseVersion(mv, &major, &minor))
      fail("asset.minVersion \"" + mv + "\": not a MAJOR.MINOR version");
    if (major != 2 || minor > 0)
      fail("asset.minVersion \"" + mv + "\": needs a reader newer than glTF 2.0");
  }

  void checkExtensions() const {
    const auto& used = model_.extensionsUsed;
    for (size_t i = 0; i < model_.extensionsRequired.size(); ++i) {
      const std::string& r = model_.extensionsRequired[i];
      if (!kSupportedExtensions.count(r)) fail("requires the unsupported extension " + r);
      if (std::find(used.begin(), used.end(), r) == used.end())
        fail(strf("extensionsRequired[%zu] %s is not in extensionsUsed", i, r.c_str()));
    }
  }

  void checkMeshes() const {
    for (size_t m = 0; m < model_.meshes.size(); ++m) {
      const auto& prims = model_.meshes[m].primitives;
      if (prims.empty()) fail(strf("meshes[%zu].primitives is empty", m));
      for (size_t p = 0; p < prims.size(); ++p) {
        const auto& prim = prims[p];
        const std::string where = strf("meshes[%zu].primitives[%zu]", m, p);
        for (const auto& [name, index] : prim.attributes)
          checkIndex(index, model_.accessors.size(), where + ".attributes." + name, "accessor",
                     "accessors");
        if (prim.indices != -1)
          checkIndex(prim.indices, model_.accessors.size(), where + ".indices", "accessor",
                     "accessors");
        if (prim.material != -1)
          checkIndex(prim.material, model_.materials.size(), where + ".material", "material",
                     "materials");
      }
    }
  }

  // A factor the spec bounds: refused outside [lo, hi] (NaN included).
  void checkRange(double v, double lo, double hi, const std::string& field) const {
    if (!(v >= lo && v <= hi)) fail(strf("%s %g: outside [%g, %g]", field.c_str(), v, lo, hi));
  }

  void checkMaterialFields() const {
    constexpr double kHuge = std::numeric_limits<double>::max();
    for (size_t i = 0; i < model_.materials.size(); ++i) {
      const auto& m = model_.materials[i];
      const std::string at = strf("materials[%zu]", i);
      const auto& pbr = m.pbrMetallicRoughness;
      const std::string p = at + ".pbrMetallicRoughness.";
      if (pbr.baseColorFactor.size() != 4) fail(p + "baseColorFactor: needs 4 numbers");
      for (size_t c = 0; c < 4; ++c)
        checkRange(pbr.baseColorFactor[c], 0.0, 1.0, strf("%sbaseColorFactor[%zu]", p.c_str(), c));
      checkRange(pbr.metallicFactor, 0.0, 1.0, p + "metallicFactor");
      checkRange(pbr.roughnessFactor, 0.0, 1.0, p + "roughnessFactor");
      // Above 1 is accepted: exporters wrote HDR emission so before
      // KHR_materials_emissive_strength (scenes/cornell_box does).
      if (m.emissiveFactor.size() != 3) fail(at + ".emissiveFactor: needs 3 numbers");
      for (size_t c = 0; c < 3; ++c)
        checkRange(m.emissiveFactor[c], 0.0, kHuge, strf("%s.emissiveFactor[%zu]", at.c_str(), c));
      auto it = m.extensions.find("KHR_materials_emissive_strength");
      if (it != m.extensions.end() && it->second.Has("emissiveStrength"))
        checkRange(it->second.Get("emissiveStrength").GetNumberAsDouble(), 0.0, kHuge,
                   at + ".extensions.KHR_materials_emissive_strength.emissiveStrength");
      if (m.alphaMode != "OPAQUE" && m.alphaMode != "MASK" && m.alphaMode != "BLEND")
        fail(at + ".alphaMode \"" + m.alphaMode + "\": not OPAQUE, MASK or BLEND");
      checkRange(m.alphaCutoff, 0.0, kHuge, at + ".alphaCutoff");
      if (pbr.baseColorTexture.index != -1)
        checkIndex(pbr.baseColorTexture.index, model_.textures.size(), p + "baseColorTexture.index",
                   "texture", "textures");
      if (pbr.metallicRoughnessTexture.index != -1)
        checkIndex(pbr.metallicRoughnessTexture.index, model_.textures.size(),
                   p + "metallicRoughnessTexture.index", "texture", "textures");
      if (m.emissiveTexture.index != -1)
        checkIndex(m.emissiveTexture.index, model_.textures.size(), at + ".emissiveTexture.index",
                   "texture", "textures");
      if (m.normalTexture.index != -1) {
        checkIndex(m.normalTexture.index, model_.textures.size(), at + ".normalTexture.index",
                   "texture", "textures");
        checkRange(m.normalTexture.scale, -kHuge, kHuge, at + ".normalTexture.scale");
      }
      if (m.occlusionTexture.index != -1) {
        checkIndex(m.occlusionTexture.index, model_.textures.size(), at + ".occlusionTexture.index",
                   "texture", "textures");
        checkRange(m.occlusionTexture.strength, 0.0, 1.0, at + ".occlusionTexture.strength");
      }
    }
  }

  void checkCameras() const {
    constexpr double kHuge = std::numeric_limits<double>::max();
    for (size_t i = 0; i < model_.cameras.size(); ++i) {
      const auto& c = model_.cameras[i];
      const std::string at = strf("cameras[%zu]", i);
      if (c.type == "perspective") {
        const auto& p = c.perspective;
        const std::string f = at + ".perspective.";
        if (!(p.yfov > 0.0)) fail(strf("%syfov %g: must be positive", f.c_str(), p.yfov));
        if (!(p.znear > 0.0)) fail(strf("%sznear %g: must be positive", f.c_str(), p.znear));
        if (p.zfar != 0.0 && !(p.zfar > p.znear))
          fail(strf("%szfar %g: must be greater than znear %g", f.c_str(), p.zfar, p.znear));
        checkRange(p.aspectRatio, 0.0, kHuge, f + "aspectRatio");
      } else if (c.type == "orthographic") {
        const auto& o = c.orthographic;
        const std::string f = at + ".orthographic.";
        if (o.xmag == 0.0 || o.ymag == 0.0 || !std::isfinite(o.xmag) || !std::isfinite(o.ymag))
          fail(f + "xmag and ymag: must be finite and not zero");
        checkRange(o.znear, 0.0, kHuge, f + "znear");
        if (!(o.zfar > o.znear))
          fail(strf("%szfar %g: must be greater than znear %g", f.c_str(), o.zfar, o.znear));
      } else {
        fail(at + ".type \"" + c.type + "\": not perspective or orthographic");
      }
    }
  }

  void checkLights() const {
    constexpr double kHalfPi = 1.5707963267948966;
    for (size_t i = 0; i < model_.lights.size(); ++i) {
      const auto& l = model_.lights[i];
      const std::string at = strf("KHR_lights_punctual.lights[%zu]", i);
      if (l.type != "directional" && l.type != "point" && l.type != "spot")
        fail(at + ".type: unknown type '" + l.type + "'");
      if (!l.color.empty() && l.color.size() != 3) fail(at + ".color: needs 3 numbers");
      for (size_t c = 0; c < l.color.size(); ++c)
        checkRange(l.color[c], 0.0, 1.0, strf("%s.color[%zu]", at.c_str(), c));
      checkRange(l.intensity, 0.0, std::numeric_limits<double>::max(), at + ".intensity");
      if (l.range < 0.0 || !std::isfinite(l.range))
        fail(strf("%s.range %g: must be positive", at.c_str(), l.range));
      if (l.type != "spot") continue;
      checkRange(l.spot.outerConeAngle, 0.0, kHalfPi, at + ".spot.outerConeAngle");
      if (!(l.spot.innerConeAngle >= 0.0 && l.spot.innerConeAngle < l.spot.outerConeAngle))
        fail(strf("%s.spot.innerConeAngle %g: outside [0, outerConeAngle %g)", at.c_str(),
                  l.spot.innerConeAngle, l.spot.outerConeAngle));
    }
  }

  void validateBuffers() const {
    for (size_t i = 0; i < model_.bufferViews.size(); ++i) {
      const auto& bv = model_.bufferViews[i];
      checkIndex(bv.buffer, model_.buffers.size(), strf("bufferViews[%zu].buffer", i), "buffer",
                 "buffers");
      if (bv.byteStride != 0 && (bv.byteStride < 4 || bv.byteStride > 252 || bv.byteStride % 4))
        fail(strf("bufferViews[%zu].byteStride %zu: not a multiple of 4 from 4 to 252", i,
                  bv.byteStride));
      const size_t size = model_.buffers[static_cast<size_t>(bv.buffer)].data.size();
      if (bv.byteOffset > size || bv.byteLength > size - bv.byteOffset)
        fail(strf("bufferView %zu: bytes [%zu, %zu) exceed buffer %d of %zu bytes", i,
                  bv.byteOffset, bv.byteOffset + bv.byteLength, bv.buffer, size));
    }
  }

  // The indices a node holds (its children are checked with the graph).
  void checkNode(size_t i) const {
    const auto& node = model_.nodes[i];
    const std::string at = strf("nodes[%zu]", i);
    if (node.mesh != -1)
      checkIndex(node.mesh, model_.meshes.size(), at + ".mesh", "mesh", "meshes");
    if (node.camera != -1)
      checkIndex(node.camera, model_.cameras.size(), at + ".camera", "camera", "cameras");
    auto le = node.extensions.find("KHR_lights_punctual");
    if (le != node.extensions.end() && le->second.Has("light"))
      checkIndex(le->second.Get("light").GetNumberAsInt(), model_.lights.size(),
                 at + ".extensions.KHR_lights_punctual.light", "light", "lights");
  }

  void validateNodeGraph() const {
    const size_t n = model_.nodes.size();
    std::vector<int> parent(n, -1);
    for (size_t i = 0; i < n; ++i) {
      checkNode(i);
      const auto& children = model_.nodes[i].children;
      for (size_t k = 0; k < children.size(); ++k) {
        const int c = children[k];
        checkIndex(c, n, strf("nodes[%zu].children[%zu]", i, k), "node", "nodes");
        if (static_cast<size_t>(c) == i) fail(strf("node %zu: is its own child (cycle)", i));
        if (parent[static_cast<size_t>(c)] >= 0)
          fail(strf("node %d: has two parents (%d and %zu); the node graph must be a forest", c,
                    parent[static_cast<size_t>(c)], i));
        parent[static_cast<size_t>(c)] = static_cast<int>(i);
      }
    }
    // With one parent each, a cycle is a loop of parent links. Node i's walk up
    // stops at a root or at a node an earlier walk showed to reach one, and meets
    // itself again only on a loop: each node is walked once, however deep the
    // hierarchy.
    std::vector<char> rooted(n, 0);
    std::vector<size_t> walkedFrom(n, n);  // the node whose walk passed here; n: none
    std::vector<size_t> walk;
    for (size_t i = 0; i < n; ++i) {
      walk.clear();
      for (size_t u = i; !rooted[u];) {
        if (walkedFrom[u] == i) fail(strf("node %zu: cycle in the node graph", i));
        walkedFrom[u] = i;
        walk.push_back(u);
        if (parent[u] < 0) break;
        u = static_cast<size_t>(parent[u]);
      }
      for (size_t u : walk) rooted[u] = 1;
    }
    checkScenes(parent);
  }

  void checkScenes(const std::vector<int>& parent) const {
    const size_t count = model_.scenes.size();
    if (model_.defaultScene != -1 &&
        (model_.defaultScene < 0 || static_cast<size_t>(model_.defaultScene) >= count))
      fail(strf("scene %d out of range (%s)", model_.defaultScene,
                countOf(count, "scene", "scenes").c_str()));
    for (size_t s = 0; s < count; ++s) {
      const auto& roots = model_.scenes[s].nodes;
      for (size_t k = 0; k < roots.size(); ++k) {
        const std::string at = strf("scenes[%zu].nodes[%zu]", s, k);
        checkIndex(roots[k], model_.nodes.size(), at, "node", "nodes");
        const int p = parent[static_cast<size_t>(roots[k])];
        if (p >= 0)
          fail(strf("%s %d is not a root node: node %d is its parent", at.c_str(), roots[k], p));
        if (std::find(roots.begin(), roots.begin() + static_cast<long>(k), roots[k]) !=
            roots.begin() + static_cast<long>(k))
          fail(strf("%s %d is listed twice", at.c_str(), roots[k]));
      }
    }
  }

  // Transforms are composed in double precision: a scene placed 10^4 units from
  // the origin keeps its detail (positions are stored relative to Scene::origin).
  glm::dmat4 localMatrix(const tinygltf::Node& node, int index) const {
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

  View accessor(int index, const char* what, std::initializer_list<int> types,
                std::initializer_list<int> componentTypes) const {
    checkIndex(index, model_.accessors.size(), strf("%s: accessor", what), "accessor", "accessors");
    const auto& a = model_.accessors[static_cast<size_t>(index)];
    if (std::find(types.begin(), types.end(), a.type) == types.end())
      fail(strf("accessor %d (%s): element type %s is not allowed here", index, what,
                typeName(a.type)));
    if (std::find(componentTypes.begin(), componentTypes.end(), a.componentType) ==
        componentTypes.end())
      fail(strf("accessor %d (%s): wrong component type %d", index, what, a.componentType));
    if (a.normalized && (a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
                         a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
      fail(strf("accessors[%d] (%s): normalized %s components: only 8- and 16-bit integers can be",
                index, what, componentName(a.componentType)));
    if (a.bufferView != -1)
      checkIndex(a.bufferView, model_.bufferViews.size(), strf("accessors[%d].bufferView", index),
                 "bufferView", "bufferViews");
    if (a.count == 0 || a.count > (size_t{1} << 31))
      fail(strf("accessor %d (%s): count %zu out of range", index, what, a.count));
    const int compSize = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(a.componentType));
    const int nComp = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
    if (compSize <= 0 || nComp <= 0) fail(strf("accessor %d (%s): invalid type", index, what));
    const size_t elem = static_cast<size_t>(compSize) * static_cast<size_t>(nComp);
    View v;
    v.count = a.count;
    v.componentType = a.componentType;
    v.type = a.type;
    v.normalized = a.normalized;
    if (a.bufferView != -1) {
      const auto& bv = model_.bufferViews[static_cast<size_t>(a.bufferView)];
      const size_t stride = bv.byteStride ? bv.byteStride : elem;
      if (stride < elem)
        fail(strf("accessor %d (%s): byteStride %zu is smaller than an element (%zu)", index, what,
                  stride, elem));
      const size_t need = a.byteOffset + stride * (a.count - 1) + elem;
      if (a.byteOffset > bv.byteLength || need > bv.byteLength)
        fail(strf("accessor %d (%s): needs %zu bytes, bufferView %d has %zu", index, what, need,
                  a.bufferView, bv.byteLength));
      checkAlignment(index, what, a, bv, compSize, stride);
      const auto& buf = model_.buffers[static_cast<size_t>(bv.buffer)];
      v.data = buf.data.data() + bv.byteOffset + a.byteOffset;
      v.stride = stride;
    }
    if (a.bufferView == -1 || a.sparse.isSparse) densify(index, what, a, elem, compSize, &v);
    checkBounds(index, what, a, v, nComp, compSize);
    return v;
  }

  // glTF 2.0's accessors without a bufferView hold zeros; a sparse part then
  // replaces the elements it lists. Either way `v` becomes a tightly packed copy:
  // the base (the bufferView's elements, or zeros) with the sparse values put in.
  void densify(int index, const char* what, const tinygltf::Accessor& a, size_t elem, int compSize,
               View* v) const {
    if (a.count > kMaxDenseBytes / elem)
      fail(
          strf("accessors[%d] (%s): %zu elements without a bufferView or with a sparse part: "
               "over the %zu MiB limit of such accessors here",
               index, what, a.count, kMaxDenseBytes >> 20));
    auto dense = std::make_shared<std::vector<unsigned char>>(a.count * elem, 0);
    if (v->data)
      for (size_t i = 0; i < a.count; ++i)
        std::memcpy(dense->data() + i * elem, v->data + i * v->stride, elem);
    if (a.sparse.isSparse) substituteSparse(index, a, elem, compSize, dense->data());
    v->data = dense->data();
    v->stride = elem;
    v->dense = std::move(dense);
  }

  // A sparse part: `count` strictly increasing element indices (unsigned 8, 16 or
  // 32 bits) and as many elements, each written over the base at its index.
  void substituteSparse(int index, const tinygltf::Accessor& a, size_t elem, int compSize,
                        unsigned char* dense) const {
    const auto& sp = a.sparse;
    const std::string at = strf("accessors[%d].sparse", index);
    if (sp.count < 1 || static_cast<size_t>(sp.count) > a.count)
      fail(strf("%s.count %d: must be from 1 to the accessor's count %zu", at.c_str(), sp.count,
                a.count));
    const int it = sp.indices.componentType;
    if (it != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        it != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT && it != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      fail(strf("%s.indices.componentType %d: not UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT",
                at.c_str(), it));
    const auto n = static_cast<size_t>(sp.count);
    const auto isz =
        static_cast<size_t>(tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(it)));
    const unsigned char* indices =
        sparseBytes(at + ".indices", sp.indices.bufferView, sp.indices.byteOffset, n * isz, isz);
    const unsigned char* values =
        sparseBytes(at + ".values", sp.values.bufferView, sp.values.byteOffset, n * elem,
                    static_cast<size_t>(compSize));
    uint32_t previous = 0;
    for (size_t k = 0; k < n; ++k) {
      const auto i = static_cast<uint32_t>(rawComponent(indices + k * isz, it));
      if (i >= a.count)
        fail(strf("%s.indices[%zu] %u: out of range (the accessor has %zu elements)", at.c_str(), k,
                  i, a.count));
      if (k > 0 && i <= previous)
        fail(
            strf("%s.indices[%zu] %u: not greater than the index before it (%u); sparse indices "
                 "must strictly increase",
                 at.c_str(), k, i, previous));
      previous = i;
      std::memcpy(dense + static_cast<size_t>(i) * elem, values + k * elem, elem);
    }
  }

  // `bytes` bytes of sparse indices or values (`at` names them) from `offset` in
  // bufferView `view`, whose components are `align` bytes.
  const unsigned char* sparseBytes(const std::string& at, int view, int offset, size_t bytes,
                                   size_t align) const {
    checkIndex(view, model_.bufferViews.size(), at + ".bufferView", "bufferView", "bufferViews");
    const auto& bv = model_.bufferViews[static_cast<size_t>(view)];
    if (bv.byteStride != 0)
      fail(strf("%s.bufferView %d: has a byteStride (%zu), which sparse data must not have",
                at.c_str(), view, bv.byteStride));
    if (offset < 0 || static_cast<size_t>(offset) % align ||
        (bv.byteOffset + static_cast<size_t>(offset)) % align)
      fail(
          strf("%s.byteOffset %d (in bufferView %d at %zu): not a multiple of the %zu-byte "
               "component size",
               at.c_str(), offset, view, bv.byteOffset, align));
    const auto off = static_cast<size_t>(offset);
    if (off > bv.byteLength || bytes > bv.byteLength - off)
      fail(strf("%s: needs %zu bytes from byte %d, bufferView %d has %zu", at.c_str(), bytes,
                offset, view, bv.byteLength));
    return model_.buffers[static_cast<size_t>(bv.buffer)].data.data() + bv.byteOffset + off;
  }

  // The spec's alignment rules: components on their own size; vertex attribute
  // elements on 4 bytes; index data tightly packed.
  void checkAlignment(int index, const char* what, const tinygltf::Accessor& a,
                      const tinygltf::BufferView& bv, int compSize, size_t stride) const {
    const auto cs = static_cast<size_t>(compSize);
    if (a.byteOffset % cs || (bv.byteOffset + a.byteOffset) % cs)
      fail(
          strf("accessors[%d].byteOffset %zu (in bufferView %d at %zu): not a multiple of the "
               "%d-byte component size",
               index, a.byteOffset, a.bufferView, bv.byteOffset, compSize));
    if (bv.byteStride % cs)
      fail(
          strf("bufferViews[%d].byteStride %zu: not a multiple of accessor %d's %d-byte "
               "components",
               a.bufferView, bv.byteStride, index, compSize));
    const std::string_view role(what);
    if ((role == "POSITION" || role == "NORMAL" || role.substr(0, 9) == "TEXCOORD_" ||
         role == "COLOR_0" || role == "TANGENT") &&
        (a.byteOffset % 4 || stride % 4))
      fail(
          strf("accessors[%d] (%s): elements of %zu bytes at offset %zu are not 4-byte aligned, "
               "as vertex attributes must be",
               index, what, stride, a.byteOffset));
    if (role == "indices" && bv.byteStride != 0)
      fail(strf("bufferViews[%d].byteStride %zu: index data must not have a byteStride",
                a.bufferView, bv.byteStride));
  }

  static double rawComponent(const unsigned char* p, int componentType) {
    switch (componentType) {
      case TINYGLTF_COMPONENT_TYPE_BYTE:
        return static_cast<double>(static_cast<int8_t>(*p));
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return static_cast<double>(*p);
      case TINYGLTF_COMPONENT_TYPE_SHORT: {
        int16_t v;
        std::memcpy(&v, p, 2);
        return v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t v;
        std::memcpy(&v, p, 2);
        return v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        uint32_t v;
        std::memcpy(&v, p, 4);
        return v;
      }
      default: {
        float v;
        std::memcpy(&v, p, 4);
        return static_cast<double>(v);
      }
    }
  }

  // min and max: required for POSITION and animation input; where given, they
  // must be the data's bounds (compared as the component type stores them).
  void checkBounds(int index, const char* what, const tinygltf::Accessor& a, const View& v,
                   int nComp, int compSize) const {
    const std::string_view role(what);
    const bool required = role == "POSITION" || role == "animation input";
    if (a.minValues.empty() && a.maxValues.empty() && !required) return;
    const auto n = static_cast<size_t>(nComp);
    if (a.minValues.size() != n || a.maxValues.size() != n)
      fail(strf("accessors[%d] (%s): min and max must both be given, %d numbers each", index, what,
                nComp));
    const bool isFloat = a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT;
    auto stored = [&](double x) {
      return isFloat ? static_cast<double>(static_cast<float>(x)) : x;
    };
    for (size_t c = 0; c < n; ++c) {
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (size_t i = 0; i < v.count; ++i) {
        const double x = rawComponent(v.data + i * v.stride + c * static_cast<size_t>(compSize),
                                      a.componentType);
        if (!std::isfinite(x)) continue;  // refused, or repaired, where it is read
        lo = std::min(lo, x);
        hi = std::max(hi, x);
      }
      if (lo > hi) continue;
      if (stored(a.minValues[c]) != lo)
        fail(strf("accessors[%d].min[%zu] %.9g: the data's minimum is %.9g", index, c,
                  a.minValues[c], lo));
      if (stored(a.maxValues[c]) != hi)
        fail(strf("accessors[%d].max[%zu] %.9g: the data's maximum is %.9g", index, c,
                  a.maxValues[c], hi));
    }
  }

  static float readComponent(const unsigned char* p, int componentType, bool normalized) {
    switch (componentType) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: {
        float f;
        std::memcpy(&f, p, 4);
        return f;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return normalized ? static_cast<float>(*p) / 255.0f : static_cast<float>(*p);
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t u;
        std::memcpy(&u, p, 2);
        return normalized ? static_cast<float>(u) / 65535.0f : static_cast<float>(u);
      }
      // Signed normalized: c / (2^(b-1) - 1), the most negative value clamped to -1
      // (glTF 2.0, "Animations"; KHR_mesh_quantization).
      case TINYGLTF_COMPONENT_TYPE_BYTE: {
        const auto c = static_cast<float>(static_cast<int8_t>(*p));
        return normalized ? std::max(c / 127.0f, -1.0f) : c;
      }
      case TINYGLTF_COMPONENT_TYPE_SHORT: {
        int16_t i;
        std::memcpy(&i, p, 2);
        const auto c = static_cast<float>(i);
        return normalized ? std::max(c / 32767.0f, -1.0f) : c;
      }
      default:
        return 0.0f;
    }
  }

  void readMaterials() {
    for (size_t i = 0; i < model_.materials.size(); ++i) {
      const auto& m = model_.materials[i];
      Material mat;
      mat.name = m.name;
      const std::string what = strf("material %zu", i);
      const auto& pbr = m.pbrMetallicRoughness;
      if (pbr.baseColorFactor.size() == 4)
        mat.baseColor = glm::vec4(toVec3(pbr.baseColorFactor, what + ": baseColorFactor"),
                                  toFloat(pbr.baseColorFactor[3], what + ": baseColorFactor"));
      mat.metallic = toFloat(pbr.metallicFactor, what + ": metallicFactor");
      mat.roughness = toFloat(pbr.roughnessFactor, what + ": roughnessFactor");
      if (m.emissiveFactor.size() == 3)
        mat.emission = toVec3(m.emissiveFactor, what + ": emissiveFactor");
      auto it = m.extensions.find("KHR_materials_emissive_strength");
      if (it != m.extensions.end() && it->second.Has("emissiveStrength"))
        mat.emission *= toFloat(it->second.Get("emissiveStrength").GetNumberAsDouble(),
                                what + ": emissiveStrength");
      mat.doubleSided = m.doubleSided;
      mat.alphaMode = m.alphaMode == "MASK"    ? AlphaMode::kMask
                      : m.alphaMode == "BLEND" ? AlphaMode::kBlend
                                               : AlphaMode::kOpaque;
      mat.alphaCutoff = toFloat(m.alphaCutoff, what + ": alphaCutoff");
      const glm::vec4 bc = mat.baseColor;
      if (!finite(glm::vec3(bc)) || !std::isfinite(bc.w) || !finite(mat.emission) ||
          !std::isfinite(mat.metallic) || !std::isfinite(mat.roughness))
        fail(strf("material %zu: NaN or Inf factor", i));
      mat.baseColor = glm::clamp(mat.baseColor, 0.0f, 1.0f);
      mat.metallic = std::clamp(mat.metallic, 0.0f, 1.0f);
      mat.roughness = std::clamp(mat.roughness, 0.0f, 1.0f);
      mat.emission = glm::max(mat.emission, 0.0f);
      const std::string at = strf("materials[%zu]", i);
      const std::string pbrAt = at + ".pbrMetallicRoughness";
      if (pbr.baseColorTexture.index != -1) {
        mat.baseColorTexture = texture(pbr.baseColorTexture.index, true);
        mat.baseColorUv = transform(pbr.baseColorTexture.texCoord, pbr.baseColorTexture.extensions,
                                    pbrAt + ".baseColorTexture");
      }
      if (pbr.metallicRoughnessTexture.index != -1) {
        mat.metallicRoughnessTexture = texture(pbr.metallicRoughnessTexture.index, false);
        mat.metallicRoughnessUv =
            transform(pbr.metallicRoughnessTexture.texCoord,
                      pbr.metallicRoughnessTexture.extensions, pbrAt + ".metallicRoughnessTexture");
      }
      if (m.emissiveTexture.index != -1 && mat.isEmissive()) {
        mat.emissiveTexture = texture(m.emissiveTexture.index, true);
        mat.emissiveUv = transform(m.emissiveTexture.texCoord, m.emissiveTexture.extensions,
                                   at + ".emissiveTexture");
      }
      if (m.normalTexture.index != -1) {
        mat.normalTexture = texture(m.normalTexture.index, false);
        mat.normalScale = toFloat(m.normalTexture.scale, what + ": normalTexture.scale");
        mat.normalUv =
            transform(m.normalTexture.texCoord, m.normalTexture.extensions, at + ".normalTexture");
      }
      if (m.occlusionTexture.index != -1) {
        mat.occlusionTexture = texture(m.occlusionTexture.index, false);
        mat.occlusionStrength =
            toFloat(m.occlusionTexture.strength, what + ": occlusionTexture.strength");
        mat.occlusionUv = transform(m.occlusionTexture.texCoord, m.occlusionTexture.extensions,
                                    at + ".occlusionTexture");
      }
      bakeChannels(&mat, at);
      scene_.materials.push_back(mat);
    }
    // The glTF default material, for primitives without one.
    defaultMaterial_ = static_cast<int>(scene_.materials.size());
    Material d;
    d.name = "default";
    scene_.materials.push_back(d);
    uvField_.push_back({});
  }

  // A texture a material reads: its source and sampler must exist (a texture no
  // material uses is not read, so not checked). `srgb`: a colour texture (base
  // colour, emissive), decoded from sRGB where it is sampled; else a data texture
  // (metallic-roughness), read linearly. One entry per texture and encoding.
  int texture(int index, bool srgb) {
    auto found = textureMap_.find({index, srgb});
    if (found != textureMap_.end()) return found->second;
    const auto& tex = model_.textures[static_cast<size_t>(index)];
    const int source = tex.source;
    checkIndex(source, model_.images.size(), strf("textures[%d].source", index), "image", "images");
    if (tex.sampler != -1)
      checkIndex(tex.sampler, model_.samplers.size(), strf("textures[%d].sampler", index),
                 "sampler", "samplers");
    const auto& img = model_.images[static_cast<size_t>(source)];
    if (img.image.empty() || img.width <= 0 || img.height <= 0)
      fail(strf("image %d: missing or unreadable image '%s'", source, img.uri.c_str()));
    Texture t;
    if (tex.sampler != -1) readSampler(tex.sampler, &t);
    t.name = img.uri.empty() ? img.name : img.uri;
    t.width = img.width;
    t.height = img.height;
    t.rgba8 = img.image;  // decoded to RGBA8 by loadImage
    t.srgb = srgb;
    scene_.textures.push_back(std::move(t));
    const int id = static_cast<int>(scene_.textures.size() - 1);
    textureMap_[{index, srgb}] = id;
    return id;
  }

  // A texture slot's texture coordinate set and KHR_texture_transform (identity
  // without the extension). `at` names the textureInfo, e.g.
  // "materials[2].pbrMetallicRoughness.baseColorTexture"; the field that names the
  // set goes to texCoordField_[at].
  TextureTransform transform(int texCoord, const tinygltf::ExtensionMap& extensions,
                             const std::string& at) {
    std::string setField = at + ".texCoord";  // where the set is named
    glm::vec2 offset(0.0f), scale(1.0f);
    float rotation = 0.0f;
    auto it = extensions.find("KHR_texture_transform");
    if (it != extensions.end()) {
      const tinygltf::Value& e = it->second;
      const std::string ext = at + ".extensions.KHR_texture_transform";
      if (!e.IsObject()) fail(ext + ": not an object");
      auto number = [&](const tinygltf::Value& v, const std::string& field) {
        if (!v.IsNumber()) fail(field + ": not a number");
        const double d = v.GetNumberAsDouble();
        if (!std::isfinite(d) || std::abs(d) > 1e30)
          fail(strf("%s %g: not finite", field.c_str(), d));
        return static_cast<float>(d);
      };
      auto pair = [&](const char* name, glm::vec2 fallback) {
        if (!e.Has(name)) return fallback;
        const tinygltf::Value& v = e.Get(name);
        const std::string field = ext + "." + name;
        if (!v.IsArray() || v.ArrayLen() != 2) fail(field + ": needs 2 numbers");
        return glm::vec2(number(v.Get(0), field + "[0]"), number(v.Get(1), field + "[1]"));
      };
      offset = pair("offset", offset);
      scale = pair("scale", scale);
      if (e.Has("rotation")) rotation = number(e.Get("rotation"), ext + ".rotation");
      if (e.Has("texCoord")) {
        const tinygltf::Value& v = e.Get("texCoord");
        if (!v.IsInt() || v.GetNumberAsInt() < 0)
          fail(ext + ".texCoord: not a non-negative integer");
        texCoord = v.GetNumberAsInt();
        setField = ext + ".texCoord";
      }
    }
    if (texCoord < 0) fail(strf("%s.texCoord %d: negative", at.c_str(), texCoord));
    TextureTransform t = textureTransform(offset, rotation, scale);
    t.texCoord = texCoord;
    texCoordField_[at] = setField;
    return t;
  }

  // The channels baked into the vertex UVs of the primitives drawn with `mat`:
  // its textures grouped by mapping (set and transform), the first distinct one
  // (the base colour's, else the first texture's) into channel 0 (mat->uv), the
  // second into channel 1 (mat->uv2); each texture's *Channel names its own. A
  // third distinct mapping is read through channel 0, with a warning. Records in
  // uvField_ the fields that name the two channels' sets.
  void bakeChannels(Material* mat, const std::string& at) {
    struct Slot {
      const char* name;
      const TextureTransform* uv;
      int* channel;
    };
    std::vector<Slot> slots;
    if (mat->baseColorTexture >= 0)
      slots.push_back({"baseColorTexture", &mat->baseColorUv, &mat->baseColorChannel});
    if (mat->metallicRoughnessTexture >= 0)
      slots.push_back(
          {"metallicRoughnessTexture", &mat->metallicRoughnessUv, &mat->metallicRoughnessChannel});
    if (mat->emissiveTexture >= 0)
      slots.push_back({"emissiveTexture", &mat->emissiveUv, &mat->emissiveChannel});
    if (mat->normalTexture >= 0)
      slots.push_back({"normalTexture", &mat->normalUv, &mat->normalChannel});
    if (mat->occlusionTexture >= 0)
      slots.push_back({"occlusionTexture", &mat->occlusionUv, &mat->occlusionChannel});
    auto field = [&](const char* name) {
      const std::string n = name;
      const bool pbr = n == "baseColorTexture" || n == "metallicRoughnessTexture";
      return texCoordField_[at + (pbr ? ".pbrMetallicRoughness." : ".") + n];
    };
    std::array<std::string, 2> fields;
    if (slots.empty()) {
      uvField_.push_back(fields);
      return;
    }
    mat->uv = *slots.front().uv;
    fields[0] = field(slots.front().name);
    const char* second = nullptr;
    for (const Slot& slot : slots) {
      if (*slot.uv == mat->uv) {
        *slot.channel = 0;
      } else if (!mat->hasUv2 || *slot.uv == mat->uv2) {
        if (!mat->hasUv2) {
          mat->hasUv2 = true;
          mat->uv2 = *slot.uv;
          fields[1] = field(slot.name);
          second = slot.name;
        }
        *slot.channel = 1;
      } else {
        *slot.channel = 0;
        if (!uvWarned_)
          warn_(
              strf("%s: %s reads a third set of texture coordinates (texCoord or "
                   "KHR_texture_transform) after those of %s and %s; it reads those of %s",
                   at.c_str(), slot.name, slots.front().name, second, slots.front().name));
        uvWarned_ = true;
      }
    }
    uvField_.push_back(fields);
  }

  // Sampler `index`'s wrap modes and filters into `t`; a field the sampler leaves
  // out keeps the default (repeat; linear, trilinear).
  void readSampler(int index, Texture* t) const {
    const auto& s = model_.samplers[static_cast<size_t>(index)];
    const std::string at = strf("samplers[%d]", index);
    auto wrap = [&](int w, const char* field) {
      if (w != kWrapRepeat && w != kWrapClampToEdge && w != kWrapMirroredRepeat)
        fail(
            strf("%s.%s %d: not REPEAT (10497), CLAMP_TO_EDGE (33071) or MIRRORED_REPEAT "
                 "(33648)",
                 at.c_str(), field, w));
      return w;
    };
    t->wrapS = wrap(s.wrapS, "wrapS");
    t->wrapT = wrap(s.wrapT, "wrapT");
    if (s.magFilter != -1) {
      if (s.magFilter != kFilterNearest && s.magFilter != kFilterLinear)
        fail(strf("%s.magFilter %d: not NEAREST (9728) or LINEAR (9729)", at.c_str(), s.magFilter));
      t->magFilter = s.magFilter;
    }
    if (s.minFilter != -1) {
      if (s.minFilter != kFilterNearest && s.minFilter != kFilterLinear &&
          (s.minFilter < kFilterNearestMipmapNearest || s.minFilter > kFilterLinearMipmapLinear))
        fail(
            strf("%s.minFilter %d: not NEAREST, LINEAR or one of their MIPMAP variants "
                 "(9728, 9729, 9984-9987)",
                 at.c_str(), s.minFilter));
      t->minFilter = s.minFilter;
    }
  }

  void traverse() {
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
  void dropDegenerateInFloat() {
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

  static bool degenerateInFloat(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
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
  void applyOrigin() {
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
  // voxgi does not implement, extra scenes, skins, morph targets, BLEND materials,
  // points and lines, cameras not used.
  void warnIgnored() {
    for (const std::string& e : model_.extensionsUsed)
      if (!kSupportedExtensions.count(e))
        warn_("extension " + e + " is not supported; " + renderedWithout(e));
    if (model_.scenes.size() > 1)
      warn_(
          strf("%zu scenes: only scenes[%d] is drawn (%s)", model_.scenes.size(),
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
      warn_(i.weightChannels.named("channels") +
            ": morph target weights are not animated; skipped");
    warnBlend();
    if (i.pointsAndLines.count())
      warn_(i.pointsAndLines.named("primitives") + ": points and lines are not rendered; skipped");
    const std::string view =
        camera_ >= 0 ? strf("the view is from cameras[%d]", camera_) : "framing the scene instead";
    if (i.orthographic.count())
      warn_(i.orthographic.named("cameras") + ": orthographic cameras are not used; " + view);
    if (i.laterCameras.count())
      warn_(i.laterCameras.named("cameras") + ": only the first perspective camera is used; " +
            view);
  }

  // The materials drawn with alphaMode BLEND: drawn opaque (alpha ignored).
  void warnBlend() {
    std::set<int> drawn;
    for (const Draw& d : scene_.draws) drawn.insert(d.material);
    Tally blend;
    for (int m : drawn)
      if (m != defaultMaterial_ && model_.materials[static_cast<size_t>(m)].alphaMode == "BLEND")
        blend.add(strf("materials[%d]", m));
    if (blend.count()) warn_(blend.named("materials") + ": alphaMode BLEND is drawn opaque");
  }

  void addCamera(int index, int node, const glm::dmat4& world) {
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

  void addLight(int index, int node, const glm::dmat4& world) {
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

  void addMesh(int meshIndex, int nodeIndex, const glm::dmat4& world) {
    const auto& mesh = model_.meshes[static_cast<size_t>(meshIndex)];
    for (size_t pi = 0; pi < mesh.primitives.size(); ++pi)
      addPrimitive(meshIndex, pi, nodeIndex, world);
  }

  void addPrimitive(int meshIndex, size_t pi, int nodeIndex, const glm::dmat4& world) {
    const auto& prim = model_.meshes[static_cast<size_t>(meshIndex)].primitives[pi];
    const std::string where = strf("mesh %d primitive %zu", meshIndex, pi);
    const int mode = prim.mode == -1 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (mode < 0 || mode > 6)
      fail(strf("%s: mode %d is not a glTF primitive mode (0-6)", where.c_str(), mode));
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      ignored_.pointsAndLines.add(where);
      return;
    }
    if (!prim.targets.empty()) ignored_.morphed.add(where);
    const PrimitiveAttributes attr = readAttributes(prim, where);
    const size_t count = attr.position.count;
    const std::vector<uint32_t> idx = triangleList(readIndices(prim, count, where), mode);
    const bool mirrored = glm::determinant(glm::dmat3(world)) < 0.0;
    const size_t base = scene_.vertices.size();
    addVertices(attr, base, world, where);
    std::vector<glm::dvec3> faceSum(count, glm::dvec3(0.0));
    const std::vector<uint32_t> kept = keepNonDegenerate(idx, base, mirrored, where, &faceSum);
    repairNormals(base, faceSum, attr.hasNormals, where);
    if (attr.normalMapped || !scene_.tangents.empty()) {
      // (1, 0, 0, 1) before the first normal-mapped primitive and for primitives
      // without a normal map: never read.
      scene_.tangents.resize(base + count, glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
      if (attr.normalMapped)
        readTangents(attr.tangent, attr.hasTangent, attr.normalChannel, kept, base, world,
                     mirrored);
    }
    if (kept.empty()) return;
    if (moving_[static_cast<size_t>(nodeIndex)])
      addAnimatedRange(nodeIndex, base, count, world, mirrored);
    addDraw(prim, meshIndex, nodeIndex, base, kept, where);
  }

  // POSITION, NORMAL, the material's TEXCOORD_n, COLOR_0 and TANGENT, in that order.
  PrimitiveAttributes readAttributes(const tinygltf::Primitive& prim, const std::string& where) {
    PrimitiveAttributes a;
    auto pos = prim.attributes.find("POSITION");
    if (pos == prim.attributes.end()) fail(where + ": no POSITION attribute");
    a.position = vertexAttribute(pos->second, "POSITION");
    const size_t count = a.position.count;
    if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
      a.normal = vertexAttribute(it->second, "NORMAL");
      if (a.normal.count != count) fail(where + ": NORMAL and POSITION counts differ");
      a.hasNormals = true;
    }
    // The texture coordinates the material's textures read (Material::uv, uv2),
    // baked with their KHR_texture_transform into the vertex UVs.
    const bool hasMaterial =
        prim.material >= 0 && static_cast<size_t>(prim.material) < model_.materials.size();
    const Material* mat =
        hasMaterial ? &scene_.materials[static_cast<size_t>(prim.material)] : nullptr;
    if (mat) {
      a.uvMap[0] = mat->uv;
      a.uvMap[1] = mat->hasUv2 ? mat->uv2 : mat->uv;
    }
    for (int c = 0; c < 2; ++c) {
      const int set = a.uvMap[c].texCoord;
      const std::string uvName = strf("TEXCOORD_%d", set);
      if (auto it = prim.attributes.find(uvName); it != prim.attributes.end()) {
        a.uv[c] = vertexAttribute(it->second, uvName.c_str());
        if (a.uv[c].count != count)
          fail(strf("%s: %s and POSITION counts differ", where.c_str(), uvName.c_str()));
        a.hasUv[c] = true;
      } else if (set != 0) {
        const std::array<std::string, 2>& fields = uvField_[static_cast<size_t>(prim.material)];
        fail(strf("%s: %s %d: the primitive has no %s attribute", where.c_str(),
                  (c == 1 && !fields[1].empty() ? fields[1] : fields[0]).c_str(), set,
                  uvName.c_str()));
      }
    }
    if (auto it = prim.attributes.find("COLOR_0"); it != prim.attributes.end()) {
      a.color = colorAttribute(it->second, count, where);
      a.hasColor = true;
    }
    if (auto it = prim.attributes.find("TANGENT"); it != prim.attributes.end()) {
      a.tangent = tangentAttribute(it->second, count, where);
      a.hasTangent = true;
    }
    a.normalMapped = mat && mat->normalTexture >= 0;
    a.normalChannel = mat ? mat->normalChannel : 0;
    return a;
  }

  View colorAttribute(int index, size_t count, const std::string& where) const {
    const View col = accessor(index, "COLOR_0", {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4},
                              {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                               TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT});
    if (col.count != count) fail(where + ": COLOR_0 and POSITION counts differ");
    if (col.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT && !col.normalized)
      fail(strf("accessors[%d] (COLOR_0): integer colours must be normalized", index));
    return col;
  }

  View tangentAttribute(int index, size_t count, const std::string& where) const {
    const View tan =
        accessor(index, "TANGENT", {TINYGLTF_TYPE_VEC4}, {TINYGLTF_COMPONENT_TYPE_FLOAT});
    if (tan.count != count) fail(where + ": TANGENT and POSITION counts differ");
    for (size_t i = 0; i < tan.count; ++i)
      for (size_t k = 0; k < 4; ++k)
        if (!std::isfinite(
                readComponent(tan.data + i * tan.stride + 4 * k, tan.componentType, false)))
          fail(strf("accessors[%d] (TANGENT): element %zu is NaN or Inf", index, i));
    return tan;
  }

  // The primitive's indices, each checked against the vertex count; 0, 1, 2, ...
  // without an index accessor.
  std::vector<uint32_t> readIndices(const tinygltf::Primitive& prim, size_t vertexCount,
                                    const std::string& where) const {
    std::vector<uint32_t> idx;
    if (prim.indices == -1) {
      idx.resize(vertexCount);
      for (size_t i = 0; i < vertexCount; ++i) idx[i] = static_cast<uint32_t>(i);
      return idx;
    }
    const View iv =
        accessor(prim.indices, "indices", {TINYGLTF_TYPE_SCALAR},
                 {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                  TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT});
    idx.resize(iv.count);
    for (size_t i = 0; i < iv.count; ++i) {
      const unsigned char* q = iv.data + i * iv.stride;
      uint32_t v = 0;
      if (iv.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE)
        v = *q;
      else if (iv.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
        uint16_t s;
        std::memcpy(&s, q, 2);
        v = s;
      } else
        std::memcpy(&v, q, 4);
      const uint32_t restart = iv.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ? 0xffu
                               : iv.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT
                                   ? 0xffffu
                                   : 0xffffffffu;
      if (v == restart)
        fail(strf("%s: index %u at %zu is the primitive restart value, which glTF forbids",
                  where.c_str(), v, i));
      if (v >= vertexCount)
        fail(strf("%s: index %u at %zu is out of range (%zu vertices)", where.c_str(), v, i,
                  vertexCount));
      idx[i] = v;
    }
    return idx;
  }

  // Appends the primitive's vertices at `base`: world positions (world_), normals
  // by the normal matrix (zero when absent), transformed UVs and colours.
  void addVertices(const PrimitiveAttributes& a, size_t base, const glm::dmat4& world,
                   const std::string& where) {
    const size_t count = a.position.count;
    const glm::mat3 normalMatrix = glm::mat3(glm::transpose(glm::inverse(glm::dmat3(world))));
    scene_.vertices.resize(base + count);
    world_.resize(base + count);
    if (a.hasColor || !scene_.colors.empty()) {
      // White for the vertices before the first coloured primitive and for
      // primitives without COLOR_0.
      scene_.colors.resize(base + count, glm::vec4(1.0f));
      if (a.hasColor) readColors(a.color, base, where);
    }
    for (size_t i = 0; i < count; ++i) {
      Vertex& v = scene_.vertices[base + i];
      const glm::vec3 lp = readVec3(a.position, i);
      if (!finite(lp)) fail(strf("%s: vertex %zu has a NaN or Inf position", where.c_str(), i));
      world_[base + i] = glm::dvec3(world * glm::dvec4(glm::dvec3(lp), 1.0));
      if (!finite(glm::vec3(world_[base + i])))
        fail(strf("%s: vertex %zu overflows after the node transform", where.c_str(), i));
      v.normal = glm::vec3(0.0f);
      if (a.hasNormals) {
        v.normal = normalMatrix * readVec3(a.normal, i);
      }
      v.uv = glm::vec2(0.0f);
      if (a.hasUv[0]) v.uv = readUv(a.uv[0], i, a.uvMap[0]);
      v.uv2 = glm::vec2(0.0f);
      if (a.hasUv[1]) v.uv2 = readUv(a.uv[1], i, a.uvMap[1]);
    }
  }

  // Element i of a TEXCOORD_n accessor through the material's texture transform;
  // (0, 0) where it or the transformed value is NaN or Inf.
  static glm::vec2 readUv(const View& t, size_t i, const TextureTransform& uvMap) {
    const size_t cs = static_cast<size_t>(
        tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(t.componentType)));
    glm::vec2 uv(readComponent(t.data + i * t.stride, t.componentType, t.normalized),
                 readComponent(t.data + i * t.stride + cs, t.componentType, t.normalized));
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) uv = glm::vec2(0.0f);
    uv = uvMap.apply(uv);
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) uv = glm::vec2(0.0f);
    return uv;
  }

  // Drops zero-area triangles (counted in dropped_); adds each kept face's
  // area-weighted normal to faceSum of its three vertices. Mirrored transforms
  // swap the winding back to counter-clockwise.
  std::vector<uint32_t> keepNonDegenerate(const std::vector<uint32_t>& idx, size_t base,
                                          bool mirrored, const std::string& where,
                                          std::vector<glm::dvec3>* faceSum) {
    std::vector<uint32_t> kept;
    kept.reserve(idx.size());
    size_t degenerate = 0;
    for (size_t i = 0; i < idx.size(); i += 3) {
      uint32_t a = idx[i], b = idx[i + 1], c = idx[i + 2];
      if (mirrored) std::swap(b, c);
      const glm::dvec3 e =
          glm::cross(world_[base + b] - world_[base + a], world_[base + c] - world_[base + a]);
      if (!(glm::dot(e, e) > 0.0) || !std::isfinite(glm::dot(e, e))) {
        ++degenerate;
        continue;
      }
      kept.insert(kept.end(), {a, b, c});
      for (uint32_t k : {a, b, c}) (*faceSum)[k] += e;
    }
    if (degenerate) {
      dropped_ += degenerate;
      droppedIn_.push_back(where);
    }
    return kept;
  }

  // Normalizes the normals at `base`; those missing, zero or NaN become the
  // area-weighted average of the faces around the vertex (counted in repaired_
  // when the file had normals).
  void repairNormals(size_t base, const std::vector<glm::dvec3>& faceSum, bool hasNormals,
                     const std::string& where) {
    size_t repaired = 0;
    for (size_t i = 0; i < faceSum.size(); ++i) {
      Vertex& v = scene_.vertices[base + i];
      const float len2 = glm::dot(v.normal, v.normal);
      if (len2 > 0.0f && std::isfinite(len2)) {
        v.normal = glm::normalize(v.normal);
      } else {
        if (hasNormals) ++repaired;
        const double f2 = glm::dot(faceSum[i], faceSum[i]);
        v.normal = f2 > 0.0 && std::isfinite(f2) ? glm::vec3(glm::normalize(faceSum[i]))
                                                 : glm::vec3(0, 1, 0);
      }
    }
    if (repaired) {
      repaired_ += repaired;
      repairedIn_.push_back(where);
    }
  }

  // The vertices at `base` kept in the node's own space, to be re-posed (Scene::pose).
  void addAnimatedRange(int nodeIndex, size_t base, size_t count, const glm::dmat4& world,
                        bool mirrored) {
    AnimatedRange r;
    r.firstVertex = static_cast<uint32_t>(base);
    r.node = nodeIndex;
    const glm::mat3 toLocal = glm::mat3(glm::transpose(glm::dmat3(world)));
    const glm::dmat4 inverse = glm::inverse(world);
    for (size_t i = 0; i < count; ++i) {
      r.localPositions.push_back(glm::dvec3(inverse * glm::dvec4(world_[base + i], 1.0)));
      r.localNormals.push_back(toLocal * scene_.vertices[base + i].normal);
    }
    if (!scene_.tangents.empty()) {
      const glm::mat3 inverse3 = glm::mat3(glm::inverse(glm::dmat3(world)));
      for (size_t i = 0; i < count; ++i) {
        const glm::vec4 wt = scene_.tangents[base + i];
        r.localTangents.push_back(glm::vec4(inverse3 * glm::vec3(wt), mirrored ? -wt.w : wt.w));
      }
    }
    scene_.animatedRanges.push_back(std::move(r));
  }

  void addDraw(const tinygltf::Primitive& prim, int meshIndex, int nodeIndex, size_t base,
               const std::vector<uint32_t>& kept, const std::string& where) {
    Draw d;
    d.firstIndex = static_cast<uint32_t>(scene_.indices.size());
    d.indexCount = static_cast<uint32_t>(kept.size());
    d.node = nodeIndex;
    d.mesh = meshIndex;
    if (prim.material != -1) {
      if (prim.material < 0 || static_cast<size_t>(prim.material) >= model_.materials.size())
        fail(strf("%s: material %d does not exist", where.c_str(), prim.material));
      d.material = prim.material;
    } else {
      d.material = defaultMaterial_;
    }
    for (uint32_t k : kept) scene_.indices.push_back(static_cast<uint32_t>(base) + k);
    scene_.draws.push_back(d);
    drawWhere_.push_back(where);
  }

  // POSITION, NORMAL or TEXCOORD_n with the component types glTF 2.0 allows (float;
  // normalized unsigned byte or short for TEXCOORD_n) and, when the file uses
  // KHR_mesh_quantization, those of the extension's table: POSITION and TEXCOORD_n
  // 8- or 16-bit integers, signed or not, normalized or not; NORMAL normalized
  // signed 8- or 16-bit integers. Read as floats (readComponent).
  View vertexAttribute(int index, const char* role) const {
    const std::string_view r(role);
    const bool texCoord = r.substr(0, 9) == "TEXCOORD_";
    checkIndex(index, model_.accessors.size(), strf("%s: accessor", role), "accessor", "accessors");
    // The component type before the layout: a quantized attribute's elements are
    // laid out differently from a float one's.
    const auto& a = model_.accessors[static_cast<size_t>(index)];
    const int c = a.componentType;
    const bool integer =
        c == TINYGLTF_COMPONENT_TYPE_BYTE || c == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
        c == TINYGLTF_COMPONENT_TYPE_SHORT || c == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
    if (integer) {
      const bool core = texCoord && a.normalized &&
                        (c == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                         c == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
      if (!core && !usesExtension("KHR_mesh_quantization"))
        fail(
            strf("accessors[%d] (%s): %s%s components need KHR_mesh_quantization, which the "
                 "file does not list in extensionsUsed",
                 index, role, a.normalized ? "normalized " : "", componentName(c)));
      if (r == "NORMAL" && !(a.normalized && (c == TINYGLTF_COMPONENT_TYPE_BYTE ||
                                              c == TINYGLTF_COMPONENT_TYPE_SHORT)))
        fail(
            strf("accessors[%d] (NORMAL): %s%s components: KHR_mesh_quantization allows "
                 "normals of normalized BYTE or SHORT only",
                 index, a.normalized ? "normalized " : "", componentName(c)));
    }
    return accessor(index, role, {texCoord ? TINYGLTF_TYPE_VEC2 : TINYGLTF_TYPE_VEC3},
                    {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE,
                     TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_SHORT,
                     TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT});
  }

  bool usesExtension(const char* name) const {
    const auto& used = model_.extensionsUsed;
    return std::find(used.begin(), used.end(), name) != used.end();
  }

  // Element i of a VEC3 accessor as floats.
  static glm::vec3 readVec3(const View& v, size_t i) {
    const auto cs = static_cast<size_t>(
        tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(v.componentType)));
    const unsigned char* q = v.data + i * v.stride;
    return glm::vec3(readComponent(q, v.componentType, v.normalized),
                     readComponent(q + cs, v.componentType, v.normalized),
                     readComponent(q + 2 * cs, v.componentType, v.normalized));
  }

  // Tangents of a normal-mapped primitive into scene_.tangents from `base` on: the
  // file's TANGENT through the node transform (a mirroring transform flips the
  // handedness), or, without one, generated with MikkTSpace (scene/tangents.h) over
  // the primitive's triangles `kept` in world space, with the UVs of `channel` (the
  // one the normal texture reads). A zero tangent or one parallel
  // to its normal gets any perpendicular vector; w is read by its sign.
  void readTangents(const View& t, bool fromFile, int channel, const std::vector<uint32_t>& kept,
                    size_t base, const glm::dmat4& world, bool mirrored) {
    const size_t count = t.count ? t.count : scene_.vertices.size() - base;
    if (!fromFile) {
      std::vector<glm::vec3> pos(count), nrm(count);
      std::vector<glm::vec2> uv(count);
      for (size_t i = 0; i < count; ++i) {
        pos[i] = glm::vec3(world_[base + i] - world_[base]);
        nrm[i] = scene_.vertices[base + i].normal;
        // glTF's v runs down the image, MikkTSpace's up (the bitangent of a glTF
        // tangent points up the image, as exporters write it): v enters flipped.
        const glm::vec2 tuv = channelUv(scene_.vertices[base + i], channel);
        uv[i] = glm::vec2(tuv.x, -tuv.y);
      }
      const std::vector<glm::vec4> gen = generateTangents(pos, nrm, uv, kept);
      std::copy(gen.begin(), gen.end(), scene_.tangents.begin() + static_cast<ptrdiff_t>(base));
      return;
    }
    const glm::mat3 m = glm::mat3(world);
    for (size_t i = 0; i < count; ++i) {
      glm::vec4 lt;
      for (int k = 0; k < 4; ++k)
        lt[k] = readComponent(t.data + i * t.stride + 4 * static_cast<size_t>(k), t.componentType,
                              false);
      const glm::vec3 n = scene_.vertices[base + i].normal;
      glm::vec3 wt = m * glm::vec3(lt);
      wt -= n * glm::dot(n, wt);
      const float len = glm::length(wt);
      wt = len > 1e-6f && std::isfinite(len) ? wt / len : anyPerpendicular(n);
      const float w = (lt.w < 0.0f) != mirrored ? -1.0f : 1.0f;
      scene_.tangents[base + i] = glm::vec4(wt, w);
    }
  }

  // COLOR_0 into scene_.colors from `base` on: VEC3 (alpha 1) or VEC4; a value that
  // is NaN, Inf or outside [0, 1] is clamped (NaN reads as 1).
  void readColors(const View& c, size_t base, const std::string& where) {
    const size_t cs = static_cast<size_t>(
        tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(c.componentType)));
    const int n = c.type == TINYGLTF_TYPE_VEC4 ? 4 : 3;
    size_t bad = 0;
    for (size_t i = 0; i < c.count; ++i) {
      glm::vec4 rgba(1.0f);
      for (int k = 0; k < n; ++k) {
        float x = readComponent(c.data + i * c.stride + static_cast<size_t>(k) * cs,
                                c.componentType, c.normalized);
        if (!(x >= 0.0f && x <= 1.0f)) {
          ++bad;
          x = std::isnan(x) ? 1.0f : std::clamp(x, 0.0f, 1.0f);
        }
        rgba[k] = x;
      }
      scene_.colors[base + i] = rgba;
    }
    if (bad && !colorWarned_) {
      colorWarned_ = true;
      warn_(strf("%s: %zu COLOR_0 components outside [0, 1] (clamped)", where.c_str(), bad));
    }
  }

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

}  // namespace

Scene loadGltf(const std::string& path, const LoadOptions& options) {
  return Loader(path, options).run();
}

Scene loadGltfFromMemory(const void* data, size_t size, const std::string& name,
                         const LoadOptions& options) {
  return Loader(name, options).runFromMemory(static_cast<const unsigned char*>(data), size);
}

}  // namespace voxgi::scene
