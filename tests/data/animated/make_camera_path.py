#!/usr/bin/env python3
"""Writes camera_path.gltf: a camera path and moving lights in a small room.

A room 4 x 4 m (floor, back, left and right walls, open above and in front) with a
block in the middle. Over 2 s:
  - node 2 "dolly" slides from (-1, 1, 3.5) to (1, 1, 3.5) (LINEAR); its child,
    node 3 "camera" (0.2 m above it), pitched 15 degrees down, turns from a yaw of
    -20 degrees (looking right, towards the middle) to +20 degrees about +y
    (LINEAR: a slerp, which keeps the pitch: the keys differ by a yaw of 40
    degrees). The camera moves with its parent: the path is the composition.
  - node 4 "lamp", a point light 0.3 m above the floor, slides from x = -1.2 to
    x = +1.2 at z = 0.8 (LINEAR): a bright spot moving across the floor.
  - node 5 "sun", a dim directional light, shines straight down until t = 1 and
    then tilted 30 degrees towards -z (STEP).
Self-contained: the buffer is a base64 data: URI. Run from anywhere; the tests
(tests/scene/camera_animation_test.cpp, tests/render/camera_animation_gltest.cpp)
compute the expected poses by hand from the numbers here.
"""
import math

from gltf_writer import Buffer, bounds, write


def quad(p0, p1, p2, p3, normal):
    """Two triangles (p0 p1 p2, p0 p2 p3), counter-clockwise seen from `normal`."""
    return [p0, p1, p2, p3], [normal] * 4, [0, 1, 2, 0, 2, 3]


def merge(parts):
    pos, nrm, idx = [], [], []
    for p, n, i in parts:
        base = len(pos)
        pos += p
        nrm += n
        idx += [base + k for k in i]
    return pos, nrm, idx


def box(lo, hi):
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    return merge([
        quad((x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1), (1, 0, 0)),
        quad((x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0), (-1, 0, 0)),
        quad((x0, y1, z0), (x0, y1, z1), (x1, y1, z1), (x1, y1, z0), (0, 1, 0)),
        quad((x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1), (0, -1, 0)),
        quad((x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1), (0, 0, 1)),
        quad((x0, y0, z0), (x0, y1, z0), (x1, y1, z0), (x1, y0, z0), (0, 0, -1)),
    ])


room = merge([
    quad((-2, 0, 2), (2, 0, 2), (2, 0, -2), (-2, 0, -2), (0, 1, 0)),    # floor
    quad((-2, 0, -2), (2, 0, -2), (2, 2, -2), (-2, 2, -2), (0, 0, 1)),  # back wall
    quad((-2, 0, 2), (-2, 0, -2), (-2, 2, -2), (-2, 2, 2), (1, 0, 0)),  # left wall
    quad((2, 0, -2), (2, 0, 2), (2, 2, 2), (2, 2, -2), (-1, 0, 0)),     # right wall
])
block = box((-0.25, 0.0, -0.25), (0.25, 0.5, 0.25))


def yaw(degrees):
    """Quaternion (x, y, z, w) of a rotation about +y."""
    h = math.radians(degrees) / 2
    return (0.0, math.sin(h), 0.0, math.cos(h))


def pitch(degrees):
    """Quaternion (x, y, z, w) of a rotation about +x."""
    h = math.radians(degrees) / 2
    return (math.sin(h), 0.0, 0.0, math.cos(h))


def mul(a, b):
    """Quaternion product a b (b applied first), (x, y, z, w)."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz)


def look(yaw_degrees):
    """The camera's rotation: pitched 15 degrees down, then turned by the yaw."""
    return mul(yaw(yaw_degrees), pitch(-15.0))


buf = Buffer()
add = buf.add


def mesh(parts):
    pos, nrm, idx = parts
    p = add(pos, "<3f", "VEC3", 5126, 34962, bounds(pos))
    n = add(nrm, "<3f", "VEC3", 5126, 34962)
    i = add(idx, "<I", "SCALAR", 5125, 34963)
    return {"POSITION": p, "NORMAL": n}, i


room_attr, room_idx = mesh(room)
block_attr, block_idx = mesh(block)
t2 = add([0.0, 2.0], "<f", "SCALAR", 5126, None, [[0.0], [2.0]])
t1 = add([0.0, 1.0], "<f", "SCALAR", 5126, None, [[0.0], [1.0]])
dolly = add([(-1.0, 1.0, 3.5), (1.0, 1.0, 3.5)], "<3f", "VEC3", 5126)
turn = add([look(-20.0), look(20.0)], "<4f", "VEC4", 5126)
lamp = add([(-1.2, 0.3, 0.8), (1.2, 0.3, 0.8)], "<3f", "VEC3", 5126)
sun = add([pitch(-90.0), pitch(-60.0)], "<4f", "VEC4", 5126)

gltf = {
    "asset": {"version": "2.0", "generator": "voxgi tests/data/animated/make_camera_path.py"},
    "extensionsUsed": ["KHR_lights_punctual"],
    "extensions": {"KHR_lights_punctual": {"lights": [
        {"name": "lamp", "type": "point", "color": [1.0, 0.9, 0.7], "intensity": 2.0},
        {"name": "sun", "type": "directional", "color": [1.0, 1.0, 1.0], "intensity": 0.5},
    ]}},
    "scene": 0,
    "scenes": [{"nodes": [0, 1, 2, 4, 5]}],
    "nodes": [
        {"name": "room", "mesh": 0},
        {"name": "block", "mesh": 1},
        {"name": "dolly", "translation": [-1.0, 1.0, 3.5], "children": [3]},
        {"name": "camera", "camera": 0, "translation": [0.0, 0.2, 0.0],
         "rotation": list(look(-20.0))},
        {"name": "lamp", "translation": [-1.2, 0.3, 0.8],
         "extensions": {"KHR_lights_punctual": {"light": 0}}},
        {"name": "sun", "rotation": list(pitch(-90.0)),
         "extensions": {"KHR_lights_punctual": {"light": 1}}},
    ],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.05}}],
    "materials": [
        {"name": "room", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1],
                                                  "metallicFactor": 0}},
        {"name": "block", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.25, 0.1, 1],
                                                   "metallicFactor": 0}},
    ],
    "meshes": [
        {"name": "room", "primitives": [{"attributes": room_attr, "indices": room_idx,
                                         "material": 0}]},
        {"name": "block", "primitives": [{"attributes": block_attr, "indices": block_idx,
                                          "material": 1}]},
    ],
    "animations": [{
        "name": "camera path",
        "samplers": [
            {"input": t2, "output": dolly, "interpolation": "LINEAR"},
            {"input": t2, "output": turn, "interpolation": "LINEAR"},
            {"input": t2, "output": lamp, "interpolation": "LINEAR"},
            {"input": t1, "output": sun, "interpolation": "STEP"},
        ],
        "channels": [
            {"sampler": 0, "target": {"node": 2, "path": "translation"}},
            {"sampler": 1, "target": {"node": 3, "path": "rotation"}},
            {"sampler": 2, "target": {"node": 4, "path": "translation"}},
            {"sampler": 3, "target": {"node": 5, "path": "rotation"}},
        ],
    }],
}
write(buf.finish(gltf), "camera_path.gltf")
