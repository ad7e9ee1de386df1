// The glTF loader: materials, textures (decoded by stb_image), texture transforms
// and samplers.
#include "scene/gltf_loader_impl.h"

#include <stb_image.h>

namespace voxgi::scene::gltf_detail {

namespace {

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

}  // namespace

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

void Loader::readMaterials() {
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
          transform(pbr.metallicRoughnessTexture.texCoord, pbr.metallicRoughnessTexture.extensions,
                    pbrAt + ".metallicRoughnessTexture");
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
int Loader::texture(int index, bool srgb) {
  auto found = textureMap_.find({index, srgb});
  if (found != textureMap_.end()) return found->second;
  const auto& tex = model_.textures[static_cast<size_t>(index)];
  const int source = tex.source;
  checkIndex(source, model_.images.size(), strf("textures[%d].source", index), "image", "images");
  if (tex.sampler != -1)
    checkIndex(tex.sampler, model_.samplers.size(), strf("textures[%d].sampler", index), "sampler",
               "samplers");
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
TextureTransform Loader::transform(int texCoord, const tinygltf::ExtensionMap& extensions,
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
      if (!v.IsInt() || v.GetNumberAsInt() < 0) fail(ext + ".texCoord: not a non-negative integer");
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
void Loader::bakeChannels(Material* mat, const std::string& at) {
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
void Loader::readSampler(int index, Texture* t) const {
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

}  // namespace voxgi::scene::gltf_detail
