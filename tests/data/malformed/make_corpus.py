#!/usr/bin/env python3
"""Writes the malformed glTF corpus used by tests/scene/gltf_loader_test.cpp.

Every file here starts from a valid one- or two-triangle scene and carries exactly
one defect. The loader must refuse each with voxgi::Error, a one-line message that
starts with the file's path and contains the substring listed in expected.txt
(one line per file: "filename<TAB>expected substring").

The valid starting points are written to valid/ so that the tests can show that
the defect, not the base scene, is what the loader refuses.

Run from anywhere (Python 3, standard library only); the outputs land next to
this script and are committed with it:
    python3 tests/data/malformed/make_corpus.py
"""

import base64
import copy
import json
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
VALID_DIR = os.path.join(HERE, "valid")

FLOAT = 5126
UNSIGNED_BYTE = 5121
UNSIGNED_SHORT = 5123
UNSIGNED_INT = 5125
ARRAY_BUFFER = 34962
ELEMENT_ARRAY_BUFFER = 34963

# JSON cannot spell infinity; these placeholders are replaced by raw number text
# after json.dumps (1e400 overflows a double to +Inf in every common JSON reader).
INF_TOKEN = "__VOXGI_INF__"
NAN_TOKEN = "__VOXGI_NAN__"

QUAD_POSITIONS = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (1.0, 1.0, 0.0), (0.0, 1.0, 0.0)]
QUAD_NORMALS = [(0.0, 0.0, 1.0)] * 4
QUAD_UVS = [(0.0, 1.0), (1.0, 1.0), (1.0, 0.0), (0.0, 0.0)]
QUAD_INDICES = [0, 1, 2, 0, 2, 3]
TRIANGLE_POSITIONS = QUAD_POSITIONS[:3]
TRIANGLE_INDICES = [0, 1, 2]


def pad4(data, fill=b"\0"):
    return data + fill * (-len(data) % 4)


def data_uri(data, mime="application/octet-stream"):
    return "data:%s;base64,%s" % (mime, base64.b64encode(data).decode("ascii"))


def floats(values):
    return b"".join(struct.pack("<%df" % len(v), *v) for v in values)


def finite_bounds(values):
    """min/max over the finite components (a NaN would make the JSON invalid)."""
    lo = [min(v[i] for v in values if all(x == x and abs(x) != float("inf") for x in v)) for i in range(3)]
    hi = [max(v[i] for v in values if all(x == x and abs(x) != float("inf") for x in v)) for i in range(3)]
    return lo, hi


def scene(positions=None, indices=None, normals=False, uvs=False):
    """A valid glTF (as a dict) with one node, one mesh and an embedded buffer.

    Layout: bufferView 0 = positions, 1 = indices (uint16), then optional
    normals and uvs. Accessor 0 = POSITION, 1 = indices, then NORMAL, TEXCOORD_0.
    """
    positions = QUAD_POSITIONS if positions is None else positions
    indices = QUAD_INDICES if indices is None else indices
    blobs = [floats(positions), struct.pack("<%dH" % len(indices), *indices)]
    lo, hi = finite_bounds(positions)
    accessors = [
        {"bufferView": 0, "componentType": FLOAT, "count": len(positions), "type": "VEC3",
         "min": lo, "max": hi},
        {"bufferView": 1, "componentType": UNSIGNED_SHORT, "count": len(indices), "type": "SCALAR"},
    ]
    targets = [ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER]
    attributes = {"POSITION": 0}
    if normals:
        blobs.append(floats(QUAD_NORMALS[: len(positions)]))
        targets.append(ARRAY_BUFFER)
        attributes["NORMAL"] = len(accessors)
        accessors.append({"bufferView": len(blobs) - 1, "componentType": FLOAT,
                          "count": len(positions), "type": "VEC3"})
    if uvs:
        blobs.append(floats(QUAD_UVS[: len(positions)]))
        targets.append(ARRAY_BUFFER)
        attributes["TEXCOORD_0"] = len(accessors)
        accessors.append({"bufferView": len(blobs) - 1, "componentType": FLOAT,
                          "count": len(positions), "type": "VEC2"})
    buffer = b""
    views = []
    for blob, target in zip(blobs, targets):
        views.append({"buffer": 0, "byteOffset": len(buffer), "byteLength": len(blob), "target": target})
        buffer += pad4(blob)
    return {
        "asset": {"version": "2.0", "generator": "voxgi make_corpus.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": attributes, "indices": 1, "mode": 4}]}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(buffer), "uri": data_uri(buffer)}],
    }


def png_chunk(kind, payload):
    return struct.pack(">I", len(payload)) + kind + payload + struct.pack(">I", zlib.crc32(kind + payload) & 0xFFFFFFFF)


def png(width, height, rgba_rows=None):
    """An 8-bit PNG. With rgba_rows, a complete RGBA image; without, only the
    first scanline of an RGB image is stored (enough for a header-only reader)."""
    signature = b"\x89PNG\r\n\x1a\n"
    if rgba_rows is not None:
        ihdr = struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)
        raw = b"".join(b"\0" + bytes(row) for row in rgba_rows)
    else:
        ihdr = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
        raw = b"\0" + b"\0" * (3 * width)
    return (signature + png_chunk(b"IHDR", ihdr) + png_chunk(b"IDAT", zlib.compress(raw, 9))
            + png_chunk(b"IEND", b""))


TINY_PNG = png(2, 2, [[255, 0, 0, 255, 0, 255, 0, 255], [0, 0, 255, 255, 255, 255, 255, 255]])


def textured(image):
    """The quad with a base-colour texture whose image is `image` (a glTF image dict)."""
    g = scene(uvs=True)
    g["meshes"][0]["primitives"][0]["material"] = 0
    g["materials"] = [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]
    g["samplers"] = [{}]
    g["textures"] = [{"source": 0, "sampler": 0}]
    g["images"] = [image]
    return g


def to_json(g):
    text = json.dumps(g, indent=1, allow_nan=False)
    return text.replace('"%s"' % INF_TOKEN, "1e400").replace('"%s"' % NAN_TOKEN, "NaN").encode() + b"\n"


def glb(g, bin_data):
    """A .glb from a dict whose buffer 0 has no uri, with bin_data as its BIN chunk."""
    return glb_from_text(json.dumps(g, separators=(",", ":")).encode(), bin_data)


def glb_from_text(json_text, bin_data):
    text = pad4(json_text, b" ")
    body = pad4(bin_data)
    chunks = (struct.pack("<I", len(text)) + b"JSON" + text + struct.pack("<I", len(body)) + b"BIN\0" + body)
    return b"glTF" + struct.pack("<II", 2, 12 + len(chunks)) + chunks


def glb_scene():
    g = scene()
    data = base64.b64decode(g["buffers"][0]["uri"].split(",", 1)[1])
    del g["buffers"][0]["uri"]
    return g, data


# --- the cases ----------------------------------------------------------------
# Each returns (bytes, expected substring). The substring names the problem as a
# user should read it; where the loader says something else, the test fails and
# tells us so.

CASES = {}


def case(name, expected):
    def register(fn):
        CASES[name] = (fn, expected)
        return fn
    return register


def edited(fn):
    """Case body that edits a fresh quad scene in place."""
    def build():
        g = scene()
        fn(g)
        return to_json(g)
    return build


# Container and JSON level.
case("empty.gltf", "empty")(lambda: b"")
case("not_json.gltf", "parse error")(lambda: b"This is not a glTF file, just text.\n")
case("truncated_json.gltf", "parse error")(lambda: (lambda t: t[: len(t) // 2])(to_json(scene())))
case("json_array.gltf", "not a JSON object")(lambda: to_json([scene()]))


# tinygltf converts "extras" recursively: nesting this deep would overflow the stack.
DEEP = b"[" * 100000 + b"]" * 100000


@case("deep_nesting.gltf", "nested deeper than")
def _():
    g = scene()
    g["extras"] = "__VOXGI_DEEP__"
    return to_json(g).replace(b'"__VOXGI_DEEP__"', DEEP)


@case("deep_nesting.glb", "nested deeper than")
def _():
    g, data = glb_scene()
    g["extras"] = "__VOXGI_DEEP__"
    return glb_from_text(json.dumps(g, separators=(",", ":")).encode().replace(b'"__VOXGI_DEEP__"', DEEP), data)


@case("missing_asset.gltf", "\"asset\"")
@edited
def _(g):
    del g["asset"]


@case("missing_asset_version.gltf", "version")
@edited
def _(g):
    del g["asset"]["version"]


# Buffers and views.
@case("missing_bin.gltf", "missing_buffer.bin")
@edited
def _(g):
    g["buffers"][0]["uri"] = "missing_buffer.bin"


@case("buffer_bytelength_mismatch.gltf", "byteLength")
@edited
def _(g):
    # 4 KiB of unused bytes after the geometry, so that an error message quoting
    # the data: URI shows as the wall of text it would be for a real file.
    data = base64.b64decode(g["buffers"][0]["uri"].split(",", 1)[1]) + bytes(range(256)) * 16
    g["buffers"][0]["uri"] = data_uri(data)
    g["buffers"][0]["byteLength"] = len(data) + 8


@case("bufferview_beyond_buffer.gltf", "exceed buffer")
@edited
def _(g):
    g["bufferViews"][1]["byteLength"] += 64


@case("bufferview_bad_buffer.gltf", "bufferViews[0].buffer 3 points nowhere (1 buffer)")
@edited
def _(g):
    g["bufferViews"][0]["buffer"] = 3


@case("bytestride_too_small.gltf", "smaller than an element")
@edited
def _(g):
    g["bufferViews"][0]["byteStride"] = 4


# Accessors.
@case("accessor_count_too_large.gltf", "needs 60 bytes")
@edited
def _(g):
    g["accessors"][0]["count"] = 5  # 4 vertices stored


@case("accessor_count_zero.gltf", "count 0")
@edited
def _(g):
    g["accessors"][0]["count"] = 0


@case("accessor_count_huge.gltf", "count 2147483649")
@edited
def _(g):
    g["accessors"][0]["count"] = 2**31 + 1


@case("accessor_count_overflow.gltf", "count 4611686018427387905")
@edited
def _(g):
    g["accessors"][0]["count"] = 2**62 + 1  # stride * count wraps a 64-bit size


@case("accessor_bad_bufferview.gltf", "accessors[0].bufferView 9 points nowhere (2 bufferViews)")
@edited
def _(g):
    g["accessors"][0]["bufferView"] = 9


@case("position_bad_accessor.gltf", "attributes.POSITION 9 points nowhere (2 accessors)")
@edited
def _(g):
    g["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 9


@case("indices_bad_accessor.gltf", "primitive indices accessor out of bounds")
@edited
def _(g):
    g["meshes"][0]["primitives"][0]["indices"] = 9


@case("position_vec2.gltf", "element type VEC2 is not allowed")
@edited
def _(g):
    g["accessors"][0]["type"] = "VEC2"
    del g["accessors"][0]["min"], g["accessors"][0]["max"]


@case("position_ubyte.gltf", "accessors[0] (POSITION): normalized UNSIGNED_BYTE components need KHR_mesh_quantization")
@edited
def _(g):
    g["accessors"][0]["componentType"] = UNSIGNED_BYTE
    g["accessors"][0]["normalized"] = True


@case("indices_float.gltf", "wrong component type 5126")
@edited
def _(g):
    g["accessors"][1]["componentType"] = FLOAT
    g["accessors"][1]["count"] = 3  # 12 bytes of the 12-byte view


@case("no_position.gltf", "no POSITION")
@edited
def _(g):
    g["meshes"][0]["primitives"][0]["attributes"] = {"TEXCOORD_0": 0}


def sparse_scene(indices=(1,), values=((2.0, 0.0, 0.0),), itype=UNSIGNED_SHORT, count=None):
    """The quad whose POSITION has a sparse part: `indices` (componentType
    `itype`) replaced by `values`, in a second buffer; count defaults to theirs."""
    g = scene()
    fmt = {UNSIGNED_BYTE: "B", UNSIGNED_SHORT: "H", UNSIGNED_INT: "I", FLOAT: "f"}[itype]
    packed = struct.pack("<%d%s" % (len(indices), fmt), *indices)
    data = pad4(packed) + floats(values)
    g["buffers"].append({"byteLength": len(data), "uri": data_uri(data)})
    g["bufferViews"].append({"buffer": 1, "byteOffset": 0, "byteLength": len(packed)})
    g["bufferViews"].append({"buffer": 1, "byteOffset": len(pad4(packed)), "byteLength": 12 * len(values)})
    g["accessors"][0]["sparse"] = {
        "count": len(indices) if count is None else count,
        "indices": {"bufferView": 2, "componentType": itype},
        "values": {"bufferView": 3},
    }
    final = list(QUAD_POSITIONS)
    for i, v in zip(indices, values):
        if 0 <= int(i) < len(final):
            final[int(i)] = v
    lo, hi = finite_bounds(final)
    g["accessors"][0]["min"], g["accessors"][0]["max"] = lo, hi
    return g


# Sparse accessors: each rule of glTF 2.0's accessor.sparse.
@case("sparse_index_out_of_range.gltf", "accessors[0].sparse.indices[1] 4: out of range")
def _():
    return to_json(sparse_scene(indices=(1, 4), values=((2.0, 0.0, 0.0), (3.0, 0.0, 0.0))))


@case("sparse_indices_not_increasing.gltf", "sparse indices must strictly increase")
def _():
    return to_json(sparse_scene(indices=(2, 1), values=((2.0, 0.0, 0.0), (3.0, 0.0, 0.0))))


@case("sparse_indices_repeated.gltf", "sparse indices must strictly increase")
def _():
    return to_json(sparse_scene(indices=(1, 1), values=((2.0, 0.0, 0.0), (3.0, 0.0, 0.0))))


@case("sparse_count_above_count.gltf", "accessors[0].sparse.count 5: must be from 1 to the accessor's count 4")
def _():
    values = [(float(i), 2.0, 0.0) for i in range(5)]
    return to_json(sparse_scene(indices=range(5), values=values))


@case("sparse_count_zero.gltf", "accessors[0].sparse.count 0")
def _():
    return to_json(sparse_scene(count=0))


@case("sparse_count_beyond_data.gltf", "accessors[0].sparse.indices: needs 4 bytes")
def _():
    return to_json(sparse_scene(count=2))


@case("sparse_indices_float.gltf", "accessors[0].sparse.indices.componentType 5126")
def _():
    return to_json(sparse_scene(indices=(1.0,), itype=FLOAT))


@case("sparse_values_beyond_bufferview.gltf", "accessors[0].sparse.values: needs 12 bytes")
def _():
    g = sparse_scene()
    g["bufferViews"][3]["byteLength"] = 8
    return to_json(g)


@case("sparse_indices_bytestride.gltf", "sparse data must not have")
def _():
    g = sparse_scene()
    g["bufferViews"][2]["byteStride"] = 4
    g["bufferViews"][2]["byteLength"] = 4
    return to_json(g)


@case("sparse_indices_bad_bufferview.gltf", "accessors[0].sparse.indices.bufferView 7 points nowhere")
def _():
    g = sparse_scene()
    g["accessors"][0]["sparse"]["indices"]["bufferView"] = 7
    return to_json(g)


# KHR_mesh_quantization: its component types only with the extension, and
# normals only normalized signed.
def quantized_scene(attribute, ctype, normalized, extension=True):
    """The quad with `attribute` (NORMAL or TEXCOORD_0) of `ctype` components."""
    g = scene(normals=attribute == "NORMAL", uvs=attribute == "TEXCOORD_0")
    acc = g["accessors"][2]
    values = QUAD_NORMALS if attribute == "NORMAL" else QUAD_UVS
    fmt = {5120: "b", UNSIGNED_BYTE: "B", 5122: "h", UNSIGNED_SHORT: "H"}[ctype]
    size = struct.calcsize(fmt)
    n = len(values[0])
    stride = -(-n * size // 4) * 4
    one = {1: 127, 2: 32767}[size] if fmt in "bh" else {1: 255, 2: 65535}[size]
    data = b"".join(pad4(struct.pack("<%d%s" % (n, fmt), *[int(round(x * one)) for x in v])) for v in values)
    g["buffers"].append({"byteLength": len(data), "uri": data_uri(data)})
    view = {"buffer": 1, "byteOffset": 0, "byteLength": len(data)}
    if stride != n * size:
        view["byteStride"] = stride
    g["bufferViews"].append(view)
    acc["bufferView"] = len(g["bufferViews"]) - 1
    acc["componentType"] = ctype
    if normalized:
        acc["normalized"] = True
    if extension:
        g["extensionsUsed"] = ["KHR_mesh_quantization"]
        g["extensionsRequired"] = ["KHR_mesh_quantization"]
    return g


@case("quantized_without_extension.gltf", "accessors[2] (NORMAL): normalized BYTE components need KHR_mesh_quantization")
def _():
    return to_json(quantized_scene("NORMAL", 5120, True, extension=False))


@case("quantized_normal_not_normalized.gltf", "accessors[2] (NORMAL): BYTE components: KHR_mesh_quantization allows normals of normalized BYTE or SHORT only")
def _():
    return to_json(quantized_scene("NORMAL", 5120, False))


@case("quantized_normal_unsigned.gltf", "KHR_mesh_quantization allows normals of normalized BYTE or SHORT only")
def _():
    return to_json(quantized_scene("NORMAL", UNSIGNED_SHORT, True))


@case("texcoord_not_normalized.gltf", "accessors[2] (TEXCOORD_0): UNSIGNED_BYTE components need KHR_mesh_quantization")
def _():
    return to_json(quantized_scene("TEXCOORD_0", UNSIGNED_BYTE, False, extension=False))


@case("float_normalized.gltf", "normalized FLOAT components")
@edited
def _(g):
    g["accessors"][0]["normalized"] = True


# Samplers of a texture a material reads.
@case("sampler_bad_wrap.gltf", "samplers[0].wrapT 10498: not REPEAT")
def _():
    g = textured({"uri": data_uri(TINY_PNG, "image/png")})
    g["samplers"] = [{"wrapT": 10498}]
    return to_json(g)


@case("texcoord_set_missing.gltf",
      "materials[0].pbrMetallicRoughness.baseColorTexture.texCoord 1: the primitive has no TEXCOORD_1")
def _():
    g = textured({"uri": data_uri(TINY_PNG, "image/png")})
    g["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = 1
    return to_json(g)


@case("texture_transform_texcoord_missing.gltf",
      "baseColorTexture.extensions.KHR_texture_transform.texCoord 2: the primitive has no TEXCOORD_2")
def _():
    g = textured({"uri": data_uri(TINY_PNG, "image/png")})
    g["extensionsUsed"] = ["KHR_texture_transform"]
    g["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
        "KHR_texture_transform": {"texCoord": 2}}
    return to_json(g)


@case("texture_transform_bad_offset.gltf",
      "materials[0].pbrMetallicRoughness.baseColorTexture.extensions.KHR_texture_transform.offset: needs 2 numbers")
def _():
    g = textured({"uri": data_uri(TINY_PNG, "image/png")})
    g["extensionsUsed"] = ["KHR_texture_transform"]
    g["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
        "KHR_texture_transform": {"offset": [0.5]}}
    return to_json(g)


@case("texture_transform_bad_rotation.gltf", "KHR_texture_transform.rotation: not a number")
def _():
    g = textured({"uri": data_uri(TINY_PNG, "image/png")})
    g["extensionsUsed"] = ["KHR_texture_transform"]
    g["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
        "KHR_texture_transform": {"rotation": "quarter"}}
    return to_json(g)


@case("occlusion_strength_above_one.gltf", "materials[0].occlusionTexture.strength 2: outside [0, 1]")
def _():
    g = textured({"uri": data_uri(TINY_PNG, "image/png")})
    g["materials"][0]["occlusionTexture"] = {"index": 0, "strength": 2.0}
    return to_json(g)


@case("sampler_bad_mag_filter.gltf", "samplers[0].magFilter 9984: not NEAREST (9728) or LINEAR (9729)")
def _():
    g = textured({"uri": data_uri(TINY_PNG, "image/png")})
    g["samplers"] = [{"magFilter": 9984}]
    return to_json(g)


@case("sampler_bad_min_filter.gltf", "samplers[0].minFilter 9730")
def _():
    g = textured({"uri": data_uri(TINY_PNG, "image/png")})
    g["samplers"] = [{"minFilter": 9730}]
    return to_json(g)


@case("normal_count_mismatch.gltf", "counts differ")
def _():
    g = scene(normals=True)
    g["accessors"][2]["count"] = 3
    return to_json(g)


# Vertex data.
@case("index_out_of_range.gltf", "out of range")
def _():
    return to_json(scene(indices=[0, 1, 2, 0, 2, 7]))


@case("nan_position.gltf", "NaN or Inf position")
def _():
    return to_json(scene(positions=[(0.0, 0.0, 0.0), (1.0, float("nan"), 0.0), (1.0, 1.0, 0.0), (0.0, 1.0, 0.0)]))


@case("inf_position.gltf", "NaN or Inf position")
def _():
    return to_json(scene(positions=[(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (float("inf"), 1.0, 0.0), (0.0, 1.0, 0.0)]))


@case("position_overflow_after_transform.gltf", "overflows")
@edited
def _(g):
    # A finite float transform that sends vertex (1, 0, 0) to x = 6e38 > FLT_MAX.
    g["nodes"][0]["scale"] = [3e38, 3e38, 3e38]
    g["nodes"][0]["translation"] = [3e38, 0.0, 0.0]


# Node transforms.
@case("nan_matrix.gltf", "parse error")  # JSON has no NaN: the text says NaN anyway
@edited
def _(g):
    g["nodes"][0]["matrix"] = [1.0, 0.0, 0.0, 0.0, 0.0, NAN_TOKEN, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0]


@case("inf_matrix.gltf", "number overflow")  # 1e400 is +Inf even as a double
@edited
def _(g):
    g["nodes"][0]["matrix"] = [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, INF_TOKEN, 0.0, 0.0, 1.0]


@case("matrix_float_overflow.gltf", "NaN or Inf")
@edited
def _(g):
    # Finite as a double, infinite as the float the loader works in.
    g["nodes"][0]["matrix"] = [1e300, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0]


@case("inf_translation.gltf", "NaN or Inf")
@edited
def _(g):
    g["nodes"][0]["translation"] = [1e39, 0.0, 0.0]  # +Inf as a float


# Node graph.
@case("node_cycle.gltf", "cycle")
@edited
def _(g):
    g["nodes"] = [{"children": [1]}, {"children": [0], "mesh": 0}]


@case("node_self_child.gltf", "own child")
@edited
def _(g):
    g["nodes"][0]["children"] = [0]


@case("node_two_parents.gltf", "two parents")
@edited
def _(g):
    g["scenes"][0]["nodes"] = [0, 1]
    g["nodes"] = [{"children": [2]}, {"children": [2]}, {"mesh": 0}]


@case("node_bad_child.gltf", "nodes[0].children[0] 7 points nowhere (1 node)")
@edited
def _(g):
    g["nodes"][0]["children"] = [7]


@case("scene_bad_node.gltf", "scenes[0].nodes[1] 5 points nowhere (1 node)")
@edited
def _(g):
    g["scenes"][0]["nodes"] = [0, 5]


@case("node_bad_mesh.gltf", "nodes[0].mesh 7 points nowhere (1 mesh)")
@edited
def _(g):
    g["nodes"][0]["mesh"] = 7


@case("node_negative_mesh.gltf", "mesh -2")
@edited
def _(g):
    g["nodes"][0]["mesh"] = -2


@case("node_bad_camera.gltf", "nodes[1].camera 3 points nowhere (0 cameras)")
@edited
def _(g):
    g["nodes"].append({"camera": 3, "translation": [0.0, 0.0, 2.0]})
    g["scenes"][0]["nodes"].append(1)


@case("camera_zero_yfov.gltf", "yfov")
@edited
def _(g):
    g["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.0, "znear": 0.01}}]
    g["nodes"].append({"camera": 0, "translation": [0.0, 0.0, 2.0]})
    g["scenes"][0]["nodes"].append(1)


@case("node_bad_light.gltf", "nodes[0].extensions.KHR_lights_punctual.light 4 points nowhere (1 light)")
@edited
def _(g):
    g["extensionsUsed"] = ["KHR_lights_punctual"]
    g["extensions"] = {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 1.0}]}}
    g["nodes"][0]["extensions"] = {"KHR_lights_punctual": {"light": 4}}


@case("light_unknown_type.gltf", "unknown type 'area'")
@edited
def _(g):
    g["extensionsUsed"] = ["KHR_lights_punctual"]
    g["extensions"] = {"KHR_lights_punctual": {"lights": [{"type": "area", "intensity": 1.0}]}}
    g["nodes"][0]["extensions"] = {"KHR_lights_punctual": {"light": 0}}


@case("primitive_bad_mode.gltf", "mode 9")
@edited
def _(g):
    g["meshes"][0]["primitives"][0]["mode"] = 9  # glTF modes are 0..6


# Extensions.
@case("unknown_required_extension.gltf", "KHR_draco_mesh_compression")
@edited
def _(g):
    g["extensionsUsed"] = ["KHR_draco_mesh_compression"]
    g["extensionsRequired"] = ["KHR_draco_mesh_compression"]


@case("made_up_required_extension.gltf", "VOXGI_made_up_extension")
@edited
def _(g):
    g["extensionsUsed"] = ["VOXGI_made_up_extension"]
    g["extensionsRequired"] = ["VOXGI_made_up_extension"]


# Materials, textures, images.
@case("primitive_bad_material.gltf", "meshes[0].primitives[0].material 3 points nowhere (1 material)")
@edited
def _(g):
    g["materials"] = [{}]
    g["meshes"][0]["primitives"][0]["material"] = 3


@case("material_inf_emission.gltf", "NaN or Inf")
@edited
def _(g):
    g["materials"] = [{"emissiveFactor": [1e39, 1.0, 1.0]}]  # +Inf as a float
    g["meshes"][0]["primitives"][0]["material"] = 0


@case("material_bad_texture_index.gltf", "baseColorTexture.index 3 points nowhere (1 texture)")
def _():
    g = textured({"uri": data_uri(TINY_PNG, "image/png")})
    g["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"] = 3
    return to_json(g)


@case("material_bad_emissive_texture_index.gltf",
      "materials[0].emissiveTexture.index 2 points nowhere (1 texture)")
def _():
    g = textured({"uri": data_uri(TINY_PNG, "image/png")})
    g["materials"][0]["emissiveFactor"] = [1.0, 1.0, 1.0]
    g["materials"][0]["emissiveTexture"] = {"index": 2}
    return to_json(g)


@case("material_bad_metallic_roughness_texture_index.gltf",
      "materials[0].pbrMetallicRoughness.metallicRoughnessTexture.index -2 points nowhere")
def _():
    g = textured({"uri": data_uri(TINY_PNG, "image/png")})
    g["materials"][0]["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {"index": -2}
    return to_json(g)


@case("texture_bad_image_index.gltf", "textures[0].source 5 points nowhere (1 image)")
def _():
    g = textured({"uri": data_uri(TINY_PNG, "image/png")})
    g["textures"][0]["source"] = 5
    return to_json(g)


@case("missing_texture_image.gltf", "missing_basecolor.png")
def _():
    return to_json(textured({"uri": "missing_basecolor.png"}))


@case("image_not_decodable.gltf", "not a decodable")
def _():
    return to_json(textured({"uri": data_uri(b"\x89PNG\r\n\x1a\n but not really a PNG", "image/png")}))


@case("huge_texture.gltf", "exceeds")
def _():
    return to_json(textured({"uri": data_uri(png(65536, 65536), "image/png")}))


@case("image_bufferview_beyond_buffer.gltf", "exceed buffer")
def _():
    g = textured({"bufferView": 0, "mimeType": "image/png"})
    # The PNG goes in a buffer of its own; its view claims 16 bytes more than there are.
    g["buffers"].append({"byteLength": len(pad4(TINY_PNG)), "uri": data_uri(pad4(TINY_PNG))})
    g["bufferViews"].append({"buffer": 1, "byteOffset": 0, "byteLength": len(pad4(TINY_PNG)) + 16})
    g["images"][0]["bufferView"] = len(g["bufferViews"]) - 1
    return to_json(g)


@case("image_bufferview_offset_beyond_buffer.gltf", "exceed buffer")
def _():
    g = textured({"bufferView": 0, "mimeType": "image/png"})
    # The image's view starts 100 MB past the end of its 76-byte buffer.
    g["buffers"].append({"byteLength": len(pad4(TINY_PNG)), "uri": data_uri(pad4(TINY_PNG))})
    g["bufferViews"].append({"buffer": 1, "byteOffset": 100000000, "byteLength": 4096})
    g["images"][0]["bufferView"] = len(g["bufferViews"]) - 1
    return to_json(g)


# Binary glTF.
@case("bad_magic.glb", "magic")
def _():
    g, data = glb_scene()
    return b"glTX" + glb(g, data)[4:]


@case("truncated.glb", "truncated")
def _():
    g, data = glb_scene()
    whole = glb(g, data)
    return whole[: len(whole) * 2 // 3]


@case("glb_too_short.glb", "truncated GLB")
def _():
    g, data = glb_scene()
    return glb(g, data)[:12]


@case("glb_bin_chunk_too_long.glb", "BIN")
def _():
    g, data = glb_scene()
    whole = bytearray(glb(g, data))
    json_length = struct.unpack_from("<I", whole, 12)[0]
    bin_header = 20 + json_length
    struct.pack_into("<I", whole, bin_header, len(data) + 64)
    return bytes(whole)


@case("glb_missing_bin_chunk.glb", "BIN")
def _():
    g, _ = glb_scene()
    text = pad4(json.dumps(g, separators=(",", ":")).encode(), b" ")
    return b"glTF" + struct.pack("<II", 2, 20 + len(text)) + struct.pack("<I", len(text)) + b"JSON" + text



# Validity rules of the glTF 2.0 spec for the parts voxgi reads (see README,
# "glTF validity"). Index errors name the field: "nodes[0].mesh 7 points nowhere".
@case("asset_version_3.gltf", 'asset.version "3.0": only glTF 2.x is supported')
@edited
def _(g):
    g["asset"]["version"] = "3.0"


@case("asset_version_not_a_version.gltf", "not a MAJOR.MINOR version")
@edited
def _(g):
    g["asset"]["version"] = "two"


@case("asset_min_version_newer.gltf", 'asset.minVersion "2.1"')
@edited
def _(g):
    g["asset"]["version"] = "2.1"
    g["asset"]["minVersion"] = "2.1"


@case("required_extension_not_used.gltf", "extensionsRequired[0] KHR_lights_punctual is not in extensionsUsed")
@edited
def _(g):
    g["extensionsRequired"] = ["KHR_lights_punctual"]


@case("scene_out_of_range.gltf", "scene 4 out of range (2 scenes)")
@edited
def _(g):
    g["scenes"].append({"nodes": [0]})
    g["scene"] = 4


@case("scene_without_scenes.gltf", "scene 0 out of range (0 scenes)")
@edited
def _(g):
    del g["scenes"]


@case("scene_non_root_node.gltf", "scenes[0].nodes[1] 1 is not a root node")
@edited
def _(g):
    g["nodes"] = [{"children": [1]}, {"mesh": 0}]
    g["scenes"][0]["nodes"] = [0, 1]


@case("scene_node_twice.gltf", "scenes[0].nodes[1] 0 is listed twice")
@edited
def _(g):
    g["scenes"][0]["nodes"] = [0, 0]


@case("unused_node_bad_mesh.gltf", "nodes[1].mesh 7 points nowhere (1 mesh)")
@edited
def _(g):
    g["nodes"].append({"mesh": 7})  # in no scene: every node is checked all the same


@case("mesh_no_primitives.gltf", "meshes[1].primitives is empty")
@edited
def _(g):
    g["meshes"].append({"primitives": []})


@case("normal_bad_accessor.gltf", "meshes[0].primitives[0].attributes.NORMAL 9 points nowhere (2 accessors)")
@edited
def _(g):
    g["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = 9


@case("tangent_bad_accessor.gltf", "attributes.TANGENT 9 points nowhere")
@edited
def _(g):
    g["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] = 9


@case("accessor_offset_unaligned.gltf", "not a multiple of the 4-byte component size")
@edited
def _(g):
    g["accessors"][0]["byteOffset"] = 2
    g["accessors"][0]["count"] = 3


@case("texcoord_unaligned.gltf", "not 4-byte aligned")
def _():
    g = scene()
    uvs = bytes([0, 255, 255, 255, 255, 0, 0, 0])  # UNSIGNED_BYTE VEC2: 2-byte elements
    data = base64.b64decode(g["buffers"][0]["uri"].split(",", 1)[1]) + uvs
    g["buffers"][0] = {"byteLength": len(data), "uri": data_uri(data)}
    g["bufferViews"].append({"buffer": 0, "byteOffset": len(data) - 8, "byteLength": 8, "target": ARRAY_BUFFER})
    g["accessors"].append({"bufferView": 2, "componentType": UNSIGNED_BYTE, "normalized": True,
                           "count": 4, "type": "VEC2"})
    g["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 2
    return to_json(g)


def with_color(g, data, component_type, kind, count, normalized=None):
    """Appends `data` as a COLOR_0 accessor (and its bufferView) to the quad `g`."""
    buf = base64.b64decode(g["buffers"][0]["uri"].split(",", 1)[1])
    offset = len(buf)
    buf += pad4(data)
    g["buffers"][0] = {"byteLength": len(buf), "uri": data_uri(buf)}
    g["bufferViews"].append({"buffer": 0, "byteOffset": offset, "byteLength": len(data),
                             "target": ARRAY_BUFFER})
    accessor = {"bufferView": len(g["bufferViews"]) - 1, "componentType": component_type,
                "count": count, "type": kind}
    if normalized is not None:
        accessor["normalized"] = normalized
    g["accessors"].append(accessor)
    g["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = len(g["accessors"]) - 1
    return g


@case("color0_wrong_type.gltf", "accessor 2 (COLOR_0): element type VEC2 is not allowed here")
def _():
    return to_json(with_color(scene(), floats([(1.0, 0.0)] * 4), FLOAT, "VEC2", 4))


@case("color0_wrong_count.gltf", "COLOR_0 and POSITION counts differ")
def _():
    return to_json(with_color(scene(), floats([(1.0, 0.0, 0.0, 1.0)] * 3), FLOAT, "VEC4", 3))


@case("color0_not_normalized.gltf", "accessors[2] (COLOR_0): integer colours must be normalized")
def _():
    return to_json(with_color(scene(), bytes([255, 0, 0, 255] * 4), UNSIGNED_BYTE, "VEC4", 4))


def with_tangent(g, data, kind, count):
    """Appends `data` as a FLOAT TANGENT accessor (and its bufferView) to the quad `g`."""
    buf = base64.b64decode(g["buffers"][0]["uri"].split(",", 1)[1])
    offset = len(buf)
    buf += pad4(data)
    g["buffers"][0] = {"byteLength": len(buf), "uri": data_uri(buf)}
    g["bufferViews"].append({"buffer": 0, "byteOffset": offset, "byteLength": len(data),
                             "target": ARRAY_BUFFER})
    g["accessors"].append({"bufferView": len(g["bufferViews"]) - 1, "componentType": FLOAT,
                           "count": count, "type": kind})
    g["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] = len(g["accessors"]) - 1
    return g


@case("tangent_wrong_type.gltf", "accessor 2 (TANGENT): element type VEC3 is not allowed here")
def _():
    return to_json(with_tangent(scene(), floats([(1.0, 0.0, 0.0)] * 4), "VEC3", 4))


@case("tangent_wrong_count.gltf", "TANGENT and POSITION counts differ")
def _():
    return to_json(with_tangent(scene(), floats([(1.0, 0.0, 0.0, 1.0)] * 3), "VEC4", 3))


@case("tangent_nan.gltf", "accessors[2] (TANGENT): element 1 is NaN or Inf")
def _():
    t = [(1.0, 0.0, 0.0, 1.0), (float("nan"), 0.0, 0.0, 1.0), (1.0, 0.0, 0.0, 1.0), (1.0, 0.0, 0.0, 1.0)]
    return to_json(with_tangent(scene(), floats(t), "VEC4", 4))


# tinygltf refuses these two before voxgi's own checks, in its own words.
@case("bytestride_not_multiple_of_4.gltf", "must be the multiple of 4 : 14")
@edited
def _(g):
    g["bufferViews"][0]["byteStride"] = 14


@case("bytestride_too_large.gltf", "must be the multiple of 4 : 256")
@edited
def _(g):
    g["bufferViews"][0]["byteStride"] = 256


@case("indices_with_bytestride.gltf", "index data must not have a byteStride")
@edited
def _(g):
    g["bufferViews"][1]["byteStride"] = 4
    g["accessors"][1]["count"] = 3


@case("index_primitive_restart.gltf", "primitive restart value")
def _():
    return to_json(scene(indices=[0, 1, 2, 0, 2, 65535]))


@case("position_no_bounds.gltf", "min and max must both be given")
@edited
def _(g):
    del g["accessors"][0]["min"], g["accessors"][0]["max"]


@case("position_max_mismatch.gltf", "accessors[0].max[0] 2: the data's maximum is 1")
@edited
def _(g):
    g["accessors"][0]["max"] = [2.0, 1.0, 0.0]


@case("position_min_mismatch.gltf", "accessors[0].min[1] 0.5: the data's minimum is 0")
@edited
def _(g):
    g["accessors"][0]["min"] = [0.0, 0.5, 0.0]


def with_material(material):
    def build():
        g = scene()
        g["materials"] = [material]
        g["meshes"][0]["primitives"][0]["material"] = 0
        return to_json(g)
    return build


case("material_metallic_above_one.gltf", "pbrMetallicRoughness.metallicFactor 1.5: outside [0, 1]")(
    with_material({"pbrMetallicRoughness": {"metallicFactor": 1.5}}))
case("material_negative_roughness.gltf", "roughnessFactor -0.25: outside [0, 1]")(
    with_material({"pbrMetallicRoughness": {"roughnessFactor": -0.25}}))
case("material_base_color_above_one.gltf", "baseColorFactor[1] 2: outside [0, 1]")(
    with_material({"pbrMetallicRoughness": {"baseColorFactor": [1.0, 2.0, 1.0, 1.0]}}))
case("material_negative_emission.gltf", "materials[0].emissiveFactor[2] -1")(
    with_material({"emissiveFactor": [1.0, 1.0, -1.0]}))
case("material_bad_alpha_mode.gltf", 'alphaMode "SOMETIMES": not OPAQUE, MASK or BLEND')(
    with_material({"alphaMode": "SOMETIMES"}))
case("material_negative_alpha_cutoff.gltf", "alphaCutoff -0.5")(
    with_material({"alphaMode": "MASK", "alphaCutoff": -0.5}))


@case("material_negative_emissive_strength.gltf", "emissiveStrength -2")
def _():
    g = json.loads(with_material({"emissiveFactor": [1.0, 1.0, 1.0], "extensions": {
        "KHR_materials_emissive_strength": {"emissiveStrength": -2.0}}})())
    g["extensionsUsed"] = ["KHR_materials_emissive_strength"]
    return to_json(g)


@case("texture_bad_sampler.gltf", "textures[0].sampler 4 points nowhere (1 sampler)")
def _():
    g = textured({"uri": data_uri(TINY_PNG, "image/png")})
    g["textures"][0]["sampler"] = 4
    return to_json(g)


def with_camera(camera):
    def build():
        g = scene()
        g["cameras"] = [camera]
        g["nodes"].append({"camera": 0, "translation": [0.0, 0.0, 2.0]})
        g["scenes"][0]["nodes"].append(1)
        return to_json(g)
    return build


case("camera_zero_znear.gltf", "cameras[0].perspective.znear 0: must be positive")(
    with_camera({"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.0}}))
case("camera_zfar_below_znear.gltf", "zfar 0.5: must be greater than znear 1")(
    with_camera({"type": "perspective", "perspective": {"yfov": 0.8, "znear": 1.0, "zfar": 0.5}}))
case("camera_orthographic_zero_xmag.gltf", "xmag and ymag")(
    with_camera({"type": "orthographic", "orthographic": {"xmag": 0.0, "ymag": 1.0, "znear": 0.0, "zfar": 10.0}}))


def with_light(light):
    def build():
        g = scene()
        g["extensionsUsed"] = ["KHR_lights_punctual"]
        g["extensions"] = {"KHR_lights_punctual": {"lights": [light]}}
        g["nodes"].append({"extensions": {"KHR_lights_punctual": {"light": 0}}, "translation": [0.0, 0.0, 2.0]})
        g["scenes"][0]["nodes"].append(1)
        return to_json(g)
    return build


case("light_negative_intensity.gltf", "lights[0].intensity -1")(
    with_light({"type": "point", "intensity": -1.0}))
case("light_color_above_one.gltf", "lights[0].color[0] 4")(
    with_light({"type": "point", "color": [4.0, 1.0, 1.0]}))
case("light_negative_range.gltf", "lights[0].range -3: must be positive")(
    with_light({"type": "point", "range": -3.0}))
case("light_spot_inner_above_outer.gltf", "spot.innerConeAngle 0.6: outside [0, outerConeAngle 0.5)")(
    with_light({"type": "spot", "spot": {"innerConeAngle": 0.6, "outerConeAngle": 0.5}}))
case("light_spot_outer_above_half_pi.gltf", "spot.outerConeAngle 2")(
    with_light({"type": "spot", "spot": {"innerConeAngle": 0.1, "outerConeAngle": 2.0}}))


VALID = {
    "quad.gltf": lambda: to_json(scene()),
    "quad_normals.gltf": lambda: to_json(scene(normals=True)),
    "triangle.gltf": lambda: to_json(scene(positions=TRIANGLE_POSITIONS, indices=TRIANGLE_INDICES)),
    "textured.gltf": lambda: to_json(textured({"uri": data_uri(TINY_PNG, "image/png")})),
    "quad.glb": lambda: glb(*glb_scene()),
    "no_scenes.gltf": lambda: no_scenes(),
    "unread_texture_points_nowhere.gltf": lambda: unread_texture_points_nowhere(),
    # Vertex 1 moved to (2, 0, 0) by a sparse part.
    "sparse_accessor.gltf": lambda: to_json(sparse_scene()),
}


def no_scenes():
    """Valid glTF without scenes: the two root nodes (and the child of one) are drawn."""
    g = scene()
    del g["scene"], g["scenes"]
    g["nodes"] = [{"mesh": 0, "children": [2]}, {"mesh": 0, "translation": [2.0, 0.0, 0.0]},
                  {"mesh": 0, "translation": [0.0, 2.0, 0.0]}]
    return to_json(g)


def unread_texture_points_nowhere():
    """A texture whose source points nowhere, used by no material: invalid glTF in a
    part voxgi does not read (scenes/cornell_box has one), so it loads."""
    g = scene()
    g["samplers"] = [{}]
    g["textures"] = [{"source": 0, "sampler": 0}]
    return to_json(g)


def write(path, data):
    with open(path, "wb") as f:
        f.write(data)


def main():
    # Remove outputs of earlier runs so that a renamed case leaves nothing behind.
    for name in os.listdir(HERE):
        if name.endswith((".gltf", ".glb")):
            os.remove(os.path.join(HERE, name))
    os.makedirs(VALID_DIR, exist_ok=True)
    for name in os.listdir(VALID_DIR):
        if name.endswith((".gltf", ".glb")):
            os.remove(os.path.join(VALID_DIR, name))
    lines = []
    for name in sorted(CASES):
        fn, expected = CASES[name]
        assert "\t" not in expected and "\n" not in expected
        write(os.path.join(HERE, name), fn())
        lines.append("%s\t%s\n" % (name, expected))
    write(os.path.join(HERE, "expected.txt"), "".join(lines).encode())
    for name, fn in sorted(VALID.items()):
        write(os.path.join(VALID_DIR, name), fn())
    print("wrote %d malformed files and %d valid ones to %s" % (len(CASES), len(VALID), HERE))


if __name__ == "__main__":
    main()
