// The glTF loader: accessors, their names and bytes, checked, densified and read.
#include "scene/gltf_loader_impl.h"

namespace voxgi::scene::gltf_detail {

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

Loader::View Loader::accessor(int index, const char* what, std::initializer_list<int> types,
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
void Loader::densify(int index, const char* what, const tinygltf::Accessor& a, size_t elem,
                     int compSize, View* v) const {
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
void Loader::substituteSparse(int index, const tinygltf::Accessor& a, size_t elem, int compSize,
                              unsigned char* dense) const {
  const auto& sp = a.sparse;
  const std::string at = strf("accessors[%d].sparse", index);
  if (sp.count < 1 || static_cast<size_t>(sp.count) > a.count)
    fail(strf("%s.count %d: must be from 1 to the accessor's count %zu", at.c_str(), sp.count,
              a.count));
  const int it = sp.indices.componentType;
  if (it != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && it != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      it != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
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
const unsigned char* Loader::sparseBytes(const std::string& at, int view, int offset, size_t bytes,
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
    fail(strf("%s: needs %zu bytes from byte %d, bufferView %d has %zu", at.c_str(), bytes, offset,
              view, bv.byteLength));
  return model_.buffers[static_cast<size_t>(bv.buffer)].data.data() + bv.byteOffset + off;
}

// The spec's alignment rules: components on their own size; vertex attribute
// elements on 4 bytes; index data tightly packed.
void Loader::checkAlignment(int index, const char* what, const tinygltf::Accessor& a,
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
    fail(strf("bufferViews[%d].byteStride %zu: index data must not have a byteStride", a.bufferView,
              bv.byteStride));
}

double Loader::rawComponent(const unsigned char* p, int componentType) {
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
void Loader::checkBounds(int index, const char* what, const tinygltf::Accessor& a, const View& v,
                         int nComp, int compSize) const {
  const std::string_view role(what);
  const bool required = role == "POSITION" || role == "animation input";
  if (a.minValues.empty() && a.maxValues.empty() && !required) return;
  const auto n = static_cast<size_t>(nComp);
  if (a.minValues.size() != n || a.maxValues.size() != n)
    fail(strf("accessors[%d] (%s): min and max must both be given, %d numbers each", index, what,
              nComp));
  const bool isFloat = a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT;
  auto stored = [&](double x) { return isFloat ? static_cast<double>(static_cast<float>(x)) : x; };
  for (size_t c = 0; c < n; ++c) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (size_t i = 0; i < v.count; ++i) {
      const double x =
          rawComponent(v.data + i * v.stride + c * static_cast<size_t>(compSize), a.componentType);
      if (!std::isfinite(x)) continue;  // refused, or repaired, where it is read
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
    if (lo > hi) continue;
    if (stored(a.minValues[c]) != lo)
      fail(strf("accessors[%d].min[%zu] %.9g: the data's minimum is %.9g", index, c, a.minValues[c],
                lo));
    if (stored(a.maxValues[c]) != hi)
      fail(strf("accessors[%d].max[%zu] %.9g: the data's maximum is %.9g", index, c, a.maxValues[c],
                hi));
  }
}

float Loader::readComponent(const unsigned char* p, int componentType, bool normalized) {
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

// POSITION, NORMAL or TEXCOORD_n with the component types glTF 2.0 allows (float;
// normalized unsigned byte or short for TEXCOORD_n) and, when the file uses
// KHR_mesh_quantization, those of the extension's table: POSITION and TEXCOORD_n
// 8- or 16-bit integers, signed or not, normalized or not; NORMAL normalized
// signed 8- or 16-bit integers. Read as floats (readComponent).
Loader::View Loader::vertexAttribute(int index, const char* role) const {
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
    const bool core =
        texCoord && a.normalized &&
        (c == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || c == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
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

bool Loader::usesExtension(const char* name) const {
  const auto& used = model_.extensionsUsed;
  return std::find(used.begin(), used.end(), name) != used.end();
}

// Element i of a VEC3 accessor as floats.
glm::vec3 Loader::readVec3(const View& v, size_t i) {
  const auto cs = static_cast<size_t>(
      tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(v.componentType)));
  const unsigned char* q = v.data + i * v.stride;
  return glm::vec3(readComponent(q, v.componentType, v.normalized),
                   readComponent(q + cs, v.componentType, v.normalized),
                   readComponent(q + 2 * cs, v.componentType, v.normalized));
}

}  // namespace voxgi::scene::gltf_detail
