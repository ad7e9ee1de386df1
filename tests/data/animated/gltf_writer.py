"""What the generators of this folder share: a glTF buffer built accessor by
accessor, and the file written next to them with the buffer embedded (a base64
data: URI), so each .gltf stands alone."""
import base64
import json
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
