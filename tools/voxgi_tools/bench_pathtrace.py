"""Path tracer throughput, per device, and side by side with Mitsuba 3 in one run.

For each scene: voxgi's path tracer renders SIZE at SPP samples per pixel on each
device asked for (--devices, default cpu,gl), RUNS times, and reports the median
samples per second of the frame (start-up excluded: the BVH, the kernel's JIT).
With --against-mitsuba the same scene, converted to a Mitsuba 3 scene (see
mitsuba_scene below), is rendered by Mitsuba's llvm_ad_rgb variant at the same
size and spp, interleaved with voxgi's runs so that both see the same machine
load; the timed Mitsuba renders follow one untimed warm-up render (its JIT).
Both images are scored against the scene's reference (voxgi_tools.reference:
tests/data/reference/ or out/reference/, the highest spp) with FLIP, so the ratio is
read at an equal error. Results go to out/bench-pathtrace/results.json.
"""

import argparse
import json
import math
import os
import statistics
import struct
import subprocess
import sys
import time
from pathlib import Path

import voxgi_tools
from voxgi_tools import metrics
from voxgi_tools import reference as refs

ROOT = Path(voxgi_tools.ROOT)
LLVM = "/usr/lib/x86_64-linux-gnu/libLLVM-19.so"


def parse_args(argv):
    p = argparse.ArgumentParser(
        prog="tools/bench-pathtrace",
        description="Path tracer throughput per device, optionally against Mitsuba 3.")
    p.add_argument("--scenes", default="cornell_room,dark_plane",
                   help="comma-separated names under scenes/ (default cornell_room,dark_plane)")
    p.add_argument("--size", default="256x256")
    p.add_argument("--spp", type=int, default=64)
    p.add_argument("--runs", type=int, default=3, help="timed renders per renderer (median)")
    p.add_argument("--devices", default="cpu,gl", help="voxgi devices: cpu, gl or both")
    p.add_argument("--gl-runs", type=int, default=1,
                   help="timed renders on the gl device (slow on llvmpipe; default 1)")
    p.add_argument("--against-mitsuba", action="store_true",
                   help="also render with Mitsuba 3 (llvm_ad_rgb) and print the ratio")
    p.add_argument("--reference-dir",
                   help="where the references are (default: tests/data/reference and out/reference)")
    p.add_argument("--out", default=str(ROOT / "out" / "bench-pathtrace"))
    return p.parse_args(argv)


# --- glTF (the subset the reference scenes use) --------------------------------------
def quat_matrix(q):
    x, y, z, w = q
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w), 0],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w), 0],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y), 0],
            [0, 0, 0, 1]]


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def node_matrix(node):
    if "matrix" in node:
        m = node["matrix"]  # column-major
        return [[m[c * 4 + r] for c in range(4)] for r in range(4)]
    t = node.get("translation", [0, 0, 0])
    r = node.get("rotation", [0, 0, 0, 1])
    s = node.get("scale", [1, 1, 1])
    tm = [[1, 0, 0, t[0]], [0, 1, 0, t[1]], [0, 0, 1, t[2]], [0, 0, 0, 1]]
    sm = [[s[0], 0, 0, 0], [0, s[1], 0, 0], [0, 0, s[2], 0], [0, 0, 0, 1]]
    return matmul(matmul(tm, quat_matrix(r)), sm)


def apply(m, v, w=1.0):
    return [sum(m[i][k] * (v[k] if k < 3 else w) for k in range(4)) for i in range(3)]


def read_accessor(gltf, buffers, index):
    a = gltf["accessors"][index]
    view = gltf["bufferViews"][a["bufferView"]]
    data = buffers[view["buffer"]]
    comps = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[a["type"]]
    fmt = {5126: "f", 5125: "I", 5123: "H", 5121: "B"}[a["componentType"]]
    size = struct.calcsize(fmt)
    stride = view.get("byteStride", size * comps)
    base = view.get("byteOffset", 0) + a.get("byteOffset", 0)
    return [struct.unpack_from("<" + fmt * comps, data, base + i * stride)
            for i in range(a["count"])]


def mitsuba_scene(mi, path, width, height, spp, ply_dir):
    """The glTF scene as a Mitsuba dict: Lambert -> diffuse, perfect mirror ->
    conductor 'none' (reflectance = base colour, no Fresnel), both two-sided as voxgi
    shades the side a ray arrives from; emissive -> area emitter on the front face.
    Anything else is refused (this converter serves the benchmark scenes)."""
    import numpy as np
    gltf = json.loads(Path(path).read_text())
    buffers = [(Path(path).parent / b["uri"]).read_bytes() for b in gltf["buffers"]]
    scene = {"type": "scene",
             "integrator": {"type": "path", "max_depth": 8, "rr_depth": 5, "hide_emitters": False}}
    parents = {}
    for i, n in enumerate(gltf["nodes"]):
        for c in n.get("children", []):
            parents[c] = i

    def world(i):
        m = node_matrix(gltf["nodes"][i])
        return matmul(world(parents[i]), m) if i in parents else m

    camera = None
    for i, node in enumerate(gltf["nodes"]):
        m = world(i)
        if "camera" in node and camera is None:
            cam = gltf["cameras"][node["camera"]]["perspective"]
            origin = apply(m, [0, 0, 0])
            target = apply(m, [0, 0, -1])
            up = apply(m, [0, 1, 0], 0.0)
            camera = {"type": "perspective", "fov_axis": "y",
                      "fov": math.degrees(cam["yfov"]),
                      "to_world": mi.ScalarTransform4f().look_at(origin=origin, target=target,
                                                                 up=up),
                      "film": {"type": "hdrfilm", "width": width, "height": height,
                               "rfilter": {"type": "box"}, "pixel_format": "rgb"},
                      "sampler": {"type": "independent", "sample_count": spp}}
        if "mesh" not in node:
            continue
        for k, prim in enumerate(gltf["meshes"][node["mesh"]]["primitives"]):
            pos = [apply(m, p) for p in read_accessor(gltf, buffers, prim["attributes"]["POSITION"])]
            idx = [i[0] for i in read_accessor(gltf, buffers, prim["indices"])]
            mat = gltf["materials"][prim.get("material", 0)]
            pbr = mat.get("pbrMetallicRoughness", {})
            base = pbr.get("baseColorFactor", [1, 1, 1, 1])[:3]
            metallic = pbr.get("metallicFactor", 1.0)
            roughness = pbr.get("roughnessFactor", 1.0)
            strength = mat.get("extensions", {}).get(
                "KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0)
            emission = [e * strength for e in mat.get("emissiveFactor", [0, 0, 0])]
            mesh = mi.Mesh(f"n{i}p{k}", len(pos), len(idx) // 3, has_vertex_normals=False)
            params = mi.traverse(mesh)
            params["vertex_positions"] = np.array(pos, dtype=np.float32).ravel()
            params["faces"] = np.array(idx, dtype=np.uint32)
            params.update()
            if any(e > 0 for e in emission):
                if any(b > 0 for b in base):
                    raise SystemExit(f"{path}: emissive material with a base colour: not converted")
                bsdf = {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0, 0, 0]}}
                emitter = {"type": "area", "radiance": {"type": "rgb", "value": emission}}
            elif metallic <= 0 and roughness >= 1:
                bsdf = {"type": "twosided", "bsdf": {
                    "type": "diffuse", "reflectance": {"type": "rgb", "value": base}}}
                emitter = None
            elif metallic >= 1 and roughness <= 0:
                bsdf = {"type": "twosided", "bsdf": {
                    "type": "conductor", "material": "none",
                    "specular_reflectance": {"type": "rgb", "value": base}}}
                emitter = None
            else:
                raise SystemExit(f"{path}: material '{mat.get('name')}' is neither Lambert nor a "
                                 "perfect mirror: the Mitsuba converter does not take it")
            ply = ply_dir / f"{Path(path).stem}_n{i}p{k}.ply"
            mesh.write_ply(str(ply))
            shape = {"type": "ply", "filename": str(ply), "face_normals": True, "bsdf": bsdf}
            if emitter:
                shape["emitter"] = emitter
            scene[f"n{i}p{k}"] = shape
    if camera is None:
        raise SystemExit(f"{path}: no camera node")
    scene["sensor"] = camera
    return mi.load_dict(scene)


# --- runs -----------------------------------------------------------------------------
def flip(test, ref):
    """FLIP of test against the reference, or None without one."""
    if ref is None:
        return None
    return metrics.flip(str(test), ref[1])


def voxgi_run(scene, device, size, spp, out_dir):
    stats = out_dir / f"{scene.stem}_{device}.json"
    image = out_dir / f"{scene.stem}_{device}.exr"
    subprocess.run([str(ROOT / "build" / "voxgi"), "render", str(scene), "--mode", "pathtrace",
                    "--pt-device", device, "--size", size, "--spp", str(spp), "--no-progress",
                    "--stats", str(stats), "--out", str(image), "-q"], check=True)
    s = json.loads(stats.read_text())
    return s["samples_per_second"], image, s


def main(argv=None):
    args = parse_args(argv)
    width, height = (int(x) for x in args.size.split("x"))
    out_dir = Path(args.out)
    out_dir.mkdir(parents=True, exist_ok=True)
    devices = [d for d in args.devices.split(",") if d]
    mi = None
    if args.against_mitsuba:
        os.environ.setdefault("DRJIT_LIBLLVM_PATH", LLVM)
        try:
            import mitsuba as mi
            mi.set_variant("llvm_ad_rgb")
        except Exception as e:  # noqa: any import or variant failure reads the same
            raise SystemExit(f"bench-pathtrace: Mitsuba 3 llvm_ad_rgb unavailable ({e}); run "
                             "tools/setup --mitsuba") from e
    results = []
    for name in [s for s in args.scenes.split(",") if s]:
        scene = ROOT / "scenes" / name / f"{name}.gltf"
        if not scene.exists():
            raise SystemExit(f"bench-pathtrace: {scene}: no such scene")
        folders = [args.reference_dir] if args.reference_dir else [refs.COMMITTED, refs.MADE]
        ref = refs.find(name, args.size, folders)
        row = {"scene": name, "size": args.size, "spp": args.spp,
               "reference": ref[0] if ref else None}
        rates = {d: [] for d in devices}
        mi_rates = []
        mi_scene = None
        if mi is not None:
            t0 = time.perf_counter()
            mi_scene = mitsuba_scene(mi, scene, width, height, args.spp, out_dir)
            mi.render(mi_scene, spp=args.spp, seed=0)  # warm-up: the JIT compiles the kernels
            row["mitsuba_startup_s"] = time.perf_counter() - t0
        for run in range(args.runs):
            for d in devices:
                if d == "gl" and run >= args.gl_runs:
                    continue
                rate, image, stats = voxgi_run(scene, d, args.size, args.spp, out_dir)
                rates[d].append(rate)
                row[f"{d}_startup_ms"] = stats["startup_ms"]
                print(f"{name} voxgi {d}: {rate / 1e6:.3f} M samples/s", flush=True)
            if mi_scene is not None:
                t0 = time.perf_counter()
                img = mi.render(mi_scene, spp=args.spp, seed=run + 1)
                import drjit as dr
                dr.eval(img)
                dr.sync_thread()
                dt = time.perf_counter() - t0
                mi_rates.append(width * height * args.spp / dt)
                mi.util.write_bitmap(str(out_dir / f"{name}_mitsuba.exr"), img, write_async=False)
                print(f"{name} mitsuba: {mi_rates[-1] / 1e6:.3f} M samples/s", flush=True)
        for d in devices:
            row[f"{d}_samples_per_second"] = statistics.median(rates[d])
            row[f"{d}_flip"] = flip(out_dir / f"{name}_{d}.exr", ref)
        if mi_rates:
            row["mitsuba_samples_per_second"] = statistics.median(mi_rates)
            row["mitsuba_flip"] = flip(out_dir / f"{name}_mitsuba.exr", ref)
        results.append(row)

    print(f"\n{'scene':<14}{'renderer':<16}{'M samples/s':>12}{'FLIP vs ref':>13}{'ratio':>8}")
    for row in results:
        base = row.get("mitsuba_samples_per_second")
        for who in devices + (["mitsuba"] if base else []):
            rate = row[f"{who}_samples_per_second"]
            f = row.get(f"{who}_flip")
            label = "Mitsuba 3 llvm" if who == "mitsuba" else f"voxgi {who}"
            ratio = f"{rate / base:7.2f}x" if base else ""
            fs = f"{f:13.4f}" if f is not None else f"{'-':>13}"
            print(f"{row['scene']:<14}{label:<16}{rate / 1e6:12.3f}{fs}{ratio:>8}")
    (out_dir / "results.json").write_text(json.dumps(results, indent=2))
    print(f"\nresults: {out_dir / 'results.json'}; load average {os.getloadavg()[0]:.1f} on "
          f"{os.cpu_count()} cores")


if __name__ == "__main__":
    sys.exit(main())
