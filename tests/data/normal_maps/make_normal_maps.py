#!/usr/bin/env python3
"""Writes the normal-map test scenes: a 2 x 2 quad in the z = 0 plane facing +z,
white Lambert (metallic 0, roughness 1), under a directional light of pi W/m^2, so
that its radiance is the cosine between its shading normal and the light. Its
normal texture is one constant texel, linear, that tilts the normal by `tilt`
degrees towards +x (the tangent: u grows with x, v with -y, as glTF maps an image
onto a quad seen from the front).

  tilted_quad.gltf          tilt 45 deg, light straight down, TANGENT in the file:
                            radiance cos 45 = 0.7071 (flat: 1)
  tilted_quad_scale.gltf    the same with normalTexture.scale 0.5: the map's x halved
  tilted_quad_generated.gltf  no TANGENT: the loader generates it (MikkTSpace)
  mirrored_quad.gltf        u runs the other way (u = (1 - x) / 2), no TANGENT: the
                            generated tangent is -x and its handedness -1, so the
                            normal leans towards -x; radiance still cos 45
  grazing_quad.gltf         tilt 80 deg and a camera 10 deg above the quad on the side
                            the normal leans away from: the mapped normal faces away
                            from the viewer (the back-facing rule)
  bumps_quad.gltf           a map of 4 x 4 round bumps (spherical caps) under a low
                            light from +x, for the docs' image
  leak_quad.gltf            tilt 80 deg, light from below the quad at 18 deg, where
                            the mapped normal faces it but the surface does not: no
                            light may reach the point (radiance 0)
  channel1_quad.gltf        a 4 x 1 map, flat in its left half and tilted 45 deg in
                            its right, read through TEXCOORD_1, which runs the other
                            way (u = (1 - x) / 2), while a white base-colour
                            texture reads TEXCOORD_0: the tilted half shows on the
                            left (x < 0), no TANGENT

Self-contained: buffers and the PNG are data: URIs. Run from anywhere."""
import base64
import math
import os
import struct
import sys
import zlib

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "animated"))
from gltf_writer import Buffer, bounds, write  # noqa: E402

FLOAT, UNSIGNED_SHORT = 5126, 5123


def png(width, height, rgba):
    """An RGBA8 PNG: of one colour (a 4-tuple), or rgba(x, y) per pixel."""
    pixel = rgba if callable(rgba) else (lambda x, y: rgba)
    raw = b"".join(b"\0" + b"".join(bytes(pixel(x, y)) for x in range(width)) for y in range(height))

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def texel(tilt_deg):
    """The texel of a normal tilted by tilt_deg towards +x (tangent space), 8-bit."""
    t = math.radians(tilt_deg)
    n = (math.sin(t), 0.0, math.cos(t))
    return tuple(int(round((c * 0.5 + 0.5) * 255)) for c in n) + (255,)


def quad(tilt, name, tangent=True, mirrored=False, scale=None, light_dir=(0, 0, -1),
         camera=None, image=None, channel1=False):
    pos = [(-1.0, -1.0, 0.0), (1.0, -1.0, 0.0), (1.0, 1.0, 0.0), (-1.0, 1.0, 0.0)]
    uv = [((1 - x) / 2 if mirrored else (x + 1) / 2, (1 - y) / 2) for x, y, _ in pos]
    b = Buffer()
    attrs = {"POSITION": b.add(pos, "<3f", "VEC3", FLOAT, minmax=bounds(pos)),
             "NORMAL": b.add([(0.0, 0.0, 1.0)] * 4, "<3f", "VEC3", FLOAT),
             "TEXCOORD_0": b.add(uv, "<2f", "VEC2", FLOAT)}
    if channel1:
        attrs["TEXCOORD_1"] = b.add([((1 - x) / 2, (1 - y) / 2) for x, y, _ in pos], "<2f", "VEC2",
                                    FLOAT)
    if tangent:
        attrs["TANGENT"] = b.add([(-1.0 if mirrored else 1.0, 0.0, 0.0, -1.0 if mirrored else 1.0)] * 4,
                                 "<4f", "VEC4", FLOAT)
    prim = {"attributes": attrs, "indices": b.add([0, 1, 2, 0, 2, 3], "<H", "SCALAR", UNSIGNED_SHORT),
            "material": 0}
    normal = {"index": 0}
    if scale is not None:
        normal["scale"] = scale
    if channel1:
        normal["texCoord"] = 1
    d = light_dir
    # The light node's -z along d: a rotation taking -z to d (about the axis -z x d).
    a = (-0.0 * d[2] + 1.0 * d[1], -1.0 * d[0] - 0.0 * d[2], 0.0)
    al = math.sqrt(a[0] ** 2 + a[1] ** 2)
    ang = math.acos(max(-1.0, min(1.0, -d[2] / math.sqrt(sum(c * c for c in d)))))
    rot = ([0.0, 0.0, 0.0, 1.0] if al < 1e-9 else
           [a[0] / al * math.sin(ang / 2), a[1] / al * math.sin(ang / 2), 0.0, math.cos(ang / 2)])
    nodes = [{"mesh": 0}, {"rotation": rot,
                           "extensions": {"KHR_lights_punctual": {"light": 0}}}]
    if camera:
        nodes.append(camera)
    gltf = {
        "asset": {"version": "2.0", "generator": "voxgi make_normal_maps.py"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "directional", "color": [1, 1, 1], "intensity": math.pi}]}},
        "scene": 0,
        "scenes": [{"nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": [{"primitives": [prim]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0,
                                                "roughnessFactor": 1},
                       "normalTexture": normal}],
        "textures": [{"source": 0}],
        "images": [{"uri": "data:image/png;base64," + base64.b64encode(image or png(4, 4, texel(tilt))).decode()}],
    }
    if channel1:  # a white base-colour texture on TEXCOORD_0
        gltf["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {"index": 1}
        gltf["textures"].append({"source": 1})
        gltf["images"].append({"uri": "data:image/png;base64,"
                               + base64.b64encode(png(1, 1, (255, 255, 255, 255))).decode()})
    if camera:
        gltf["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.05,
                                                                     "zfar": 100}}]
    write(b.finish(gltf), os.path.join("..", "normal_maps", name))


def look_at_rotation(eye, target):
    """The quaternion (x, y, z, w) turning a camera's -z towards target, +y up-ish."""
    f = [t - e for t, e in zip(target, eye)]
    fl = math.sqrt(sum(c * c for c in f))
    f = [c / fl for c in f]
    up = (0.0, 0.0, 1.0) if abs(f[2]) < 0.99 else (0.0, 1.0, 0.0)
    r = (f[1] * up[2] - f[2] * up[1], f[2] * up[0] - f[0] * up[2], f[0] * up[1] - f[1] * up[0])
    rl = math.sqrt(sum(c * c for c in r))
    r = [c / rl for c in r]
    u = (r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2], r[0] * f[1] - r[1] * f[0])
    z = [-c for c in f]
    m = [[r[0], u[0], z[0]], [r[1], u[1], z[1]], [r[2], u[2], z[2]]]  # columns: x, y, z axes
    tr = m[0][0] + m[1][1] + m[2][2]
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        return [(m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s, 0.25 * s]
    if m[0][0] > m[1][1] and m[0][0] > m[2][2]:
        s = math.sqrt(1.0 + m[0][0] - m[1][1] - m[2][2]) * 2
        return [0.25 * s, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s, (m[2][1] - m[1][2]) / s]
    if m[1][1] > m[2][2]:
        s = math.sqrt(1.0 + m[1][1] - m[0][0] - m[2][2]) * 2
        return [(m[0][1] + m[1][0]) / s, 0.25 * s, (m[1][2] + m[2][1]) / s, (m[0][2] - m[2][0]) / s]
    s = math.sqrt(1.0 + m[2][2] - m[0][0] - m[1][1]) * 2
    return [(m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, 0.25 * s, (m[1][0] - m[0][1]) / s]


def camera(eye, target):
    return {"camera": 0, "translation": list(eye), "rotation": look_at_rotation(eye, target)}


top = camera((0.0, 0.0, 4.0), (0.0, 0.0, 0.0))
quad(45, "tilted_quad.gltf", camera=top)
quad(45, "tilted_quad_scale.gltf", scale=0.5, camera=top)
quad(45, "tilted_quad_generated.gltf", tangent=False, camera=top)
quad(45, "mirrored_quad.gltf", tangent=False, mirrored=True, camera=top)
# The normal leans towards +x; the camera sits on the -x side, 10 degrees up.
g = math.radians(10)
quad(80, "grazing_quad.gltf", camera=camera((-6 * math.cos(g), 0.0, 6 * math.sin(g)), (0.0, 0.0, 0.0)))
# Light from below: travelling up and towards -x (the point sees it 18 deg under its plane).
l = math.radians(18)
quad(80, "leak_quad.gltf", light_dir=(-math.cos(l), 0.0, math.sin(l)), camera=top)


def bump(x, y, size=64, cells=4):
    """A spherical cap per cell: the normal of a dome of radius 0.45 cell, flat outside."""
    c = size / cells
    dx = (x + 0.5) % c / c - 0.5
    dy = (y + 0.5) % c / c - 0.5
    r2 = dx * dx + dy * dy
    n = (0.0, 0.0, 1.0)
    if r2 < 0.45 ** 2:
        # Image y runs down, the bitangent up: the normal's y is -dy.
        h = math.sqrt(0.45 ** 2 - r2)
        length = math.sqrt(r2 + h * h)
        n = (dx / length, -dy / length, h / length)
    return tuple(int(round((v * 0.5 + 0.5) * 255)) for v in n) + (255,)


e = math.radians(35)
quad(0, "bumps_quad.gltf", light_dir=(-math.cos(e), -0.3, -math.sin(e)),
     camera=camera((0.0, -1.2, 3.6), (0.0, 0.0, 0.0)), image=png(64, 64, bump))
quad(45, "channel1_quad.gltf", tangent=False, camera=top, channel1=True,
     image=png(4, 1, lambda x, y: texel(45) if x >= 2 else texel(0)))
