"""rtgi while the camera moves: the error at the end of a camera move, with and
without reprojection, against the path tracer.

For each view (cornell_room from its camera and from a second viewpoint, dark_plane)
the camera orbits the view's target by --orbit degrees over --move frames (a glTF
camera path added to a copy of the scene, played at 30 fps), ending at the view;
then it holds still. The image after 1, 4, 16 and 64 frames at the end pose is
measured against the view's path-traced reference (FLIP on sRGB 8-bit, RMSE), with
--reproject off (every move restarts accumulation: the previous design, the anchor
of the same run) and on with each --history-cap of --caps, the running mean itself
(--denoise off) and denoised. The stage times come
from the same renders (the median frame, the reproject stage on moving frames).

Writes out/bench-motion/table.md and motion.png and prints the table. References
come from out/reference/ (the highest spp there); a missing one is rendered.
"""
import argparse
import base64
import json
import math
import os
import re
import shutil
import struct
import subprocess
import sys

from voxgi_tools import ROOT, metrics, scene_path, voxgi
from voxgi_tools import reference as refs
from voxgi_tools.bench_convergence import SIZE

FPS = 30.0
SEED = 7
# Each view: its scene, the eye and the target it ends at.
VIEWS = {
    "cornell_room": ("cornell_room", (0.0, 1.0, 3.4), (0.0, 1.0, 0.0)),
    "cornell_room_side": ("cornell_room", (0.75, 1.5, 1.1), (-0.4, 0.35, -0.5)),
    "dark_plane": ("dark_plane", (0.0, 1.2, 4.0), (0.0, 0.5, 0.0)),
}
STILL = [1, 4, 16, 64]


def look_rotation(eye, target):
    """The glTF rotation (x, y, z, w) of a camera at eye looking at target, +y up."""
    f = [t - e for t, e in zip(target, eye)]
    n = math.sqrt(sum(c * c for c in f))
    back = [-c / n for c in f]
    up0 = (0.0, 1.0, 0.0)
    right = [up0[1] * back[2] - up0[2] * back[1], up0[2] * back[0] - up0[0] * back[2],
             up0[0] * back[1] - up0[1] * back[0]]
    n = math.sqrt(sum(c * c for c in right))
    right = [c / n for c in right]
    up = [back[1] * right[2] - back[2] * right[1], back[2] * right[0] - back[0] * right[2],
          back[0] * right[1] - back[1] * right[0]]
    m = [[right[0], up[0], back[0]], [right[1], up[1], back[1]], [right[2], up[2], back[2]]]
    tr = m[0][0] + m[1][1] + m[2][2]
    if tr > 0.0:
        s = 2.0 * math.sqrt(tr + 1.0)
        return ((m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s, s / 4)
    i = max(range(3), key=lambda k: m[k][k])
    j, k = (i + 1) % 3, (i + 2) % 3
    s = 2.0 * math.sqrt(1.0 + m[i][i] - m[j][j] - m[k][k])
    q = [0.0, 0.0, 0.0, (m[k][j] - m[j][k]) / s]
    q[i] = s / 4
    q[j] = (m[j][i] + m[i][j]) / s
    q[k] = (m[k][i] + m[i][k]) / s
    return tuple(q)


def orbit(eye, target, degrees):
    """eye turned about the vertical through target."""
    a = math.radians(degrees)
    dx, dz = eye[0] - target[0], eye[2] - target[2]
    return (target[0] + dx * math.cos(a) + dz * math.sin(a), eye[1],
            target[2] - dx * math.sin(a) + dz * math.cos(a))


def path_scene(view, move, hold, degrees, outdir, settle=0):
    """A copy of the view's scene whose camera holds its start pose for `settle`
    frames, orbits into the view over `move` frames and then holds for `hold` (glTF
    animations loop: the last key holds the end pose past every frame rendered).
    Returns the path of the copy's glTF."""
    scene, eye, target = VIEWS[view]
    src = os.path.dirname(scene_path(scene))
    dst = os.path.join(outdir, "scenes", view)
    shutil.rmtree(dst, ignore_errors=True)
    shutil.copytree(src, dst)
    path = os.path.join(dst, f"{scene}.gltf")
    with open(path) as f:
        g = json.load(f)
    cam = next(i for i, n in enumerate(g["nodes"]) if "camera" in n)
    times, moves, turns = [], [], []
    if settle > 0:
        e = orbit(eye, target, -degrees)
        times.append(0.0)
        moves.append(e)
        turns.append(look_rotation(e, target))
    for k in range(move):
        u = k / (move - 1) if move > 1 else 1.0
        e = orbit(eye, target, -degrees * (1.0 - u))
        times.append((settle + k) / FPS)
        moves.append(e)
        turns.append(look_rotation(e, target))
    times.append((settle + move + hold + 1) / FPS)
    moves.append(moves[-1])
    turns.append(turns[-1])
    move = len(times)
    blob = struct.pack(f"<{len(times)}f", *times)
    blob += b"".join(struct.pack("<3f", *e) for e in moves)
    blob += b"".join(struct.pack("<4f", *q) for q in turns)
    g["buffers"].append({"byteLength": len(blob), "uri": "data:application/octet-stream;base64,"
                         + base64.b64encode(blob).decode()})
    b = len(g["buffers"]) - 1
    views = g.setdefault("bufferViews", [])
    acc = g.setdefault("accessors", [])
    offsets = [(0, 4 * move, "SCALAR"), (4 * move, 12 * move, "VEC3"), (16 * move, 16 * move, "VEC4")]
    first = len(acc)
    for off, length, kind in offsets:
        views.append({"buffer": b, "byteOffset": off, "byteLength": length})
        acc.append({"bufferView": len(views) - 1, "componentType": 5126, "count": move,
                    "type": kind})
    acc[first]["min"] = [times[0]]
    acc[first]["max"] = [times[-1]]
    g["nodes"][cam].pop("matrix", None)
    g["nodes"][cam]["translation"] = list(moves[-1])
    g["nodes"][cam]["rotation"] = list(turns[-1])
    g.setdefault("animations", []).append({
        "name": "camera move",
        "samplers": [{"input": first, "output": first + 1, "interpolation": "LINEAR"},
                     {"input": first, "output": first + 2, "interpolation": "LINEAR"}],
        "channels": [{"sampler": 0, "target": {"node": cam, "path": "translation"}},
                     {"sampler": 1, "target": {"node": cam, "path": "rotation"}}]})
    with open(path, "w") as f:
        json.dump(g, f)
    return path


def reference(view, spp):
    scene, eye, target = VIEWS[view]
    extra = [] if view == scene else ["--look-from", ",".join(map(str, eye)),
                                      "--look-at", ",".join(map(str, target))]
    return refs.get(view, scene_path(scene), extra, SIZE, spp)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n".join(__doc__.splitlines()[1:]))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "bench-motion"))
    ap.add_argument("--move", type=int, default=16, help="frames of the move (default 16)")
    ap.add_argument("--orbit", type=float, default=10.0,
                    help="degrees the camera turns about the target (default 10)")
    ap.add_argument("--caps", default="8,16,32",
                    help="--history-cap values to measure (default 8,16,32)")
    ap.add_argument("--still", default=",".join(map(str, STILL)),
                    help="frames at the end pose to measure after (default 1,4,16,64)")
    ap.add_argument("--ref-spp", type=int, default=1024,
                    help="spp of a reference rendered because none exists (default 1024)")
    ap.add_argument("--view", action="append", choices=list(VIEWS),
                    help="only this view (repeatable)")
    a = ap.parse_args(argv)
    if not os.path.exists(voxgi()):
        raise SystemExit("bench-motion: error: build/voxgi missing (tools/build)")
    if a.move < 2:
        raise SystemExit("bench-motion: error: --move must be at least 2 frames")
    caps = [int(c) for c in a.caps.split(",") if c]
    still = [int(s) for s in a.still.split(",") if s]
    os.makedirs(a.out, exist_ok=True)
    configs = [("restart", ["--reproject", "off", "--denoise", "off"])]
    configs += [(f"reproject, cap {c}",
                 ["--reproject", "on", "--history-cap", str(c), "--denoise", "off"])
                for c in caps]
    configs += [(f"reproject, cap {c}, denoised",
                 ["--reproject", "on", "--history-cap", str(c), "--denoise", "on"])
                for c in caps]
    lines = [f"Camera orbiting {a.orbit:g} degrees over {a.move} frames, then still; "
             "FLIP and RMSE against the path tracer at the end pose.", "",
             "| view | history | frames still | FLIP | RMSE | frame ms | reproject ms | "
             "denoise ms |", "|---|---|---:|---:|---:|---:|---:|---:|"]
    print("\n".join(lines), flush=True)
    rows = []
    for view in VIEWS:
        if a.view and view not in a.view:
            continue
        ref_exr, ref_png, ref_spp = reference(view, a.ref_spp)
        scene = path_scene(view, a.move, max(still), a.orbit, a.out)
        for name, flags in configs:
            for s in still:
                tag = re.sub(r"[^a-z0-9]+", "_", f"{view}_{name}_{s}")
                base = os.path.join(a.out, "runs", tag)
                os.makedirs(os.path.dirname(base), exist_ok=True)
                subprocess.run([voxgi(), "render", scene, "--mode", "rtgi", "--size",
                                SIZE, "--seed", str(SEED), "--fps", str(FPS),
                                "--frames", str(a.move - 1 + s), "--out", base + ".exr",
                                "--out", base + ".png", "--stats", base + ".json", "-q"]
                               + flags, check=True)
                with open(base + ".json") as f:
                    stats = json.load(f)
                m = metrics.measure(base, ref_exr, ref_png)
                row = {"view": view, "history": name, "still": s, **m,
                       "frame_ms": stats["frame_ms"],
                       "reproject_ms": stats["stages"].get("reproject", 0.0),
                       "denoise_ms": stats["stages"].get("denoise", 0.0)}
                rows.append(row)
                line = (f"| {view} | {name} | {s} | {m['flip']:.4f} | {m['rmse']:.4f} | "
                        f"{row['frame_ms']:.1f} | {row['reproject_ms']:.2f} | "
                        f"{row['denoise_ms']:.2f} |")
                lines.append(line)
                print(line, flush=True)
        lines.append(f"| {view} | reference | {ref_spp} spp | | | | | |")
    with open(os.path.join(a.out, "table.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    plot(rows, a.out)


def plot(rows, outdir):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    views = sorted({r["view"] for r in rows}, key=list(VIEWS).index)
    fig, axes = plt.subplots(1, len(views), figsize=(5 * len(views), 4), squeeze=False)
    for ax, view in zip(axes[0], views):
        for name in dict.fromkeys(r["history"] for r in rows):
            pts = [(r["still"], r["flip"]) for r in rows
                   if r["view"] == view and r["history"] == name]
            ax.plot([p[0] for p in pts], [p[1] for p in pts],
                    "s--" if name == "restart" else "o-", label=name)
        ax.set(xscale="log", xlabel="frames since the camera stopped", ylabel="FLIP", title=view)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "motion.png"), dpi=80)


if __name__ == "__main__":
    sys.exit(main())
