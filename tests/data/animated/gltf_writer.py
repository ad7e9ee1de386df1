"""What the generators of this folder share: a glTF buffer built accessor by
accessor, and the file written next to them with the buffer embedded (a base64
data: URI), so each .gltf stands alone."""
import base64
import json
import math
import os
import struct
import zlib


class Buffer:
    """One buffer's bytes, with its bufferViews and accessors."""

    def __init__(self):
        self.blob = b""
        self.views = []
        self.accessors = []

    def add(self, data, fmt, type_, ctype, target=None, minmax=None):
        """Appends `data` (values or tuples packed with struct format `fmt`, 4-byte
        aligned) as an accessor of glTF type `type_` and componentType `ctype`;
        returns the accessor's index."""
        while len(self.blob) % 4:
            self.blob += b"\0"
        raw = b"".join(struct.pack(fmt, *v) if isinstance(v, tuple) else struct.pack(fmt, v)
                       for v in data)
        view = {"buffer": 0, "byteOffset": len(self.blob), "byteLength": len(raw)}
        if target:
            view["target"] = target
        self.views.append(view)
        acc = {"bufferView": len(self.views) - 1, "componentType": ctype, "count": len(data),
               "type": type_}
        if minmax:
            acc["min"], acc["max"] = minmax
        self.accessors.append(acc)
        self.blob += raw
        return len(self.accessors) - 1

    def finish(self, gltf):
        """Puts the accessors, views and the embedded buffer into `gltf`."""
        gltf["accessors"] = self.accessors
        gltf["bufferViews"] = self.views
        gltf["buffers"] = [{"byteLength": len(self.blob),
                            "uri": "data:application/octet-stream;base64,"
                            + base64.b64encode(self.blob).decode()}]
        return gltf


def bounds(p):
    """POSITION's min and max, as glTF requires them."""
    return [[min(v[i] for v in p) for i in range(3)], [max(v[i] for v in p) for i in range(3)]]


def write(gltf, name):
    """Writes `gltf` as `name` next to this file."""
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), name)
    with open(out, "w") as f:
        json.dump(gltf, f, indent=1)
    print("wrote", out)


def png_rgba(width, height, pixels):
    """An 8-bit RGBA PNG; pixels row by row, top first, (r, g, b, a) each."""
    def chunk(kind, payload):
        return (struct.pack(">I", len(payload)) + kind + payload
                + struct.pack(">I", zlib.crc32(kind + payload) & 0xFFFFFFFF))
    rows = b"".join(b"\0" + bytes(c for p in pixels[y * width:(y + 1) * width] for c in p)
                    for y in range(height))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


def write_next_to(script, name, gltf):
    """Writes `gltf` as `name` in the folder of `script` (a generator's __file__)."""
    out = os.path.join(os.path.dirname(os.path.abspath(script)), name)
    with open(out, "w") as f:
        json.dump(gltf, f, indent=1)
        f.write("\n")
    print("wrote", out)


def quad_primitive(buf, positions, texcoords):
    """A quad facing +z (corners counter-clockwise), material 0: POSITION, NORMAL, then
    each (attribute name, UVs) of `texcoords` in order, then its two triangles."""
    attributes = {"POSITION": buf.add(positions, "<3f", "VEC3", 5126, minmax=bounds(positions)),
                  "NORMAL": buf.add([(0.0, 0.0, 1.0)] * 4, "<3f", "VEC3", 5126)}
    for name, uv in texcoords:
        attributes[name] = buf.add(uv, "<2f", "VEC2", 5126)
    return {"attributes": attributes,
            "indices": buf.add([0, 1, 2, 0, 2, 3], "<H", "SCALAR", 5123),
            "material": 0}


def quad_document(generator, prim, material, png, samplers=None):
    """One textured quad seen by a camera at (0, 0, 2) whose square field of view it
    fills (the texture tests' layout): the mesh of `prim`, `material`, texture 0 from
    the PNG bytes `png`, with sampler 0 when `samplers` are given."""
    g = {
        "asset": {"version": "2.0", "generator": generator},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0.0, 0.0, 2.0]}],
        "cameras": [{"type": "perspective",
                     "perspective": {"yfov": 2.0 * math.atan(0.5), "aspectRatio": 1.0,
                                     "znear": 0.1, "zfar": 10.0}}],
        "meshes": [{"primitives": [prim]}],
        "materials": [material],
    }
    if samplers is not None:
        g["samplers"] = samplers
    g["textures"] = [{"source": 0, "sampler": 0} if samplers is not None else {"source": 0}]
    g["images"] = [{"uri": "data:image/png;base64," + base64.b64encode(png).decode(),
                    "mimeType": "image/png"}]
    return g
