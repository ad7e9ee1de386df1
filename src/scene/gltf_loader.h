// glTF 2.0 (.gltf and .glb) through tinygltf, validated, baked to world space.
//
// Reads: node hierarchy (matrix or TRS), indexed and non-indexed triangles (strips
// and fans converted), normals (generated when missing or broken), TEXCOORD_n,
// metallic-roughness materials with base-colour textures, emission with
// KHR_materials_emissive_strength, KHR_texture_transform, KHR_lights_punctual,
// perspective cameras. The texture coordinates a material's textures read (their
// texCoord and transform) are baked into the vertex UVs of its primitives.
// Bad input throws voxgi::Error with one line "FILE: problem". Unsupported
// primitive modes (points, lines) are skipped with a warning.
#ifndef VOXGI_SCENE_GLTF_LOADER_H
#define VOXGI_SCENE_GLTF_LOADER_H

#include <cstddef>
#include <string>

#include "scene/scene.h"

namespace voxgi::scene {

struct LoadOptions {
  // Largest texture side accepted; larger images are refused before decoding.
  int maxTextureSize = 16384;
  bool addDefaultLight = true;
};

Scene loadGltf(const std::string& path, const LoadOptions& options = {});

// The same from bytes in memory: `name` stands for the path in messages and picks
// the format by its extension (.gltf or .glb). No other file is read: external
// buffers and images are refused (data: URIs and GLB chunks work).
Scene loadGltfFromMemory(const void* data, size_t size, const std::string& name,
                         const LoadOptions& options = {});

}  // namespace voxgi::scene

#endif  // VOXGI_SCENE_GLTF_LOADER_H
