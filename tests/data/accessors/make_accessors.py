#!/usr/bin/env python3
"""Writes twins: scenes stored with KHR_mesh_quantization or sparse accessors, each
beside the same scene in plain float accessors. A twin pair must load to the same
vertices and render the same image (tests/scene/gltf_loader_test.cpp,
tests/render/accessors_gltest.cpp).

quantized.gltf / quantized_float.gltf: four meshes, each under a node whose
transform undoes its quantization (as exporters such as gltfpack write them), all
with one textured material (a 4 x 4 checker) and lit by a directional light:
  mesh 0, a 2 x 2 wall: POSITION SHORT (-100..100, node scale 0.01), NORMAL
          normalized BYTE, TEXCOORD_0 UNSIGNED_BYTE (0..2: the checker twice);
  mesh 1, a tilted tile: POSITION normalized BYTE, NORMAL normalized SHORT,
          TEXCOORD_0 normalized SHORT (-1..1);
  mesh 2, a triangle: POSITION normalized UNSIGNED_SHORT, NORMAL normalized BYTE,
          TEXCOORD_0 BYTE (-1..3);
  mesh 3, a small square: POSITION UNSIGNED_BYTE (0..10, node scale 0.05),
          TEXCOORD_0 normalized UNSIGNED_SHORT, no NORMAL (generated).
The float twin holds each value as the loader dequantizes it: c / (2^b - 1)
unsigned, max(c / (2^(b-1) - 1), -1) signed, rounded to float.

sparse.gltf / sparse_float.gltf: two quads in one primitive (8 vertices), under
the same light and texture. POSITION's base puts the second quad 10 units away; its
sparse part (UNSIGNED_BYTE indices 4..7) moves it beside the first and tilts it.
TEXCOORD_0's sparse part (UNSIGNED_SHORT indices 1 and 2) stretches the first
quad's UVs; NORMAL has no bufferView (zeros) and a sparse part (UNSIGNED_INT
indices 0..7) that gives every vertex its normal.

Self-contained: buffers and the image are base64 data: URIs. Run from anywhere.
"""
import base64
import math
import os
import struct
import zlib
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "animated"))
from gltf_writer import write_next_to  # noqa: E402

BYTE, UNSIGNED_BYTE, SHORT, UNSIGNED_SHORT, UNSIGNED_INT, FLOAT = 5120, 5121, 5122, 5123, 5125, 5126
FORMAT = {BYTE: "b", UNSIGNED_BYTE: "B", SHORT: "h", UNSIGNED_SHORT: "H", UNSIGNED_INT: "I",
          FLOAT: "f"}
SIZE = {BYTE: 1, UNSIGNED_BYTE: 1, SHORT: 2, UNSIGNED_SHORT: 2, UNSIGNED_INT: 4, FLOAT: 4}
COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3}


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def dequantize(c, ctype, normalized):
    """What the loader makes of component c (glTF 2.0 and KHR_mesh_quantization)."""
    if ctype == FLOAT or not normalized:
        return f32(c)
    bits = 8 * SIZE[ctype]
    if ctype in (BYTE, SHORT):
        return max(f32(c / (2 ** (bits - 1) - 1)), -1.0)
    return f32(c / (2 ** bits - 1))


class Writer:
    """One buffer with its views and accessors; vertex attributes padded to 4-byte
    elements (byteStride) where their elements are smaller, as glTF requires."""

    def __init__(self):
        self.blob = b""
        self.views = []
        self.accessors = []

    def view(self, raw, stride=None):
        while len(self.blob) % 4:
            self.blob += b"\0"
        v = {"buffer": 0, "byteOffset": len(self.blob), "byteLength": len(raw)}
        if stride:
            v["byteStride"] = stride
        self.views.append(v)
        self.blob += raw
        return len(self.views) - 1

    def pack(self, values, type_, ctype, pad=True):
        n = COMPONENTS[type_]
        elem = n * SIZE[ctype]
        stride = elem + (-elem % 4) if pad and type_ != "SCALAR" else elem
        raw = b""
        for v in values:
            v = v if isinstance(v, tuple) else (v,)
            raw += struct.pack("<%d%s" % (n, FORMAT[ctype]), *v) + b"\0" * (stride - elem)
        return raw, (stride if stride != elem else None)

    def add(self, values, type_, ctype, normalized=False, minmax=False, sparse=None,
            no_view=False):
        acc = {"componentType": ctype, "count": len(values), "type": type_}
        if not no_view:
            raw, stride = self.pack(values, type_, ctype)
            acc["bufferView"] = self.view(raw, stride)
        if normalized:
            acc["normalized"] = True
        if sparse:
            indices, itype, replacement = sparse
            acc["sparse"] = {
                "count": len(indices),
                "indices": {"bufferView": self.view(self.pack(indices, "SCALAR", itype)[0]),
                            "componentType": itype},
                "values": {"bufferView": self.view(self.pack(replacement, type_, ctype, False)[0])},
            }
        if minmax:
            final = list(values)
            if sparse:
                for i, v in zip(sparse[0], sparse[2]):
                    final[i] = v
            n = COMPONENTS[type_]
            acc["min"] = [min(v[k] for v in final) for k in range(n)]
            acc["max"] = [max(v[k] for v in final) for k in range(n)]
        self.accessors.append(acc)
        return len(self.accessors) - 1

    def finish(self, g):
        g["accessors"] = self.accessors
        g["bufferViews"] = self.views
        g["buffers"] = [{"byteLength": len(self.blob),
                         "uri": "data:application/octet-stream;base64,"
                         + base64.b64encode(self.blob).decode()}]
        return g


def checker_png():
    """4 x 4 RGB checker, orange and blue, as an 8-bit PNG."""
    rows = b""
    for y in range(4):
        rows += b"\0" + b"".join(bytes((230, 140, 30) if (x + y) % 2 else (40, 90, 220))
                                 for x in range(4))

    def chunk(kind, payload):
        return (struct.pack(">I", len(payload)) + kind + payload
                + struct.pack(">I", zlib.crc32(kind + payload) & 0xFFFFFFFF))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 4, 4, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


def document(w, meshes, nodes, quantized):
    g = {
        "asset": {"version": "2.0", "generator": "voxgi make_accessors.py"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "scene": 0,
        "scenes": [{"nodes": list(range(len(nodes) + 1))}],
        "nodes": nodes + [{"rotation": [-0.3826834, 0.0, 0.0, 0.9238795],
                           "extensions": {"KHR_lights_punctual": {"light": 0}}}],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional",
                                                           "intensity": 3.0}]}},
        "meshes": meshes,
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                                                "metallicFactor": 0, "roughnessFactor": 1}}],
        "samplers": [{"wrapS": 10497, "wrapT": 10497}],
        "textures": [{"source": 0, "sampler": 0}],
        "images": [{"uri": "data:image/png;base64," + base64.b64encode(checker_png()).decode(),
                    "mimeType": "image/png"}],
    }
    if quantized:
        g["extensionsUsed"].append("KHR_mesh_quantization")
        g["extensionsRequired"] = ["KHR_mesh_quantization"]
    return w.finish(g)


# (POSITION, NORMAL or None, TEXCOORD_0, indices), each attribute as
# (values, componentType, normalized); node transforms.
QUANTIZED = [
    ([(-100, -100, 0), (100, -100, 0), (100, 100, 0), (-100, 100, 0)], SHORT, False,
     [(0, 0, 127)] * 4, BYTE,
     [(0, 2), (2, 2), (2, 0), (0, 0)], UNSIGNED_BYTE, False,
     [0, 1, 2, 0, 2, 3], {"scale": [0.01, 0.01, 0.01]}),
    ([(-100, -90, 0), (90, -100, 20), (100, 90, 40), (-90, 100, 20)], BYTE, True,
     [(0, -19660, 26214)] * 4, SHORT,
     [(-32767, 32767), (32767, 32767), (32767, -32767), (-32767, -32767)], SHORT, True,
     [0, 1, 2, 0, 2, 3], {"translation": [-0.45, 0.4, 0.3], "scale": [0.4, 0.4, 0.4]}),
    ([(0, 0, 0), (65535, 0, 30000), (20000, 65535, 0)], UNSIGNED_SHORT, True,
     [(0, 0, 127)] * 3, BYTE,
     [(-1, 3), (3, 3), (1, -1)], BYTE, False,
     [0, 1, 2], {"translation": [0.1, -0.9, 0.25], "scale": [0.7, 0.6, 0.5]}),
    ([(0, 0, 0), (10, 0, 0), (10, 10, 0), (0, 10, 0)], UNSIGNED_BYTE, False,
     None, None,
     [(0, 65535), (65535, 65535), (65535, 0), (0, 0)], UNSIGNED_SHORT, True,
     [0, 1, 2, 0, 2, 3], {"translation": [0.35, 0.35, 0.2], "scale": [0.05, 0.05, 0.05]}),
]


def quantized_scene(quantized):
    w = Writer()
    meshes, nodes = [], []
    for m, (pos, ptype, pnorm, nrm, ntype, uv, ttype, tnorm, idx, node) in enumerate(QUANTIZED):
        def attr(values, type_, ctype, normalized, minmax=False):
            if quantized:
                return w.add(values, type_, ctype, normalized, minmax)
            floats = [tuple(dequantize(c, ctype, normalized) for c in v) for v in values]
            return w.add(floats, type_, FLOAT, False, minmax)
        attributes = {"POSITION": attr(pos, "VEC3", ptype, pnorm, True),
                      "TEXCOORD_0": attr(uv, "VEC2", ttype, tnorm)}
        if nrm is not None:
            attributes["NORMAL"] = attr(nrm, "VEC3", ntype, True)
        meshes.append({"primitives": [{"attributes": attributes,
                                       "indices": w.add(idx, "SCALAR", UNSIGNED_BYTE),
                                       "material": 0}]})
        nodes.append(dict(node, mesh=m))
    return document(w, meshes, nodes, quantized)


def sparse_scene(sparse):
    w = Writer()
    c, s = math.cos(0.5), math.sin(0.5)
    base_pos = [(-1.0, -1.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, 0.0), (-1.0, 0.0, 0.0),
                (10.0, 0.0, 0.0), (11.0, 0.0, 0.0), (11.0, 1.0, 0.0), (10.0, 1.0, 0.0)]
    moved = [(0.2, 0.0, 0.0), (0.2 + c, 0.0, -s), (0.2 + c, 1.0, -s), (0.2, 1.0, 0.0)]
    base_uv = [(0.0, 1.0), (1.0, 1.0), (1.0, 0.0), (0.0, 0.0)] * 2
    stretched = [(2.0, 1.0), (2.0, -1.0)]
    n = (s, 0.0, c)
    normals = [(0.0, 0.0, 1.0)] * 4 + [n] * 4
    idx = [0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7]
    if sparse:
        pos = w.add(base_pos, "VEC3", FLOAT, minmax=True,
                    sparse=([4, 5, 6, 7], UNSIGNED_BYTE, moved))
        uv = w.add(base_uv, "VEC2", FLOAT, sparse=([1, 2], UNSIGNED_SHORT, stretched))
        nrm = w.add(normals, "VEC3", FLOAT, no_view=True,
                    sparse=(list(range(8)), UNSIGNED_INT, normals))
    else:
        final_uv = list(base_uv)
        final_uv[1:3] = stretched
        pos = w.add(base_pos[:4] + moved, "VEC3", FLOAT, minmax=True)
        uv = w.add(final_uv, "VEC2", FLOAT)
        nrm = w.add(normals, "VEC3", FLOAT)
    meshes = [{"primitives": [{"attributes": {"POSITION": pos, "NORMAL": nrm, "TEXCOORD_0": uv},
                               "indices": w.add(idx, "SCALAR", UNSIGNED_BYTE),
                               "material": 0}]}]
    return document(w, meshes, [{"mesh": 0}], False)


def write(name, g):
    write_next_to(__file__, name, g)


write("quantized.gltf", quantized_scene(True))
write("quantized_float.gltf", quantized_scene(False))
write("sparse.gltf", sparse_scene(True))
write("sparse_float.gltf", sparse_scene(False))
