#!/usr/bin/env python3
"""Writes the validation set's architectural scenes into scenes/hall/ (see
scenes/hall/README.md for what each holds and why).

One geometry buffer, hall.bin, is shared by four glTF files that differ in their
lights and cameras:

  hall.gltf             day: a 16 x 4 m skylight panel, 24 small lamps by the
                        columns, the sun through a window, four point lights and a
                        spot light
  hall_night.gltf       night: no emitting surface; 22 point lights and the moon
  sealed_room.gltf      the camera in a sealed 3 x 3 m room behind the hall's 15 cm
                        end wall, with a lamp of its own; the hall lit as by day
  sealed_room_dark.gltf the same with the hall's lights off: nothing can pass the
                        wall, so its reference is the same image

With --dense it also writes hall_dense.gltf and hall_dense.bin: the day hall with a
sculpture of some 1.2 million triangles (not kept in git: tools/make-hall --dense
makes it in a few seconds). With --triangles N it writes hall_N.gltf and hall_N.bin:
the day hall with the knot tessellated so that the scene has at least N triangles
(a scale scene: nearly the same image at any triangle count; N >= 10,000).

Units are metres, +y up, colours linear. The output is deterministic: the same
bytes on every run (tests/scene/validation_set_test.cpp checks the committed files
against a fresh run).
"""
import argparse
import json
import math
import os
import struct
import sys
import zlib

import numpy as np

from voxgi_tools import ROOT

OUT = os.path.join(ROOT, "scenes", "hall")

# The hall: x in [-12, 12], z in [-6, 6], y in [0, 8]; walls and slabs 15 cm thick
# solids (thinner than a voxel at the default 128^3 over the set's 27 m extent).
WALL = 0.15
HALL_X, HALL_Z, HALL_H = 12.0, 6.0, 8.0
ROOM = (12.0 + WALL, 15.0 + WALL, -1.5, 1.5, 3.0)  # x0, x1, z0, z1, height: the sealed room


class Mesh:
    """Triangles with per-vertex normals and texture coordinates."""

    def __init__(self):
        self.p, self.n, self.uv, self.i = [], [], [], []
        self.count = 0

    def add(self, p, n, uv, idx):
        self.p.append(np.asarray(p, np.float32).reshape(-1, 3))
        self.n.append(np.asarray(n, np.float32).reshape(-1, 3))
        self.uv.append(np.asarray(uv, np.float32).reshape(-1, 2))
        self.i.append(np.asarray(idx, np.uint32).reshape(-1) + self.count)
        self.count += len(self.p[-1])

    def quad(self, o, u, v, uv_scale=0.5):
        """The parallelogram o, o+u, o+u+v, o+v, facing u x v; texture coordinates
        in metres times uv_scale."""
        o, u, v = (np.asarray(a, np.float64) for a in (o, u, v))
        n = np.cross(u, v)
        n /= np.linalg.norm(n)
        p = [o, o + u, o + u + v, o + v]
        lu, lv = np.linalg.norm(u) * uv_scale, np.linalg.norm(v) * uv_scale
        self.add(p, [n] * 4, [(0, 0), (lu, 0), (lu, lv), (0, lv)], [0, 1, 2, 0, 2, 3])

    def box(self, lo, hi):
        """A closed box, faces outwards."""
        x0, y0, z0 = lo
        x1, y1, z1 = hi
        dx, dy, dz = x1 - x0, y1 - y0, z1 - z0
        self.quad((x0, y0, z1), (dx, 0, 0), (0, dy, 0))    # +z
        self.quad((x1, y0, z0), (-dx, 0, 0), (0, dy, 0))   # -z
        self.quad((x1, y0, z1), (0, 0, -dz), (0, dy, 0))   # +x
        self.quad((x0, y0, z0), (0, 0, dz), (0, dy, 0))    # -x
        self.quad((x0, y1, z1), (dx, 0, 0), (0, 0, -dz))   # +y
        self.quad((x0, y0, z0), (dx, 0, 0), (0, 0, dz))    # -y

    def sphere(self, c, r, rings, segments):
        th = np.linspace(0, math.pi, rings + 1)
        ph = np.linspace(0, 2 * math.pi, segments + 1)
        t, f = np.meshgrid(th, ph, indexing="ij")
        n = np.stack([np.sin(t) * np.cos(f), np.cos(t), np.sin(t) * np.sin(f)], -1).reshape(-1, 3)
        uv = np.stack([f / (2 * math.pi), t / math.pi], -1).reshape(-1, 2)
        idx = []
        w = segments + 1
        for a in range(rings):
            for b in range(segments):
                q = [a * w + b, a * w + b + 1, (a + 1) * w + b + 1, (a + 1) * w + b]
                # Counter-clockwise seen from outside (theta down from +y, phi
                # towards +z): the faces' winding agrees with their normals.
                if a > 0:
                    idx += [q[0], q[1], q[2]]
                if a < rings - 1:
                    idx += [q[0], q[2], q[3]]
        self.add(np.asarray(c) + r * n, n, uv, idx)

    def knot(self, c, scale, tube, along, around):
        """A (2, 3) torus knot tube: a smooth curved surface of 2*along*around
        triangles."""
        s = np.linspace(0, 2 * math.pi, along, endpoint=False)

        def curve(s):
            r = 2 + np.cos(3 * s)
            return np.stack([r * np.cos(2 * s), np.sin(3 * s) + 1.2, r * np.sin(2 * s)], -1)

        p0, p1 = curve(s), curve(s + 1e-4)
        tangent = p1 - p0
        tangent /= np.linalg.norm(tangent, axis=1, keepdims=True)
        up = np.array([0.0, 1.0, 0.0])
        b = np.cross(tangent, up)
        b /= np.linalg.norm(b, axis=1, keepdims=True)
        nn = np.cross(b, tangent)
        a = np.linspace(0, 2 * math.pi, around, endpoint=False)
        ring = (np.cos(a)[None, :, None] * b[:, None, :] + np.sin(a)[None, :, None] * nn[:, None, :])
        pos = np.asarray(c) + scale * (p0[:, None, :] + tube * ring)
        uv = np.stack(np.meshgrid(s / (2 * math.pi), a / (2 * math.pi), indexing="ij"), -1)
        i0 = np.arange(along)[:, None] * around + np.arange(around)[None, :]
        i1 = ((np.arange(along)[:, None] + 1) % along) * around + np.arange(around)[None, :]
        i2 = ((np.arange(along)[:, None] + 1) % along) * around + (np.arange(around)[None, :] + 1) % around
        i3 = np.arange(along)[:, None] * around + (np.arange(around)[None, :] + 1) % around
        idx = np.stack([i0, i1, i2, i0, i2, i3], -1).reshape(-1)
        self.add(pos.reshape(-1, 3), ring.reshape(-1, 3), uv.reshape(-1, 2), idx)


class Writer:
    """Meshes into one binary buffer; accessors and views for every glTF file."""

    def __init__(self):
        self.blob = bytearray()
        self.views, self.accessors, self.meshes = [], [], []

    def _accessor(self, array, type_, ctype, target, minmax=False):
        while len(self.blob) % 4:
            self.blob += b"\0"
        raw = array.tobytes()
        self.views.append({"buffer": 0, "byteOffset": len(self.blob), "byteLength": len(raw),
                           "target": target})
        acc = {"bufferView": len(self.views) - 1, "componentType": ctype,
               "count": int(array.shape[0]), "type": type_}
        if minmax:
            acc["min"] = [float(v) for v in array.min(0)]
            acc["max"] = [float(v) for v in array.max(0)]
        self.accessors.append(acc)
        self.blob += raw
        return len(self.accessors) - 1

    def mesh(self, name, m, material):
        p = np.concatenate(m.p)
        attributes = {"POSITION": self._accessor(p, "VEC3", 5126, 34962, True),
                      "NORMAL": self._accessor(np.concatenate(m.n), "VEC3", 5126, 34962),
                      "TEXCOORD_0": self._accessor(np.concatenate(m.uv), "VEC2", 5126, 34962)}
        indices = self._accessor(np.concatenate(m.i), "SCALAR", 5125, 34963)
        self.meshes.append({"name": name, "primitives": [
            {"attributes": attributes, "indices": indices, "material": material, "mode": 4}]})
        return len(self.meshes) - 1


def png(width, height, rgb):
    """An 8-bit RGB PNG of rows top first (rgb: height x width x 3 uint8)."""
    rows = b"".join(b"\0" + rgb[y].tobytes() for y in range(height))

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b""))


def floor_tiles():
    """Stone tiles, two tones in a checker, with grout: 256 x 256 texels for a 2 x 2 m
    patch (4 tiles of 1 m)."""
    y, x = np.mgrid[0:256, 0:256]
    tone = ((x // 128) + (y // 128)) % 2
    grout = ((x % 128) < 3) | ((y % 128) < 3)
    rng = np.random.default_rng(5)
    noise = rng.integers(-10, 11, size=(256, 256))
    base = np.where(tone[..., None] == 1, np.array([190, 178, 160]), np.array([150, 146, 140]))
    rgb = base + noise[..., None]
    rgb = np.where(grout[..., None], np.array([90, 88, 85]), rgb)
    return np.clip(rgb, 0, 255).astype(np.uint8)


def material(name, color, metallic=0.0, roughness=1.0, emission=None, texture=None, double=True):
    m = {"name": name, "pbrMetallicRoughness": {
        "baseColorFactor": list(color) + [1.0], "metallicFactor": metallic,
        "roughnessFactor": roughness}, "doubleSided": double}
    if texture is not None:
        m["pbrMetallicRoughness"]["baseColorTexture"] = {"index": texture}
    if emission is not None:
        strength = max(emission)
        m["emissiveFactor"] = [e / strength for e in emission]
        m["extensions"] = {"KHR_materials_emissive_strength": {"emissiveStrength": strength}}
    return m


MATERIALS = [
    material("floor_tiles", (1.0, 1.0, 1.0), roughness=0.9, texture=0),  # 0
    material("plaster", (0.7, 0.68, 0.64)),                               # 1
    material("stone", (0.55, 0.52, 0.48)),                                # 2
    material("gallery_wood", (0.45, 0.3, 0.18), roughness=0.7),           # 3
    material("skylight", (0.0, 0.0, 0.0), emission=(4.0, 4.2, 4.6), double=False),  # 4
    material("lamp", (0.0, 0.0, 0.0), emission=(160.0, 130.0, 90.0)),     # 5
    material("mirror", (0.95, 0.95, 0.95), metallic=1.0, roughness=0.0),  # 6
    material("bronze", (0.8, 0.55, 0.35), metallic=1.0, roughness=0.35),  # 7
    material("room_red", (0.6, 0.12, 0.08)),                              # 8
    material("ball", (0.75, 0.75, 0.75)),                                 # 9
]

COLUMNS = [(x, z) for x in (-10.0, -6.0, -2.0, 2.0, 6.0, 10.0) for z in (-3.0, 3.0)]


def build_geometry(sculpture_along, sculpture_around):
    """The meshes, as (name, Mesh, material), in a fixed order."""
    floor, plaster, stone, wood = Mesh(), Mesh(), Mesh(), Mesh()
    # The ground slab under the hall and the sealed room.
    floor.box((-HALL_X - WALL, -0.3, -HALL_Z - WALL), (ROOM[1] + WALL, 0.0, HALL_Z + WALL))
    # Long walls; the south one (z < 0) with a 4 x 3 m window at x in [-6, -2], y in [2, 5].
    plaster.box((-HALL_X - WALL, 0, HALL_Z), (HALL_X + WALL, HALL_H, HALL_Z + WALL))
    south = (-HALL_Z - WALL, -HALL_Z)
    plaster.box((-HALL_X - WALL, 0, south[0]), (-6.0, HALL_H, south[1]))
    plaster.box((-2.0, 0, south[0]), (HALL_X + WALL, HALL_H, south[1]))
    plaster.box((-6.0, 0, south[0]), (-2.0, 2.0, south[1]))
    plaster.box((-6.0, 5.0, south[0]), (-2.0, HALL_H, south[1]))
    # End walls: the east one (x = 12) is the sealed room's west wall.
    plaster.box((-HALL_X - WALL, 0, -HALL_Z), (-HALL_X, HALL_H, HALL_Z))
    plaster.box((HALL_X, 0, -HALL_Z), (HALL_X + WALL, HALL_H, HALL_Z))
    # The roof slab with a 16 x 4 m opening, the skylight panel recessed in it.
    roof = (HALL_H, HALL_H + 0.3)
    plaster.box((-HALL_X - WALL, roof[0], -HALL_Z - WALL), (HALL_X + WALL, roof[1], -2.0))
    plaster.box((-HALL_X - WALL, roof[0], 2.0), (HALL_X + WALL, roof[1], HALL_Z + WALL))
    plaster.box((-HALL_X - WALL, roof[0], -2.0), (-8.0, roof[1], 2.0))
    plaster.box((8.0, roof[0], -2.0), (HALL_X + WALL, roof[1], 2.0))
    plaster.box((-8.0, roof[1], -2.0), (8.0, roof[1] + 0.1, 2.0))  # above the panel: sealed
    # Two arcades of six columns, a gallery floor over each aisle on them.
    for x, z in COLUMNS:
        stone.box((x - 0.3, 0.0, z - 0.3), (x + 0.3, HALL_H, z + 0.3))
    wood.box((-HALL_X, 4.0, 3.3), (HALL_X, 4.25, HALL_Z))
    wood.box((-HALL_X, 4.0, -HALL_Z), (HALL_X, 4.25, -3.3))
    # The sealed room behind the east wall: its walls and roof 15 cm solids.
    x0, x1, z0, z1, h = ROOM
    accent = Mesh()
    plaster.box((x0, 0, z0 - WALL), (x1, h, z0))
    accent.box((x0, 0, z1), (x1, h, z1 + WALL))  # the north wall red
    plaster.box((x1, 0, z0 - WALL), (x1 + WALL, h, z1 + WALL))
    plaster.box((x0, h, z0 - WALL), (x1 + WALL, h + WALL, z1 + WALL))
    skylight = Mesh()
    skylight.quad((-8.0, roof[1] - 0.02, -2.0), (16.0, 0, 0), (0, 0, 4.0))  # faces -y
    lamps = Mesh()
    for x, z in COLUMNS:  # one each side of every column, 35 cm from its face
        for side in (-1.0, 1.0):
            lamps.sphere((x, 2.6, z + side * 0.65), 0.045, 6, 12)
    mirror = Mesh()
    mirror.sphere((4.0, 0.6, -0.8), 0.6, 24, 48)
    sculpture = Mesh()
    sculpture.knot((-4.0, 0.0, 0.8), 0.45, 0.3, sculpture_along, sculpture_around)
    balls = Mesh()
    balls.sphere((13.3, 0.35, 0.7), 0.35, 16, 32)
    return [("floor", floor, 0), ("walls", plaster, 1), ("columns", stone, 2),
            ("galleries", wood, 3), ("room_accent", accent, 8), ("skylight", skylight, 4),
            ("lamps", lamps, 5), ("mirror_ball", mirror, 6), ("sculpture", sculpture, 7),
            ("room_ball", balls, 9)]


def look_at(eye, target):
    """A glTF camera node's rotation (x, y, z, w) looking from eye at target, +y up."""
    f = np.asarray(target, float) - np.asarray(eye, float)
    f /= np.linalg.norm(f)
    r = np.cross(f, [0.0, 1.0, 0.0])
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    m = np.stack([r, u, -f], 1)  # columns: the camera's x, y, z in the world
    w = math.sqrt(max(0.0, 1 + m[0, 0] + m[1, 1] + m[2, 2])) / 2
    x = math.copysign(math.sqrt(max(0.0, 1 + m[0, 0] - m[1, 1] - m[2, 2])) / 2, m[2, 1] - m[1, 2])
    y = math.copysign(math.sqrt(max(0.0, 1 - m[0, 0] + m[1, 1] - m[2, 2])) / 2, m[0, 2] - m[2, 0])
    z = math.copysign(math.sqrt(max(0.0, 1 - m[0, 0] - m[1, 1] + m[2, 2])) / 2, m[1, 0] - m[0, 1])
    return [x, y, z, w]


# Each file's camera (eye, target); the set's other viewpoints are in
# scenes/validation_set.json.
HALL_VIEW = ((-11.0, 1.7, -1.2), (6.0, 2.6, 0.6))
ROOM_VIEW = ((14.8, 1.7, 1.3), (12.15, 0.3, -0.7))


def punctual(kind, color, intensity, name, **extra):
    light = {"type": kind, "color": list(color), "intensity": intensity, "name": name}
    light.update(extra)
    return light


def light_node(index, position=None, target=None, name=""):
    node = {"name": name, "extensions": {"KHR_lights_punctual": {"light": index}}}
    if position is not None:
        node["translation"] = list(position)
    if target is not None:
        node["rotation"] = look_at(position if position is not None else (0, 0, 0), target)
    return node


def lights_for(variant):
    """KHR_lights_punctual lights and their nodes, and the meshes left out."""
    lights, nodes = [], []

    def add(light, position=None, target=None):
        nodes.append(light_node(len(lights), position, target, light["name"]))
        lights.append(light)

    day = variant in ("hall", "sealed_room")
    if day:
        # The sun through the south window, 35 degrees high.
        sun = (0.25, -0.57, 0.78)
        add(punctual("directional", (1.0, 0.95, 0.85), 6.0, "sun"), (0, 0, 0), sun)
        for i, (x, z) in enumerate([(-6.0, 4.6), (6.0, 4.6), (-6.0, -4.6), (6.0, -4.6)]):
            add(punctual("point", (1.0, 0.85, 0.7), 3.0, f"gallery_{i}", range=0), (x, 6.0, z))
        add(punctual("spot", (1.0, 1.0, 1.0), 40.0, "spot",
                     spot={"innerConeAngle": 0.2, "outerConeAngle": 0.35}),
            (-4.0, 7.5, 4.5), (-4.0, 1.0, 0.8))
    elif variant == "hall_night":
        add(punctual("directional", (0.6, 0.7, 1.0), 0.4, "moon"), (0, 0, 0), (0.3, -0.7, 0.65))
        for i in range(11):  # 22 small lights along the aisles
            for z in (-4.6, 4.6):
                add(punctual("point", (1.0, 0.8, 0.55), 2.0, f"aisle_{i}_{'s' if z < 0 else 'n'}",
                             range=0), (-10.0 + 2.0 * i, 2.2, z))
    if variant.startswith("sealed_room"):
        add(punctual("point", (1.0, 0.9, 0.8), 1.5, "room_lamp", range=0), (14.3, 2.6, -0.8))
    for light in lights:
        if light.get("range") == 0:
            del light["range"]
    # Meshes each variant leaves out: the emitting surfaces at night or with the
    # hall dark.
    dropped = set()
    if variant in ("hall_night", "sealed_room_dark"):
        dropped = {"skylight", "lamps"}
    return lights, nodes, dropped


def gltf_for(variant, writer, names, bin_name, image_name):
    lights, light_nodes, dropped = lights_for(variant)
    nodes = [{"name": name, "mesh": i} for i, name in enumerate(names) if name not in dropped]
    eye, target = ROOM_VIEW if variant.startswith("sealed_room") else HALL_VIEW
    nodes.append({"name": "camera", "camera": 0, "translation": list(eye),
                  "rotation": look_at(eye, target)})
    nodes += light_nodes
    g = {
        "asset": {"version": "2.0", "generator": "voxgi tools/make-hall"},
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength"],
        "scene": 0,
        "scenes": [{"name": variant, "nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": writer.meshes,
        "materials": MATERIALS,
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}],
        "images": [{"uri": image_name}],
        "cameras": [{"type": "perspective", "name": "camera", "perspective": {
            "aspectRatio": 1.0, "yfov": math.radians(60.0), "znear": 0.05, "zfar": 200.0}}],
        "accessors": writer.accessors,
        "bufferViews": writer.views,
        "buffers": [{"byteLength": len(writer.blob), "uri": bin_name}],
    }
    if lights:
        g["extensions"] = {"KHR_lights_punctual": {"lights": lights}}
    else:
        g["extensionsUsed"].remove("KHR_lights_punctual")
    return g


def write(path, data):
    mode = "wb" if isinstance(data, (bytes, bytearray)) else "w"
    with open(path, mode) as f:
        f.write(data)
    print("make-hall: wrote", os.path.relpath(path))


LIGHTINGS = ["hall", "hall_night", "sealed_room", "sealed_room_dark"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--out", default=OUT, help="output folder (default scenes/hall)")
    ap.add_argument("--dense", action="store_true",
                    help="also write hall_dense.gltf/.bin (about 1.2 M triangles, ~60 MB)")
    ap.add_argument("--triangles", type=int, action="append", default=[], metavar="N",
                    help="also write hall_N.gltf/.bin with at least N triangles (repeatable)")
    args = ap.parse_args(argv)
    base = 37142 - 2 * 240 * 64  # the hall's triangles without the knot
    os.makedirs(args.out, exist_ok=True)
    write(os.path.join(args.out, "hall_tiles.png"), png(256, 256, floor_tiles()))
    variants = [("hall.bin", (240, 64), LIGHTINGS)]
    if args.dense:
        variants.append(("hall_dense.bin", (4800, 128), ["hall_dense"]))
    for n in args.triangles:
        if n < 10000:
            ap.error(f"--triangles {n}: at least 10000 (the hall without its knot has {base})")
        around = 64 if n < 1000000 else 256
        along = -(-(n - base) // (2 * around))
        variants.append((f"hall_{n}.bin", (along, around), [f"hall_{n}"]))
    for bin_name, (along, around), names in variants:
        writer = Writer()
        geometry = build_geometry(along, around)
        for name, mesh, mat in geometry:
            writer.mesh(name, mesh, mat)
        mesh_names = [g[0] for g in geometry]
        write(os.path.join(args.out, bin_name), bytes(writer.blob))
        for variant in names:
            # The dense and scale files are lit as the day hall.
            lighting = variant if variant in LIGHTINGS else "hall"
            g = gltf_for(lighting, writer, mesh_names, bin_name, "hall_tiles.png")
            write(os.path.join(args.out, variant + ".gltf"), json.dumps(g, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
