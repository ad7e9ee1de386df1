#!/usr/bin/env python3
"""Writes the texture-coordinate test scenes: emissive quads whose texture is read
through TEXCOORD_1 or through KHR_texture_transform.

Each file holds a 2 x 2 quad in the z = 0 plane, facing +z, seen by a camera at
(0, 0, 2) whose field of view (2 atan(1/2), square images) the quad fills exactly,
as in tests/data/samplers. The material is black with an emissive texture (factor
1), so every mode shows the texture's linear value. The texture is the samplers'
2 x 2 one (red 255 in the right column, 40 in the left; green 255 in the bottom
row, 40 in the top), sampled NEAREST with REPEAT.

The "right" coordinates run s from 0 at the left edge to 1 at the right and t from
0 at the top to 1 at the bottom; the "wrong" ones are those flipped on both axes,
so that reading the wrong set shows the opposite texel everywhere.

Files:
  texcoord1.gltf        TEXCOORD_0 wrong, TEXCOORD_1 right, emissiveTexture.texCoord 1.
  transform.gltf        TEXCOORD_0 right, KHR_texture_transform (required) with offset
                        (0.5, 1), rotation pi/2, scale (2, 1).
  transform_texcoord1.gltf  the same transform, TEXCOORD_0 wrong, TEXCOORD_1 right,
                        selected by the extension's texCoord override.
  mixed_transforms.gltf  transform.gltf plus a base-colour texture without the
                        transform: the two textures read two channels, the base
                        colour channel 0 (untransformed), the emissive texture
                        channel 1 (transformed).
  two_sets.gltf         texcoord1.gltf plus a base-colour texture on TEXCOORD_0 (the
                        wrong coordinates): the emissive texture reads channel 1.
  occlusion_texcoord1.gltf  the base colour (factor white) on TEXCOORD_0 (right),
                        the occlusion texture on TEXCOORD_1 (wrong): its red, linear,
                        is 40/255 in the right half of the image, 1 in the left.
  normal_transform.gltf  the base colour untransformed, the normal texture through
                        the transform.
  three_mappings.gltf   mixed_transforms.gltf plus an occlusion texture on TEXCOORD_1:
                        a third mapping (a warning; the occlusion reads channel 0).
  occlusion_strength_0.gltf, occlusion_strength_1.gltf  a white Lambert quad (no
                        emission, the default light) with a 2 x 1 occlusion texture:
                        0 in the left column (fully occluded), 255 in the right;
                        occlusionTexture.strength 0 and 1.
Used by tests/render/texture_coordinates_gltest.cpp (which computes the expected
image from these numbers) and tests/scene/gltf_loader_test.cpp.
Self-contained: buffers and the image are base64 data: URIs. Run from anywhere.
"""
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "animated"))
from gltf_writer import Buffer, png_rgba, quad_document, quad_primitive, write_next_to  # noqa: E402

NEAREST, REPEAT = 9728, 10497


TEXELS = [(40, 40, 0, 255), (255, 40, 0, 255),     # top row: left, right
          (40, 255, 0, 255), (255, 255, 0, 255)]   # bottom row

# Corners: bottom left, bottom right, top right, top left.
POSITIONS = [(-1.0, -1.0, 0.0), (1.0, -1.0, 0.0), (1.0, 1.0, 0.0), (-1.0, 1.0, 0.0)]
RIGHT = [(0.0, 1.0), (1.0, 1.0), (1.0, 0.0), (0.0, 0.0)]
WRONG = [(1.0 - s, 1.0 - t) for s, t in RIGHT]
TRANSFORM = {"offset": [0.5, 1.0], "rotation": math.pi / 2, "scale": [2.0, 1.0]}


SAMPLERS = [{"magFilter": NEAREST, "minFilter": NEAREST, "wrapS": REPEAT, "wrapT": REPEAT}]
GENERATOR = "voxgi make_texcoords.py"


def scene(uv0, uv1, texture_info, required=()):
    buf = Buffer()
    texcoords = [("TEXCOORD_0", uv0)] + ([("TEXCOORD_1", uv1)] if uv1 is not None else [])
    material = {"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1],
                                         "metallicFactor": 0, "roughnessFactor": 1},
                "emissiveFactor": [1, 1, 1],
                "emissiveTexture": dict(texture_info, index=0)}
    g = quad_document(GENERATOR, quad_primitive(buf, POSITIONS, texcoords), material,
                      png_rgba(2, 2, TEXELS), SAMPLERS)
    if required:
        g["extensionsUsed"] = list(required)
        g["extensionsRequired"] = list(required)
    elif "extensions" in texture_info:
        g["extensionsUsed"] = list(texture_info["extensions"])
    return buf.finish(g)


def occlusion(strength):
    buf = Buffer()
    material = {"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1],
                                         "metallicFactor": 0, "roughnessFactor": 1},
                "occlusionTexture": {"index": 0, "strength": strength}}
    png = png_rgba(2, 1, [(0, 0, 0, 255), (255, 255, 255, 255)])
    g = quad_document(GENERATOR, quad_primitive(buf, POSITIONS, [("TEXCOORD_0", RIGHT)]),
                      material, png, SAMPLERS)
    return buf.finish(g)


def write(name, g):
    write_next_to(__file__, name, g)


write("texcoord1.gltf", scene(WRONG, RIGHT, {"texCoord": 1}))
write("transform.gltf", scene(RIGHT, None, {"extensions": {"KHR_texture_transform": TRANSFORM}},
                              required=["KHR_texture_transform"]))
write("transform_texcoord1.gltf",
      scene(WRONG, RIGHT, {"extensions": {"KHR_texture_transform": dict(TRANSFORM, texCoord=1)}}))
mixed = scene(RIGHT, None, {"extensions": {"KHR_texture_transform": TRANSFORM}},
              required=["KHR_texture_transform"])
mixed["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {"index": 0}
write("mixed_transforms.gltf", mixed)
two = scene(WRONG, RIGHT, {"texCoord": 1})
two["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {"index": 0}
write("two_sets.gltf", two)
occ = scene(RIGHT, WRONG, {})
occ["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {"index": 0}
occ["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = [1, 1, 1, 1]
occ["materials"][0]["occlusionTexture"] = {"index": 0, "texCoord": 1}
write("occlusion_texcoord1.gltf", occ)
nrm = scene(RIGHT, None, {}, required=["KHR_texture_transform"])
nrm["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {"index": 0}
nrm["materials"][0]["normalTexture"] = {
    "index": 0, "extensions": {"KHR_texture_transform": TRANSFORM}}
write("normal_transform.gltf", nrm)
three = scene(RIGHT, WRONG, {"extensions": {"KHR_texture_transform": TRANSFORM}},
              required=["KHR_texture_transform"])
three["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {"index": 0}
three["materials"][0]["occlusionTexture"] = {"index": 0, "texCoord": 1}
write("three_mappings.gltf", three)
write("occlusion_strength_0.gltf", occlusion(0.0))
write("occlusion_strength_1.gltf", occlusion(1.0))
