#!/usr/bin/env python3
"""Writes red_green_quad.gltf: a 2 x 2 quad in the z = 0 plane, facing +z, made of
two halves. COLOR_0 (normalized UNSIGNED_BYTE VEC4) is red on every vertex of the
left half (x < 0) and green on the right half (x > 0); the material is white, so
each half shows its vertex colour. A second primitive, a small white square behind
the quad (z = -1) without COLOR_0, checks that primitives without vertex colours
stay white in a scene that has them.
Self-contained: the buffer is a base64 data: URI. Run from anywhere."""
import base64, json, os, struct

FLOAT, UNSIGNED_BYTE, UNSIGNED_SHORT = 5126, 5121, 5123

quad_pos = [(-1, -1, 0), (0, -1, 0), (0, 1, 0), (-1, 1, 0),
            (0, -1, 0), (1, -1, 0), (1, 1, 0), (0, 1, 0)]
quad_idx = [0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7]
quad_col = [(255, 0, 0, 255)] * 4 + [(0, 255, 0, 255)] * 4
back_pos = [(-0.25, -0.25, -1), (0.25, -0.25, -1), (0.25, 0.25, -1), (-0.25, 0.25, -1)]
back_idx = [0, 1, 2, 0, 2, 3]

blob = b""
views, accessors = [], []


def add(data, fmt, type_, ctype, minmax=False, normalized=False):
    global blob
    while len(blob) % 4:
        blob += b"\0"
    raw = b"".join(struct.pack(fmt, *v) if isinstance(v, tuple) else struct.pack(fmt, v) for v in data)
    views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(raw)})
    acc = {"bufferView": len(views) - 1, "componentType": ctype, "count": len(data), "type": type_}
    if minmax:
        acc["min"] = [float(min(v[i] for v in data)) for i in range(3)]
        acc["max"] = [float(max(v[i] for v in data)) for i in range(3)]
    if normalized:
        acc["normalized"] = True
    accessors.append(acc)
    blob += raw
    return len(accessors) - 1


def normals(n):
    return [(0.0, 0.0, 1.0)] * n


quad = {"attributes": {"POSITION": add(quad_pos, "<3f", "VEC3", FLOAT, minmax=True),
                       "NORMAL": add(normals(8), "<3f", "VEC3", FLOAT),
                       "COLOR_0": add(quad_col, "<4B", "VEC4", UNSIGNED_BYTE, normalized=True)},
        "indices": add(quad_idx, "<H", "SCALAR", UNSIGNED_SHORT), "material": 0}
back = {"attributes": {"POSITION": add(back_pos, "<3f", "VEC3", FLOAT, minmax=True),
                       "NORMAL": add(normals(4), "<3f", "VEC3", FLOAT)},
        "indices": add(back_idx, "<H", "SCALAR", UNSIGNED_SHORT), "material": 0}
while len(blob) % 4:
    blob += b"\0"

gltf = {
    "asset": {"version": "2.0", "generator": "voxgi make_vertex_colors.py"},
    "scene": 0,
    "scenes": [{"nodes": [0, 1]}],
    "nodes": [{"mesh": 0}, {"mesh": 1}],
    "meshes": [{"primitives": [quad]}, {"primitives": [back]}],
    "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0,
                                            "roughnessFactor": 1}}],
    "accessors": accessors,
    "bufferViews": views,
    "buffers": [{"byteLength": len(blob),
                 "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
}
out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "red_green_quad.gltf")
with open(out, "w") as f:
    json.dump(gltf, f, indent=1)
    f.write("\n")
print("wrote", out)
