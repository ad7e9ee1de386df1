"""rtgi's frame and its stages, on whatever machine runs it.

Medians of FRAMES frames after the warm-up; the machine's load is printed: quote
figures from a quiet one.
  1. frame time and stages of the scene (default cornell_room) with 1 diffuse bounce,
     shadows and the mirror, at 256x256, 640x360 and 1280x720;
  2. the cost of each extra bounce at 640x360: 0 bounces drops the indirect stage,
     every bounce past the first adds one voxel gather pass to "inject" (once per
     scene; every frame with --revoxelize);
  3. the octree at 128^3 and 256^3: build and inject ms, nodes, memory against the
     dense grid;
  4. at 640x360: interleaves 4 and 16, the same frame with no ray at all (the stages
     every frame pays), and the first frame after a restart under --target-fps 30,
     traced in full and with --sparse-start (median of 3 runs).
Writes each render's stats under out/bench-rtgi/ and prints the tables.
"""
import argparse
import json
import os
import statistics
import subprocess

from voxgi_tools import ROOT, scene_path, voxgi

STAGES = ["gbuffer", "shadows", "indirect", "specular", "accumulate", "tonemap"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n".join(__doc__.splitlines()[1:]))
    ap.add_argument("frames", nargs="?", type=int, default=11,
                    help="frames a render (default %(default)s)")
    ap.add_argument("scene", nargs="?", default=scene_path("cornell_room"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "bench-rtgi"))
    a = ap.parse_args(argv)
    if not os.path.exists(voxgi()):
        raise SystemExit("bench-rtgi: error: build/voxgi missing (tools/build)")
    os.makedirs(a.out, exist_ok=True)
    print("load: " + " ".join(f"{x:.2f}" for x in os.getloadavg()), flush=True)

    def run(name, *flags, frames=a.frames):
        path = os.path.join(a.out, name + ".json")
        subprocess.run([voxgi(), "render", a.scene, "--mode", "rtgi", "--frames", str(frames),
                        "--stats", path, "-q", *flags], check=True)
        with open(path) as f:
            return json.load(f)

    def stage_row(label, s):
        st = s["stages"]
        if "direct" in st:
            st = dict(st, shadows=st["direct"])
        return (f"| {label} | {s['frame_ms']:.1f} | "
                + " | ".join(f"{st[k]:.1f}" if k in st else "-" for k in STAGES) + " |")

    sizes = {size: run(f"size_{size}", "--size", size, "--bounces", "1")
             for size in ("256x256", "640x360", "1280x720")}
    bounces = {b: run(f"bounces_{b}", "--size", "640x360", "--bounces", str(b)) for b in range(5)}
    voxels = {v: run(f"voxels_{v}", "--size", "640x360", "--bounces", "2", "--voxels", str(v))
              for v in (128, 256)}
    others = {f"interleave_{n}": run(f"interleave_{n}", "--size", "640x360", "--bounces", "1",
                                     "--interleave", str(n)) for n in (4, 16)}
    others["noray"] = run("noray", "--size", "640x360", "--bounces", "1", "--effects",
                          "-shadows,-indirect,-specular")
    restarts = {"full": [], "sparse": []}
    for r in (1, 2, 3):
        for kind in restarts:
            s = run(f"restart_{kind}_{r}", "--size", "640x360", "--target-fps", "30",
                    *(["--sparse-start"] if kind == "sparse" else []), frames=4)
            restarts[kind].append(s["budget"]["frame_ms_each"][0])

    print("\n| size (1 bounce) | frame ms | " + " | ".join(STAGES) + " |")
    print("|---|---:|" + "---:|" * len(STAGES))
    for size, s in sizes.items():
        print(stage_row(size, s))
    print("\n| bounces (640x360) | frame ms | indirect ms | inject ms (once) |")
    print("|---:|---:|---:|---:|")
    for b, s in bounces.items():
        st = s["stages"]
        print(f"| {b} | {s['frame_ms']:.1f} | {st.get('indirect', 0):.1f} | {st['inject']:.0f} |")
    print("\n| grid | voxelize ms | octree ms | inject ms (2 bounces) | nodes | octree MiB | "
          "dense MiB | ratio |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|")
    for v, s in voxels.items():
        st, o = s["stages"], s["octree"]
        print(f"| {v}^3 | {st['voxelize']:.0f} | {st['octree']:.0f} | {st['inject']:.0f} | "
              f"{o['nodes']} | {o['bytes'] / 2**20:.1f} | {o['dense_bytes'] / 2**20:.0f} | "
              f"{100 * o['bytes'] / o['dense_bytes']:.1f}% |")
    print("\n| 640x360, 1 bounce | frame ms | " + " | ".join(STAGES) + " |")
    print("|---|---:|" + "---:|" * len(STAGES))
    for name, s in others.items():
        print(stage_row(name, s))
    for kind, first in restarts.items():
        print(f"first frame after a restart, --target-fps 30, {kind}: "
              f"{statistics.median(first):.1f} ms (median of {', '.join(f'{x:.1f}' for x in first)})")
    return 0
