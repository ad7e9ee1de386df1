#!/usr/bin/env python3
"""Writes the sampler test scenes: one emissive quad per glTF sampler setting.

Each file holds a 2 x 2 quad in the z = 0 plane, facing +z, seen by a camera at
(0, 0, 2) whose field of view (2 atan(1/2), square images) the quad fills exactly.
Its UVs run outside [0, 1]: s from -1 at the left edge to 2 at the right, t from -1
at the top to 2 at the bottom, so the texture shows three periods a side and the
wrap modes show. The material is black with an emissive texture (factor 1), so
every mode shows the texture's linear value as it is. The texture, 2 x 2 sRGB
texels: red 255 in the right column (40 in the left), green 255 in the bottom row
(40 in the top), blue 0. A pixel's texel tells its column and row apart.

Files, "wrap_S_T_FILTER.gltf": wrapS, wrapT (repeat, clamp, mirror) and the
magnification filter (nearest, linear); and "no_sampler.gltf", whose texture has
no sampler (glTF: repeat, and a filter of the renderer's choosing, linear here).
Used by tests/render/texture_sampler_gltest.cpp, which computes the expected
image from these numbers, and tests/scene/gltf_loader_test.cpp.
Self-contained: buffers and the image are base64 data: URIs. Run from anywhere.
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "animated"))
from gltf_writer import Buffer, png_rgba, quad_document, quad_primitive, write_next_to  # noqa: E402

WRAP = {"repeat": 10497, "clamp": 33071, "mirror": 33648}
FILTER = {"nearest": 9728, "linear": 9729}


TEXELS = [(40, 40, 0, 255), (255, 40, 0, 255),     # top row: left, right
          (40, 255, 0, 255), (255, 255, 0, 255)]   # bottom row


def scene(sampler):
    buf = Buffer()
    pos = [(-1.0, -1.0, 0.0), (1.0, -1.0, 0.0), (1.0, 1.0, 0.0), (-1.0, 1.0, 0.0)]
    uv = [(-1.0, 2.0), (2.0, 2.0), (2.0, -1.0), (-1.0, -1.0)]
    material = {"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1],
                                         "metallicFactor": 0, "roughnessFactor": 1},
                "emissiveFactor": [1, 1, 1],
                "emissiveTexture": {"index": 0}}
    g = quad_document("voxgi make_samplers.py", quad_primitive(buf, pos, [("TEXCOORD_0", uv)]),
                      material, png_rgba(2, 2, TEXELS))
    if sampler is not None:
        g["textures"][0]["sampler"] = 0
        g["samplers"] = [sampler]
    return buf.finish(g)


def write(name, g):
    write_next_to(__file__, name, g)


CASES = [("repeat", "repeat", "nearest"), ("clamp", "clamp", "nearest"),
         ("mirror", "mirror", "nearest"), ("clamp", "mirror", "nearest"),
         ("mirror", "repeat", "linear"), ("repeat", "clamp", "linear")]

for s, t, f in CASES:
    write("wrap_%s_%s_%s.gltf" % (s, t, f),
          scene({"wrapS": WRAP[s], "wrapT": WRAP[t], "magFilter": FILTER[f],
                 "minFilter": FILTER[f]}))
write("no_sampler.gltf", scene(None))
