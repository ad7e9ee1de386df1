#!/usr/bin/env python3
"""Writes moving_box.gltf: a static floor and a box whose node slides along x
from -0.5 to +0.5 over one second (LINEAR), then back by 2 s (a second key);
cubic_box.gltf, the same with CUBICSPLINE keys and a turn; thin_bar.gltf: a thin
white bar crossing a dark floor, its own width every 1/30 s.
Self-contained: the buffer is a base64 data: URI. Run from anywhere."""
from gltf_writer import Buffer, bounds, write

def box(lo, hi):
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    c = lambda i: (x1 if i & 1 else x0, y1 if i & 2 else y0, z1 if i & 4 else z0)
    faces = [(1, 3, 7, 5), (0, 4, 6, 2), (2, 6, 7, 3), (0, 1, 5, 4), (4, 5, 7, 6), (0, 2, 3, 1)]
    pos, idx = [], []
    for f in faces:
        base = len(pos)
        pos += [c(i) for i in f]
        idx += [base, base + 1, base + 2, base, base + 2, base + 3]
    return pos, idx

floor_pos = [(-1.5, 0, 1.5), (1.5, 0, 1.5), (1.5, 0, -1.5), (-1.5, 0, -1.5)]
floor_idx = [0, 1, 2, 0, 2, 3]
box_pos, box_idx = box((-0.25, 0.0, -0.25), (0.25, 0.5, 0.25))
times = [0.0, 1.0, 2.0]
moves = [(-0.5, 0.0, 0.0), (0.5, 0.0, 0.0), (-0.5, 0.0, 0.0)]


def floor_and_box():
    """A new buffer holding the floor's and the box's accessors, their indices."""
    buf = Buffer()
    add = buf.add
    return (buf, add(floor_pos, "<3f", "VEC3", 5126, 34962, bounds(floor_pos)),
            add(floor_idx, "<I", "SCALAR", 5125, 34963),
            add(box_pos, "<3f", "VEC3", 5126, 34962, bounds(box_pos)),
            add(box_idx, "<I", "SCALAR", 5125, 34963))


buf, fp, fi, bp, bi = floor_and_box()
add = buf.add
ti = add(times, "<f", "SCALAR", 5126, None, [[0.0], [2.0]])
tv = add(moves, "<3f", "VEC3", 5126)

gltf = {
    "asset": {"version": "2.0", "generator": "voxgi tests/data/animated/make_animated.py"},
    "scene": 0,
    "scenes": [{"nodes": [0, 1, 2]}],
    "nodes": [
        {"name": "floor", "mesh": 0},
        {"name": "box", "mesh": 1, "translation": [-0.5, 0.0, 0.0]},
        {"name": "camera", "camera": 0, "translation": [0.0, 1.2, 3.0],
         "rotation": [-0.1736482, 0.0, 0.0, 0.9848078]},
    ],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.01}}],
    "materials": [
        {"name": "floor", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0}},
        {"name": "box", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.2, 0.1, 1], "metallicFactor": 0}},
    ],
    "meshes": [
        {"primitives": [{"attributes": {"POSITION": fp}, "indices": fi, "material": 0}]},
        {"primitives": [{"attributes": {"POSITION": bp}, "indices": bi, "material": 1}]},
    ],
    "animations": [{"name": "slide", "samplers": [{"input": ti, "output": tv, "interpolation": "LINEAR"}],
                    "channels": [{"sampler": 0, "target": {"node": 1, "path": "translation"}}]}],
}
write(buf.finish(gltf), "moving_box.gltf")

# cubic_box.gltf: the same floor and box, the box's translation a CUBICSPLINE over
# two keys 2 s apart, x from -0.5 to 0.5, leaving with tangent (1, 0, 0) per second
# and arriving with tangent (0, 0, 0); and its rotation a CUBICSPLINE about y from 0
# to 90 degrees with zero tangents (the spline of two unit quaternions, normalized).
buf, fp, fi, bp, bi = floor_and_box()
add = buf.add
ti = add([0.0, 2.0], "<f", "SCALAR", 5126, None, [[0.0], [2.0]])
# (in-tangent, value, out-tangent) per key
tv = add([(0, 0, 0), (-0.5, 0, 0), (1, 0, 0), (0, 0, 0), (0.5, 0, 0), (0, 0, 0)], "<3f", "VEC3", 5126)
s45 = 0.7071068
rv = add([(0, 0, 0, 0), (0, 0, 0, 1), (0, 0, 0, 0), (0, 0, 0, 0), (0, s45, 0, s45), (0, 0, 0, 0)],
         "<4f", "VEC4", 5126)
cubic = dict(gltf)
cubic["asset"] = {"version": "2.0", "generator": "voxgi tests/data/animated/make_animated.py"}
cubic["meshes"] = [
    {"primitives": [{"attributes": {"POSITION": fp}, "indices": fi, "material": 0}]},
    {"primitives": [{"attributes": {"POSITION": bp}, "indices": bi, "material": 1}]},
]
cubic["animations"] = [{"name": "glide", "samplers": [
    {"input": ti, "output": tv, "interpolation": "CUBICSPLINE"},
    {"input": ti, "output": rv, "interpolation": "CUBICSPLINE"}],
    "channels": [{"sampler": 0, "target": {"node": 1, "path": "translation"}},
                 {"sampler": 1, "target": {"node": 1, "path": "rotation"}}]}]
write(buf.finish(cubic), "cubic_box.gltf")

# thin_bar.gltf: a white bar 4 cm wide, 1 cm high and 1.6 m long (along z) on a dark
# floor (albedo 0.05, a twentieth of the bar's), under the default sun; the bar
# slides along x from -0.6 to +0.6 m in 1 s (LINEAR): its own width every 1/30 s.
buf = Buffer()
add = buf.add
dark_pos = [(-1.0, 0, 1.0), (1.0, 0, 1.0), (1.0, 0, -1.0), (-1.0, 0, -1.0)]
bar_pos, bar_idx = box((-0.02, 0.0, -0.8), (0.02, 0.01, 0.8))
dp = add(dark_pos, "<3f", "VEC3", 5126, 34962, bounds(dark_pos))
di = add(floor_idx, "<I", "SCALAR", 5125, 34963)
bp = add(bar_pos, "<3f", "VEC3", 5126, 34962, bounds(bar_pos))
bi = add(bar_idx, "<I", "SCALAR", 5125, 34963)
ti = add([0.0, 1.0], "<f", "SCALAR", 5126, None, [[0.0], [1.0]])
tv = add([(-0.6, 0.0, 0.0), (0.6, 0.0, 0.0)], "<3f", "VEC3", 5126)
bar = {
    "asset": {"version": "2.0", "generator": "voxgi tests/data/animated/make_animated.py"},
    "scene": 0,
    "scenes": [{"nodes": [0, 1, 2]}],
    "nodes": [
        {"name": "floor", "mesh": 0},
        {"name": "bar", "mesh": 1, "translation": [-0.6, 0.0, 0.0]},
        {"name": "camera", "camera": 0, "translation": [0.0, 2.2, 0.0],
         "rotation": [-0.7071068, 0.0, 0.0, 0.7071068]},
    ],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01}}],
    "materials": [
        {"name": "floor", "pbrMetallicRoughness": {"baseColorFactor": [0.05, 0.05, 0.05, 1], "metallicFactor": 0}},
        {"name": "bar", "pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1], "metallicFactor": 0}},
    ],
    "meshes": [
        {"primitives": [{"attributes": {"POSITION": dp}, "indices": di, "material": 0}]},
        {"primitives": [{"attributes": {"POSITION": bp}, "indices": bi, "material": 1}]},
    ],
    "animations": [{"name": "cross", "samplers": [{"input": ti, "output": tv, "interpolation": "LINEAR"}],
                    "channels": [{"sampler": 0, "target": {"node": 1, "path": "translation"}}]}],
}
write(buf.finish(bar), "thin_bar.gltf")
