// glTF 2.0 files into a Scene: the entry points, reading the file or memory,
// tinygltf's parse, the GLB and JSON checks.
#include "scene/gltf_loader_impl.h"

namespace voxgi::scene::gltf_detail {

std::string firstLine(const std::string& s) {
  size_t b = s.find_first_not_of(" \n\r\t");
  if (b == std::string::npos) return "";
  size_t e = s.find('\n', b);
  std::string l = s.substr(b, e == std::string::npos ? std::string::npos : e - b);
  while (!l.empty() && (l.back() == '\r' || l.back() == ' ')) l.pop_back();
  return l;
}

// From a file: read whole, then parsed as from memory with external URIs
// resolved next to it.
Scene Loader::run() {
  std::error_code ec;
  if (!fs::exists(path_, ec)) fail("no such file");
  if (fs::is_directory(path_, ec)) fail("is a directory, not a glTF file");
  std::vector<unsigned char> bytes;
  readWholeFile(&bytes);
  std::string baseDir = fs::path(path_).parent_path().string();
  return parse(bytes.data(), bytes.size(), baseDir.empty() ? "." : baseDir, true);
}

// From memory: the same checks; no other file is ever opened.
Scene Loader::runFromMemory(const unsigned char* data, size_t size) {
  return parse(data, size, "", false);
}

void Loader::readWholeFile(std::vector<unsigned char>* out) const {
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

Scene Loader::parse(const unsigned char* data, size_t size, const std::string& baseDir,
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
    ok = gltf.LoadASCIIFromString(&model_, &err, &warn, reinterpret_cast<const char*>(data), length,
                                  baseDir);
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

// double -> float without undefined behaviour: NaN, Inf and values beyond the
// float range are refused with `what` named.
float Loader::toFloat(double v, const std::string& what) const {
  if (!std::isfinite(v) || std::abs(v) > static_cast<double>(std::numeric_limits<float>::max()))
    fail(what + ": NaN or Inf, or beyond the float range");
  return static_cast<float>(v);
}

glm::vec3 Loader::toVec3(const std::vector<double>& v, const std::string& what) const {
  return glm::vec3(toFloat(v[0], what), toFloat(v[1], what), toFloat(v[2], what));
}

void Loader::note_(const std::string& what) {
  logInfo(path_ + ": " + what);
  scene_.notes.push_back(what);
}

void Loader::warn_(const std::string& what) {
  logWarning(path_ + ": " + what);
  scene_.warnings.push_back(what);
}

// A GLB's 12-byte header: magic "glTF", version 2, total length = file size.
void Loader::checkGlbHeader(const unsigned char* h, size_t size) const {
  if (size < 12) fail(strf("truncated GLB: %zu bytes, shorter than the 12-byte header", size));
  if (std::memcmp(h, "glTF", 4) != 0) fail("not a GLB file (bad magic)");
  const uint32_t version = le32(h + 4);
  const uint32_t length = le32(h + 8);
  if (version != 2) fail(strf("GLB version %u is not supported (expected 2)", version));
  if (length > size)
    fail(strf("truncated GLB: header says %u bytes, the file has %zu", length, size));
}

uint32_t Loader::le32(const unsigned char* p) {
  return p[0] | (p[1] << 8) | (p[2] << 16) | (uint32_t{p[3]} << 24);
}

// The JSON chunk of a GLB whose header passed checkGlbHeader (empty when the
// chunk is malformed: tinygltf says why).
std::string_view Loader::glbJson(const unsigned char* data, size_t size) {
  if (size < 20) return {};
  const uint32_t length = le32(data + 12);
  if (length > size - 20) return {};
  return std::string_view(reinterpret_cast<const char*>(data + 20), length);
}

// tinygltf turns "extras" and "extensions" into its Value tree recursively, one
// stack frame per level: a file nested thousands deep would overflow the stack.
// No glTF needs more than a few dozen levels.
void Loader::checkJsonDepth(std::string_view json) const {
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
tinygltf::FsCallbacks Loader::noFiles() {
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
std::string Loader::explainTinygltfError(const std::string& err) {
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

}  // namespace voxgi::scene::gltf_detail

namespace voxgi::scene {

Scene loadGltf(const std::string& path, const LoadOptions& options) {
  return gltf_detail::Loader(path, options).run();
}

Scene loadGltfFromMemory(const void* data, size_t size, const std::string& name,
                         const LoadOptions& options) {
  return gltf_detail::Loader(name, options)
      .runFromMemory(static_cast<const unsigned char*>(data), size);
}

}  // namespace voxgi::scene
