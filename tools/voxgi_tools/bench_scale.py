"""Start-up, memory and frame cost against triangle count, side by side with Mitsuba 3.

For each triangle count N (--triangles), tools/make-hall writes the day hall
with its knot tessellated to N triangles (a scale scene: nearly the same image at
any N) into OUT/scenes/. Then, RUNS times, interleaved so that every renderer sees
the same machine load:

  rtgi       `voxgi render --frames 1`: wall clock from the command to the
             written image, load, start-up and BVH build (its --stats), the frame,
             and the peak RSS (/usr/bin/time);
  pathtrace  `voxgi render --mode pathtrace --spp 1`: the same, for the path
             tracer on its default device;
  mitsuba    (--against-mitsuba) a Python process that reads the glTF with numpy,
             writes one PLY per primitive, loads them into Mitsuba 3 (llvm_ad_rgb;
             diffuse base colours, emitters, punctual lights) and renders 1 spp at
             the same size: wall clock from the command to the written image, and
             its peak RSS; with transparent huge pages off, as voxgi starts.

Each renderer first runs once untimed at each size (see main). Medians are
printed as a table and written to OUT/results.json, and drawn in OUT/scale.png. The ratios the
targets name (first image and peak RSS against Mitsuba's, the frame's growth from
the smallest N) are computed from the medians of the same run.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import voxgi_tools
from voxgi_tools import mitsuba_scene  # read_gltf, LLVM

ROOT = Path(voxgi_tools.ROOT)

LLVM = mitsuba_scene.LLVM


def parse_args(argv):
    p = argparse.ArgumentParser(
        prog="tools/bench-scale",
        description="Start-up, peak memory and frame time of voxgi against triangle count, "
                    "optionally against Mitsuba 3 in the same run.")
    p.add_argument("--triangles", default="56000,740000,2440000",
                   help="comma-separated triangle counts (>= 10000; default 56000,740000,2440000)")
    p.add_argument("--size", default="256x256", help="image size (default 256x256)")
    p.add_argument("--runs", type=int, default=3, help="runs per renderer and size (median)")
    p.add_argument("--modes", default="rtgi,pathtrace",
                   help="voxgi modes to run: rtgi, pathtrace or both (default both)")
    p.add_argument("--against-mitsuba", action="store_true",
                   help="also time Mitsuba 3 to its first image (tools/setup --mitsuba)")
    p.add_argument("--voxgi", default=str(ROOT / "build" / "voxgi"), help="the voxgi binary")
    p.add_argument("--out", default=str(ROOT / "out" / "bench-scale"))
    p.add_argument("--replot", action="store_true",
                   help="only print the table and redraw OUT/scale.png from OUT/results.json")
    p.add_argument("--mitsuba-worker", nargs=3, metavar=("SCENE", "SIZE", "OUT"),
                   help=argparse.SUPPRESS)
    return p.parse_args(argv)


def timed(cmd, env=None):
    """Runs cmd under /usr/bin/time; returns (wall s, peak RSS MB, stdout)."""
    with tempfile.NamedTemporaryFile("r", suffix=".time") as t:
        start = time.perf_counter()
        r = subprocess.run(["/usr/bin/time", "-o", t.name, "-f", "%M"] + cmd,
                           capture_output=True, text=True, env=env)
        wall = time.perf_counter() - start
        if r.returncode != 0:
            raise SystemExit(f"bench-scale: {' '.join(cmd)} failed:\n{r.stderr.strip()}")
        rss_kb = int(t.read().strip().splitlines()[-1])
    return wall, rss_kb / 1024.0, r.stdout


def make_scene(n, out):
    scene = out / "scenes" / f"hall_{n}.gltf"
    if not scene.exists():
        subprocess.run([sys.executable, "-m", "voxgi_tools", "make-hall", "--triangles",
                        str(n), "--out", str(scene.parent)], check=True,
                       stdout=subprocess.DEVNULL)
    return scene


def run_voxgi(args, scene, mode, out):
    stats = out / f"{scene.stem}_{mode}.json"
    image = out / f"{scene.stem}_{mode}.png"
    cmd = [args.voxgi, "render", str(scene), "--size", args.size, "--frames", "1", "--quiet",
           "--stats", str(stats), "--out", str(image)]
    if mode == "pathtrace":
        cmd += ["--mode", "pathtrace", "--spp", "1"]
    wall, rss, _ = timed(cmd)
    s = json.loads(stats.read_text())
    return {"wall_s": wall, "peak_rss_mb": rss, "load_ms": s["load_ms"],
            "startup_ms": s["startup_ms"], "bvh_ms": s.get("startup_stages", {}).get("bvh", 0.0),
            "bvh_tree_ms": s.get("bvh_tree_ms", 0.0), "frame_ms": s["frame_ms"],
            "triangles": s["triangles"]}


def run_mitsuba(args, scene, out):
    env = dict(os.environ)
    env["DRJIT_LIBLLVM_PATH"] = LLVM
    image = out / f"{scene.stem}_mitsuba.exr"
    wall, rss, _ = timed([sys.executable, "-m", "voxgi_tools", "bench", "scale", "--mitsuba-worker", str(scene), args.size,
                          str(image)], env=env)
    return {"wall_s": wall, "peak_rss_mb": rss}


# --- the Mitsuba side: glTF -> PLY -> one image ------------------------------------
def mitsuba_worker(scene_path, size, out):
    # Transparent huge pages off, as voxgi has them until its first frame: where the
    # kernel has no free 2 MiB page at hand it compacts memory at each first touch,
    # and Mitsuba's time to its image drifted 2x within one run with it (1.2-3.0 s,
    # its system time 0.2-2.4 s), whatever it rendered.
    if sys.platform.startswith("linux"):
        import ctypes
        ctypes.CDLL(None, use_errno=True).prctl(41, 1, 0, 0, 0)  # PR_SET_THP_DISABLE
    import numpy as np
    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")
    width, height = (int(v) for v in size.split("x"))
    gltf, accessor, world = mitsuba_scene.read_gltf(scene_path)
    lights = gltf.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
    scene = {"type": "scene", "integrator": {"type": "path", "max_depth": 8}}
    ply_dir = Path(tempfile.mkdtemp(prefix="bench-scale-"))
    count = 0
    for i, node in enumerate(gltf["nodes"]):
        m = world(i)
        if "camera" in node and "sensor" not in scene:
            cam = gltf["cameras"][node["camera"]]["perspective"]
            origin, target = m @ [0, 0, 0, 1], m @ [0, 0, -1, 1]
            up = m @ [0, 1, 0, 0]
            scene["sensor"] = {
                "type": "perspective", "fov_axis": "y", "fov": float(np.degrees(cam["yfov"])),
                "to_world": mi.ScalarTransform4f().look_at(origin=origin[:3].tolist(),
                                                           target=target[:3].tolist(),
                                                           up=up[:3].tolist()),
                "film": {"type": "hdrfilm", "width": width, "height": height},
                "sampler": {"type": "independent", "sample_count": 1}}
        light = node.get("extensions", {}).get("KHR_lights_punctual")
        if light is not None:
            l = lights[light["light"]]
            colour = np.array(l.get("color", [1, 1, 1])) * l.get("intensity", 1.0)
            rgb = {"type": "rgb", "value": colour.tolist()}
            p = (m @ [0, 0, 0, 1])[:3].tolist()
            d = (m @ [0, 0, -1, 0])[:3].tolist()
            if l["type"] == "directional":
                scene[f"light{i}"] = {"type": "directional", "direction": d, "irradiance": rgb}
            elif l["type"] == "spot":
                spot = l.get("spot", {})
                scene[f"light{i}"] = {
                    "type": "spot", "intensity": rgb,
                    "cutoff_angle": float(np.degrees(spot.get("outerConeAngle", np.pi / 4))),
                    "beam_width": float(np.degrees(spot.get("innerConeAngle", 0.0))),
                    "to_world": mi.ScalarTransform4f().look_at(
                        origin=p, target=(np.array(p) + d).tolist(), up=[0, 1, 0.001])}
            else:
                scene[f"light{i}"] = {"type": "point", "position": p, "intensity": rgb}
        if "mesh" not in node:
            continue
        for prim in gltf["meshes"][node["mesh"]]["primitives"]:
            pos = accessor(prim["attributes"]["POSITION"]).astype(np.float64)
            pos = (pos @ m[:3, :3].T + m[:3, 3]).astype(np.float32)
            idx = accessor(prim["indices"]).reshape(-1, 3).astype(np.uint32)
            ply = ply_dir / f"m{count}.ply"
            mitsuba_scene.write_ply(ply, pos, None, None, idx)
            mat = gltf["materials"][prim.get("material", 0)] if "materials" in gltf else {}
            base = mat.get("pbrMetallicRoughness", {}).get("baseColorFactor", [0.8, 0.8, 0.8, 1])
            shape = {"type": "ply", "filename": str(ply),
                     "bsdf": {"type": "twosided",
                              "bsdf": {"type": "diffuse",
                                       "reflectance": {"type": "rgb", "value": base[:3]}}}}
            emitter = mitsuba_scene.area_emitter(mat)
            if emitter is not None:
                shape["emitter"] = emitter
            scene[f"shape{count}"] = shape
            count += 1
    image = mi.render(mi.load_dict(scene))
    mi.util.write_bitmap(out, image, write_async=False)
    for f in ply_dir.iterdir():
        f.unlink()
    ply_dir.rmdir()


def median_row(rows):
    return {k: statistics.median(r[k] for r in rows) for k in rows[0]}


def report(summary):
    results, modes, runs = summary["rows"], summary["modes"], summary["runs"]
    mitsuba = summary["mitsuba"]
    size = summary["size"]

    print(f"medians of {runs} runs, {size}; wall: command to written image")
    head = "| triangles |"
    rule = "|---:|"
    if "rtgi" in modes:
        head += (" load ms | start-up ms | BVH ms | BVH tree M tri/s | rtgi frame ms | rtgi wall s |"
                 " rtgi peak RSS MB |")
        rule += "---:|---:|---:|---:|---:|---:|---:|"
    if "pathtrace" in modes:
        head += " pathtrace wall s | pathtrace peak RSS MB |"
        rule += "---:|---:|"
    if mitsuba:
        head += " Mitsuba wall s | Mitsuba peak RSS MB |"
        rule += "---:|---:|"
    print(head)
    print(rule)
    for row in results:
        line = f"| {row[modes[0]]['triangles'] if modes else row['triangles_asked']:,} |"
        if "rtgi" in modes:
            g = row["rtgi"]
            tree = g.get("bvh_tree_ms", 0.0)
            rate = f"{g['triangles'] / tree / 1e3:.1f}" if tree > 0 else "-"
            line += (f" {g['load_ms']:,.0f} | {g['startup_ms']:,.0f} | {g['bvh_ms']:,.0f} | {rate} |"
                     f" {g['frame_ms']:,.0f} | {g['wall_s']:.2f} | {g['peak_rss_mb']:,.0f} |")
        if "pathtrace" in modes:
            p = row["pathtrace"]
            line += f" {p['wall_s']:.2f} | {p['peak_rss_mb']:,.0f} |"
        if mitsuba:
            mi_row = row["mitsuba"]
            line += f" {mi_row['wall_s']:.2f} | {mi_row['peak_rss_mb']:,.0f} |"
        print(line)
    if "rtgi" in modes:
        for row in results[1:]:
            growth = row["rtgi"]["frame_ms"] / results[0]["rtgi"]["frame_ms"]
            print(f"rtgi frame growth, {results[0]['rtgi']['triangles']:,} -> "
                  f"{row['rtgi']['triangles']:,} triangles: {growth:.2f}x")
    if mitsuba and "rtgi" in modes:
        for row in results:
            print(f"{row['rtgi']['triangles']:,} triangles: first rtgi image "
                  f"{row['rtgi']['wall_s'] / row['mitsuba']['wall_s']:.2f}x Mitsuba's, peak RSS "
                  f"{row['rtgi']['peak_rss_mb'] / row['mitsuba']['peak_rss_mb']:.2f}x")


def plot(summary, path):
    """First image and peak memory against triangle count, log-log."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("bench-scale: no matplotlib: no plot", file=sys.stderr)
        return
    rows = summary["rows"]
    tris = [r[summary["modes"][0]]["triangles"] if summary["modes"] else r["triangles_asked"]
            for r in rows]
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
    series = [(m, m) for m in summary["modes"]]
    if summary["mitsuba"]:
        series.append(("mitsuba", "Mitsuba 3"))
    for key, label in series:
        a.plot(tris, [r[key]["wall_s"] for r in rows], "o-", label=label)
        b.plot(tris, [r[key]["peak_rss_mb"] for r in rows], "o-", label=label)
    for ax, title in ((a, "command to first image (s)"), (b, "peak resident memory (MB)")):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("triangles")
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.suptitle(f"scale halls at {summary['size']}, medians of {summary['runs']} runs")
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    print(f"wrote {path}")


def main(argv=None):
    args = parse_args(argv)
    if args.mitsuba_worker:
        mitsuba_worker(*args.mitsuba_worker)
        return 0
    if args.replot:
        results_path = Path(args.out) / "results.json"
        if not results_path.exists():
            raise SystemExit(f"bench-scale: {results_path}: no such file (run the benchmark first)")
        summary = json.loads(results_path.read_text())
        report(summary)
        plot(summary, Path(args.out) / "scale.png")
        return 0
    if not Path(args.voxgi).exists():
        raise SystemExit(f"bench-scale: {args.voxgi}: no such binary (build first: tools/build)")
    counts = [int(v) for v in args.triangles.split(",")]
    if any(n < 10000 for n in counts):
        raise SystemExit("bench-scale: --triangles: each count must be >= 10000")
    modes = [m for m in args.modes.split(",") if m]
    for m in modes:
        if m not in ("rtgi", "pathtrace"):
            raise SystemExit(f"bench-scale: --modes: unknown mode '{m}'")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if args.against_mitsuba:
        check = subprocess.run([sys.executable, "-c", "import mitsuba"], capture_output=True)
        if check.returncode != 0:
            raise SystemExit("bench-scale: Mitsuba 3 is not installed (tools/setup --mitsuba)")
    results = []
    for n in counts:
        scene = make_scene(n, out)
        runs = {m: [] for m in modes + (["mitsuba"] if args.against_mitsuba else [])}
        # One untimed run of each first: the first touch of fresh memory costs up to
        # 3x more on a machine that has not just run the same (page zeroing; seen on
        # this virtual machine: 12.8 s against 4.2 s for the same render), and
        # Mitsuba's JIT fills its kernel cache.
        for m in modes:
            run_voxgi(args, scene, m, out)
        if args.against_mitsuba:
            run_mitsuba(args, scene, out)
        for r in range(args.runs):
            for m in modes:
                runs[m].append(run_voxgi(args, scene, m, out))
            if args.against_mitsuba:
                runs["mitsuba"].append(run_mitsuba(args, scene, out))
            print(f"bench-scale: {scene.name} run {r + 1}/{args.runs} done", file=sys.stderr,
                  flush=True)
        row = {"triangles_asked": n, "runs": args.runs}
        for m, rs in runs.items():
            row[m] = median_row(rs)
            row[m + "_all"] = rs
        results.append(row)
    summary = {"size": args.size, "runs": args.runs, "modes": modes,
               "mitsuba": args.against_mitsuba, "rows": results}
    (out / "results.json").write_text(json.dumps(summary, indent=1))
    report(summary)
    plot(summary, out / "scale.png")
    print(f"wrote {out / 'results.json'}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
