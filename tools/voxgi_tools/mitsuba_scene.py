"""A glTF scene as Mitsuba 3 renders it, with voxgi's own material model, for equal-time
races against Mitsuba on the validation set (tools/bench-convergence
--against-mitsuba).

What carries over, as voxgi's path tracer reads the file (docs/pathtracer.md):
- meshes with their normals and first texture coordinates, node transforms baked in;
- materials: metallic 0 + roughness 1 is Lambert (Mitsuba's `diffuse`); metallic 1 +
  roughness 0 a mirror of reflectance = base colour, no Fresnel (`conductor`, material
  "none"); anything else the glTF metallic-roughness BRDF, here a Python BSDF
  (`VoxgiGltfBsdf`): Lambert + GGX, height-correlated Smith, Schlick, the diffuse part
  weighed by 1 - F, sampled by visible normals or cosine as voxgi samples it. Every
  surface is two-sided; a base colour texture is read as sRGB, bilinear, repeating;
- emission (emissiveFactor x KHR_materials_emissive_strength) as an area emitter on
  the front face;
- KHR_lights_punctual: point, spot and directional lights, with the same units.

What does not: a spot light's falloff is Mitsuba's (linear in the angle between the
cones) where voxgi's is the glTF smoothstep in the cosine; a two-sided emitter emits
from its front face only (the validation set's are closed spheres, whose back faces
no ray sees). Other textures (emissive, metallic-roughness, normal maps), vertex
colours and alpha masks are not carried over: `convert` names what it dropped.

Run as a worker (its own process: Dr.Jit's LLVM is chosen before the import):
  python -m voxgi_tools mitsuba render SCENE.gltf --size WxH --spp 16,64 --out-prefix P
      [--look-from x,y,z --look-at x,y,z] [--max-depth D (default 8)] [--seed S]
writes P_<spp>spp.exr for each count and prints one JSON line per render with its
time (a first untimed render at the same count compiles the kernels).
"""
import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

# Debian's LLVM 19: Mitsuba's llvm variants abort with LLVM 15/16 (tools/setup --mitsuba).
LLVM = "/usr/lib/x86_64-linux-gnu/libLLVM-19.so"


def read_gltf(path):
    """(gltf json, accessor(i) -> numpy array [count, comps], world(node) -> 4x4)."""
    import numpy as np
    path = Path(path)
    gltf = json.loads(path.read_text())
    buffers = [np.fromfile(path.parent / b["uri"], dtype=np.uint8) for b in gltf["buffers"]]

    def accessor(i):
        a = gltf["accessors"][i]
        view = gltf["bufferViews"][a["bufferView"]]
        comps = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[a["type"]]
        dtype = {5126: np.float32, 5125: np.uint32, 5123: np.uint16, 5121: np.uint8}[
            a["componentType"]]
        size = comps * np.dtype(dtype).itemsize
        start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
        stride = view.get("byteStride", 0) or size
        raw = buffers[view["buffer"]][start:start + stride * (a["count"] - 1) + size]
        if stride == size:
            return np.frombuffer(raw.tobytes(), dtype=dtype).reshape(a["count"], comps)
        rows = np.lib.stride_tricks.as_strided(raw, (a["count"], size), (stride, 1))
        return np.frombuffer(rows.tobytes(), dtype=dtype).reshape(a["count"], comps)

    def local(node):
        if "matrix" in node:
            return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T
        t = node.get("translation", [0, 0, 0])
        x, y, z, w = node.get("rotation", [0, 0, 0, 1])
        s = node.get("scale", [1, 1, 1])
        r = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                      [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                      [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
        m = np.eye(4)
        m[:3, :3] = r * np.array(s)
        m[:3, 3] = t
        return m

    parents = {c: i for i, n in enumerate(gltf["nodes"]) for c in n.get("children", [])}

    def world(i):
        m = local(gltf["nodes"][i])
        return world(parents[i]) @ m if i in parents else m

    return gltf, accessor, world


def register_bsdf(mi, dr):
    """Registers "voxgi_gltf": voxgi's glTF metallic-roughness BRDF (brdf_shared.h)."""

    class VoxgiGltfBsdf(mi.BSDF):
        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            base = props["base_color"]  # a texture, or the colour itself when uniform
            if not isinstance(base, mi.Texture):
                base = mi.load_dict({"type": "rgb", "value": [float(base[k]) for k in range(3)]})
            self.base = base
            self.metallic = props["metallic"]
            self.alpha = min(max(props["roughness"] ** 2, 1e-3), 1.0)
            flags = (mi.BSDFFlags.DiffuseReflection | mi.BSDFFlags.GlossyReflection |
                     mi.BSDFFlags.FrontSide | mi.BSDFFlags.BackSide)
            self.m_components = [flags]
            self.m_flags = flags

        def _parts(self, si, active):
            base = self.base.eval(si, active)
            diffuse = base * (1.0 - self.metallic)
            f0 = dr.lerp(mi.Color3f(0.04), base, self.metallic)
            return diffuse, f0

        @staticmethod
        def _lum(c):
            return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]

        def _schlick(self, f0, c):
            return f0 + (1.0 - f0) * dr.power(dr.maximum(1.0 - c, 0.0), 5.0)

        def _chance(self, diffuse, f0, nv):
            ws = self._lum(self._schlick(f0, nv))
            wd = self._lum(diffuse) * (1.0 - ws)
            chance = dr.clip(ws / dr.maximum(ws + wd, 1e-30), 0.1, 1.0)
            return dr.select(wd <= 0.0, 1.0, chance)

        def _side(self, si):
            """wi in the upper hemisphere and the sign that puts it there (two-sided)."""
            flip = mi.Frame3f.cos_theta(si.wi) < 0.0
            sign = dr.select(flip, -1.0, 1.0)
            return si.wi * sign, sign

        def _eval_pdf(self, si, wi, wo, active):
            a = self.alpha
            a2 = a * a
            nv = dr.maximum(mi.Frame3f.cos_theta(wi), 1e-4)
            nl = mi.Frame3f.cos_theta(wo)
            active = active & (nl > 0.0)
            h = dr.normalize(wi + wo)
            nh = dr.maximum(mi.Frame3f.cos_theta(h), 0.0)
            vh = dr.maximum(dr.dot(wi, h), 0.0)
            diffuse, f0 = self._parts(si, active)
            f = self._schlick(f0, vh)
            d = nh * nh * (a2 - 1.0) + 1.0
            ggx = a2 / (dr.pi * d * d)
            s = nl * dr.sqrt(nv * nv * (1.0 - a2) + a2) + nv * dr.sqrt(nl * nl * (1.0 - a2) + a2)
            vis = dr.select(s > 0.0, 0.5 / s, 0.0)
            value = (f * ggx * vis + (1.0 - f) * diffuse * dr.inv_pi) * nl
            g1 = 2.0 * nv / (nv + dr.sqrt(a2 + (1.0 - a2) * nv * nv))
            chance = self._chance(diffuse, f0, nv)
            pdf = chance * g1 * ggx / (4.0 * nv) + (1.0 - chance) * nl * dr.inv_pi
            return dr.select(active, value, 0.0), dr.select(active, pdf, 0.0)

        def sample(self, ctx, si, sample1, sample2, active=True):
            wi, sign = self._side(si)
            nv = dr.maximum(mi.Frame3f.cos_theta(wi), 1e-4)
            diffuse, f0 = self._parts(si, active)
            chance = self._chance(diffuse, f0, nv)
            distr = mi.MicrofacetDistribution(mi.MicrofacetType.GGX, self.alpha, True)
            m, _ = distr.sample(wi, sample2)
            wo_spec = mi.reflect(wi, m)
            wo_diff = mi.warp.square_to_cosine_hemisphere(sample2)
            specular = sample1 < chance
            wo = dr.select(specular, wo_spec, wo_diff)
            value, pdf = self._eval_pdf(si, wi, wo, active)
            bs = mi.BSDFSample3f()
            bs.wo = wo * sign
            bs.pdf = pdf
            bs.eta = 1.0
            bs.sampled_type = dr.select(specular, int(mi.BSDFFlags.GlossyReflection),
                                        int(mi.BSDFFlags.DiffuseReflection))
            bs.sampled_component = 0
            ok = active & (pdf > 0.0) & (mi.Frame3f.cos_theta(wo) > 0.0)
            return bs, dr.select(ok, value / dr.maximum(pdf, 1e-30), 0.0)

        def eval(self, ctx, si, wo, active=True):
            wi, sign = self._side(si)
            return self._eval_pdf(si, wi, wo * sign, active)[0]

        def pdf(self, ctx, si, wo, active=True):
            wi, sign = self._side(si)
            return self._eval_pdf(si, wi, wo * sign, active)[1]

        def eval_pdf(self, ctx, si, wo, active=True):
            wi, sign = self._side(si)
            return self._eval_pdf(si, wi, wo * sign, active)

        def traverse(self, callback):
            pass

        def to_string(self):
            return f"VoxgiGltfBsdf[metallic={self.metallic}, alpha={self.alpha}]"

    mi.register_bsdf("voxgi_gltf", lambda props: VoxgiGltfBsdf(props))


def write_ply(path, pos, normals, uvs, idx):
    import numpy as np
    n = len(pos)
    props = "property float x\nproperty float y\nproperty float z\n"
    cols = [pos.astype(np.float32)]
    if normals is not None:
        props += "property float nx\nproperty float ny\nproperty float nz\n"
        cols.append(normals.astype(np.float32))
    if uvs is not None:
        props += "property float u\nproperty float v\n"
        cols.append(uvs.astype(np.float32))
    with open(path, "wb") as f:
        f.write((f"ply\nformat binary_little_endian 1.0\nelement vertex {n}\n{props}"
                 f"element face {len(idx)}\nproperty list uchar int vertex_indices\n"
                 "end_header\n").encode())
        f.write(np.ascontiguousarray(np.hstack(cols)).tobytes())
        faces = np.empty(len(idx), dtype=[("n", "u1"), ("v", "<i4", 3)])
        faces["n"] = 3
        faces["v"] = idx
        f.write(faces.tobytes())


def area_emitter(mat):
    """The glTF material's emission (emissiveFactor x KHR_materials_emissive_strength)
    as a Mitsuba area emitter, or None."""
    import numpy as np
    emission = np.array(mat.get("emissiveFactor", [0, 0, 0])) * mat.get(
        "extensions", {}).get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0)
    if not emission.max() > 0:
        return None
    return {"type": "area", "radiance": {"type": "rgb", "value": emission.tolist()}}


def convert(mi, scene_path, width, height, ply_dir, look_from=None, look_at=None,
            max_depth=8, rr_depth=5):
    """(Mitsuba scene dict, [what was not carried over])."""
    import numpy as np
    path = Path(scene_path)
    gltf, accessor, world = read_gltf(path)
    dropped = set()
    lights = gltf.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
    scene = {"type": "scene",
             "integrator": {"type": "path", "max_depth": max_depth, "rr_depth": rr_depth}}

    def sensor(origin, target, up, yfov):
        return {"type": "perspective", "fov_axis": "y", "fov": float(np.degrees(yfov)),
                "to_world": mi.ScalarTransform4f().look_at(origin=list(origin),
                                                           target=list(target), up=list(up)),
                "film": {"type": "hdrfilm", "width": width, "height": height,
                         "rfilter": {"type": "box"}},
                "sampler": {"type": "independent", "sample_count": 1}}

    def texture(info, factor):
        if info is None:
            return {"type": "rgb", "value": factor}
        image = gltf["images"][gltf["textures"][info["index"]]["source"]]
        if info.get("texCoord", 0) != 0:
            dropped.add("texture coordinates other than the first")
        tex = {"type": "bitmap", "filename": str(path.parent / image["uri"]), "raw": False,
               "filter_type": "bilinear", "wrap_mode": "repeat"}
        if any(abs(c - 1.0) > 1e-6 for c in factor):
            dropped.add("base colour factors on textures (taken as 1)")
        return tex

    def bsdf(mat):
        pbr = mat.get("pbrMetallicRoughness", {})
        base = list(pbr.get("baseColorFactor", [1, 1, 1, 1]))[:3]
        metallic = float(pbr.get("metallicFactor", 1.0))
        roughness = float(pbr.get("roughnessFactor", 1.0))
        for key in ("normalTexture", "occlusionTexture", "emissiveTexture"):
            if key in mat:
                dropped.add(key)
        if "metallicRoughnessTexture" in pbr:
            dropped.add("metallicRoughnessTexture")
        if mat.get("alphaMode", "OPAQUE") != "OPAQUE":
            dropped.add("alpha modes")
        colour = texture(pbr.get("baseColorTexture"), base)
        if metallic <= 0.0 and roughness >= 1.0:
            inner = {"type": "diffuse", "reflectance": colour}
        elif metallic >= 1.0 and roughness <= 0.0:
            inner = {"type": "conductor", "material": "none", "specular_reflectance": colour}
        else:
            return {"type": "voxgi_gltf", "base_color": colour, "metallic": metallic,
                    "roughness": roughness}
        return {"type": "twosided", "bsdf": inner}

    count = 0
    for i, node in enumerate(gltf["nodes"]):
        m = world(i)
        if "camera" in node and "sensor" not in scene:
            cam = gltf["cameras"][node["camera"]]["perspective"]
            origin, target, up = m @ [0, 0, 0, 1], m @ [0, 0, -1, 1], m @ [0, 1, 0, 0]
            if look_from is not None:
                origin, target, up = list(look_from) + [1], list(look_at) + [1], [0, 1, 0, 0]
            scene["sensor"] = sensor(origin[:3], target[:3], up[:3], cam["yfov"])
        light = node.get("extensions", {}).get("KHR_lights_punctual")
        if light is not None:
            l = lights[light["light"]]
            if l.get("range"):
                dropped.add("light ranges")
            rgb = {"type": "rgb",
                   "value": (np.array(l.get("color", [1, 1, 1])) * l.get("intensity", 1.0)).tolist()}
            p = (m @ [0, 0, 0, 1])[:3]
            d = (m @ [0, 0, -1, 0])[:3]
            if l["type"] == "directional":
                scene[f"light{i}"] = {"type": "directional", "direction": d.tolist(),
                                      "irradiance": rgb}
            elif l["type"] == "spot":
                spot = l.get("spot", {})
                up = [0, 1, 0] if abs(d[1]) < 0.99 * np.linalg.norm(d) else [1, 0, 0]
                scene[f"light{i}"] = {
                    "type": "spot", "intensity": rgb,
                    "cutoff_angle": float(np.degrees(spot.get("outerConeAngle", np.pi / 4))),
                    "beam_width": float(np.degrees(spot.get("innerConeAngle", 0.0))),
                    "to_world": mi.ScalarTransform4f().look_at(origin=p.tolist(),
                                                               target=(p + d).tolist(), up=up)}
            else:
                scene[f"light{i}"] = {"type": "point", "position": p.tolist(), "intensity": rgb}
        if "mesh" not in node:
            continue
        normal_matrix = np.linalg.inv(m[:3, :3]).T
        for prim in gltf["meshes"][node["mesh"]]["primitives"]:
            attrs = prim["attributes"]
            pos = accessor(attrs["POSITION"]).astype(np.float64) @ m[:3, :3].T + m[:3, 3]
            normals = None
            if "NORMAL" in attrs:
                normals = accessor(attrs["NORMAL"]).astype(np.float64) @ normal_matrix.T
                normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-30)
            uvs = accessor(attrs["TEXCOORD_0"]) if "TEXCOORD_0" in attrs else None
            for key in ("COLOR_0", "TANGENT"):
                if key in attrs:
                    dropped.add(key)
            idx = (accessor(prim["indices"]).reshape(-1, 3) if "indices" in prim else
                   np.arange(len(pos)).reshape(-1, 3)).astype(np.int32)
            if np.linalg.det(m[:3, :3]) < 0:
                idx = idx[:, ::-1]
            ply = Path(ply_dir) / f"m{count}.ply"
            write_ply(ply, pos, normals, uvs, idx)
            mat = gltf["materials"][prim["material"]] if "material" in prim else {}
            # The PLY loader flips v (its origin bottom left), as glTF's is top left.
            shape = {"type": "ply", "filename": str(ply), "bsdf": bsdf(mat)}
            emitter = area_emitter(mat)
            if emitter is not None:
                shape["emitter"] = emitter
            scene[f"shape{count}"] = shape
            count += 1
    if "sensor" not in scene:
        raise SystemExit(f"mitsuba_scene: {scene_path}: no camera")
    return scene, sorted(dropped)


def render_worker(argv):
    ap = argparse.ArgumentParser(prog="voxgi_tools mitsuba render")
    ap.add_argument("scene")
    ap.add_argument("--size", default="256x256")
    ap.add_argument("--spp", default="16,64")
    ap.add_argument("--out-prefix", required=True)
    ap.add_argument("--look-from")
    ap.add_argument("--look-at")
    ap.add_argument("--max-depth", type=int, default=8)
    ap.add_argument("--seed", type=int, default=7)
    a = ap.parse_args(argv)
    os.environ.setdefault("DRJIT_LIBLLVM_PATH", LLVM)
    import drjit as dr
    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")
    register_bsdf(mi, dr)
    width, height = (int(v) for v in a.size.split("x"))
    vec = (lambda s: [float(v) for v in s.split(",")]) if a.look_from else (lambda s: None)
    with tempfile.TemporaryDirectory(prefix="mitsuba-scene-") as ply_dir:
        t0 = time.perf_counter()
        try:
            d, dropped = convert(mi, a.scene, width, height, ply_dir, vec(a.look_from),
                                 vec(a.look_at) if a.look_at else None, a.max_depth)
        except (OSError, ValueError, KeyError, IndexError) as e:
            raise SystemExit(f"mitsuba_scene: {a.scene}: cannot convert ({type(e).__name__}: {e})")
        scene = mi.load_dict(d)
        load_s = time.perf_counter() - t0
        for spp in (int(s) for s in a.spp.split(",")):
            # The first render compiles the kernels; Dr.Jit's LLVM backend runs them
            # on its own threads, so each render is timed to the end of its work.
            t0 = time.perf_counter()
            image = mi.render(scene, spp=spp, seed=a.seed + 1000)
            dr.eval(image)
            dr.sync_thread()
            first_s = time.perf_counter() - t0
            t0 = time.perf_counter()
            image = mi.render(scene, spp=spp, seed=a.seed)
            dr.eval(image)
            dr.sync_thread()
            ms = (time.perf_counter() - t0) * 1000.0
            out = f"{a.out_prefix}_{spp}spp.exr"
            mi.util.write_bitmap(out, image, write_async=False)
            print(json.dumps({"spp": spp, "ms": ms, "first_render_ms": first_s * 1000.0,
                              "load_ms": load_s * 1000.0, "exr": out, "dropped": dropped}),
                  flush=True)


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if not argv or argv[0] != "render":
        print(__doc__)
        return 0 if argv and argv[0] in ("-h", "--help") else 2
    render_worker(argv[1:])
    return 0


if __name__ == "__main__":
    sys.exit(main())
