"""rtgi against the path tracer, as time goes by: time to the image and its error.

For each view of the validation set (scenes/validation_set.json; --view picks some),
renders rtgi at 1, 4, 16, 64 and 256 accumulated frames with the current defaults
(denoised) and with --denoise off (the running mean itself), one row with the
previous design's settings as the anchor of the same run
(--voxel-rays --denoise off: shadow and indirect rays marching the voxels, no denoiser), and the path tracer at 1, 4, 16 and 64 spp. Each image is measured against
the view's path-traced reference (FLIP on sRGB 8-bit, RMSE and mean luminance ratio
from `voxgi compare`). Time to the image is the render's total_ms: every frame
accumulated, start-up (voxelize, octree, inject; the BVH) excluded, after an
untimed frame of each rtgi setting has compiled its shaders.

With --against-mitsuba, Mitsuba 3 renders each view too (mitsuba_scene.py: the
same scene with voxgi's material model, its render time after a first run that
compiles its kernels), at 16 and 64 spp, and rtgi renders as many frames as fit in
each of Mitsuba's times (from its 16-frame run's time a frame): the race of the
validation set's targets, rtgi's image within Mitsuba's time against Mitsuba's.
Each side's time in the race is the median of --race-runs renders (default 3): on
this machine one render's time scatters by tens of percent, and a heat decided by
one of them was decided by that scatter (dark_plane's one frame took 452 ms in one
heat and 299 ms in the same run's table).

With --held-out N, N viewpoints drawn at random in the set's scenes (the
"held_out" section of scenes/validation_set.json; validation_set.held_out) are
rendered instead of the set's views (besides them with --view): views nobody has
tuned rtgi to, new ones with each --held-out-seed (by default one from the clock,
printed with the views so a run can be repeated). Their references are rendered
at --ref-spp into out/reference/, by a name that holds a hash of the viewpoint.

With --scene FILE (repeatable), any glTF file is raced the same way, from its own
camera or from --look-from/--look-at: a scene of your own against the path
tracer's reference and Mitsuba.

Each image is also measured on its mirrors and on its glossy surfaces alone (FLIP
over those pixels: regions.py), the light rtgi's specular stage carries, which the
whole image's FLIP averages away where they are small.

Writes out/bench-convergence/table.md and convergence.png (FLIP against time per
view, rtgi and the path tracer), and prints the table. References come from
tests/data/reference/ (committed, 4096 spp) or out/reference/, the highest spp there;
a missing one is rendered at --ref-spp.
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import time

from voxgi_tools import ROOT, metrics, regions, validation_set, voxgi
from voxgi_tools import reference as refs

SIZE = "256x256"
SEED = 7  # test renders; the references have their own (voxgi_tools.reference)
FRAMES = [1, 4, 16, 64, 256]
SPP = [1, 4, 16, 64]
ANCHOR = ["--voxel-rays", "--denoise", "off"]
# The brute-force renders go as deep as the references (voxgi_tools.reference).
PT_DEPTH = ["--max-depth", str(refs.DEPTH)]


def run(view, scene, extra, args, outdir, tag):
    base = os.path.join(outdir, "runs", f"{view}_{tag}")
    os.makedirs(os.path.dirname(base), exist_ok=True)
    subprocess.run([voxgi(), "render", scene, "--size", SIZE, "--seed", str(SEED),
                    "--out", base + ".exr", "--out", base + ".png", "--stats", base + ".json",
                    "--no-progress", "-q"] + extra + args, check=True)
    with open(base + ".json") as f:
        return base, json.load(f)


def warm_up(view, scene, extra, outdir):
    """Two untimed frames with each rtgi setting the table times, so that llvmpipe's
    compiling of their shader variants (which Mesa's disk cache then keeps) falls in
    none of the timed runs: the first run after a shader change took 1.2-1.8 s for a
    frame of 0.1-0.2 s. Two runs, each its own process: a variant new to the cache
    was compiled again by the second run (EmissiveStrengthTest, one frame: 2,007 ms,
    2,277 ms, then 286 ms; the specular stage 1,717, 2,097, then 140 ms), so one
    warm-up left the compiling in the first timed row. Mitsuba's kernels are
    compiled by a first run too."""
    for args in ([], ["--denoise", "off"], ANCHOR):
        for _ in range(2):
            run(view, scene, extra, ["--frames", "1"] + args, outdir, "warm_up")


def mitsuba(view, scene, entry_flags, spps, outdir):
    """[(spp, render ms, exr)] of Mitsuba 3 on the view (mitsuba_scene.py)."""
    prefix = os.path.join(outdir, "runs", f"{view}_mitsuba")
    os.makedirs(os.path.dirname(prefix), exist_ok=True)
    cmd = [sys.executable, "-m", "voxgi_tools", "mitsuba", "render", scene, "--size", SIZE,
           "--spp", ",".join(map(str, spps)), "--out-prefix", prefix, "--seed", str(SEED),
           "--max-depth", str(refs.DEPTH)]
    # --look-at=-0.4,... : a value that starts with '-' joined to its flag.
    cmd += [f"{f}={v}" for f, v in zip(entry_flags[::2], entry_flags[1::2])]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(f"bench-convergence: Mitsuba on {view} failed ({r.stderr.strip()[-600:]}); "
                         "Mitsuba 3 comes with tools/setup --mitsuba")
    out = []
    for line in r.stdout.splitlines():
        if line.startswith("{"):
            d = json.loads(line)
            if d["dropped"]:
                print(f"bench-convergence: {view}: Mitsuba's copy leaves out "
                      f"{', '.join(d['dropped'])}", flush=True)
            out.append((d["spp"], d["ms"], d["exr"]))
    return out


def timed(view, scene, extra, args, outdir, tag, runs):
    """run() `runs` times: its base and stats, total_ms the median of the runs' (the
    same seed gives the same image each time, so only the time is measured again)."""
    times = []
    for _ in range(runs):
        base, stats = run(view, scene, extra, args, outdir, tag)
        times.append(stats["total_ms"])
    stats["total_ms"] = statistics.median(times)
    return base, stats


def frames_within(view, scene, extra, budget_ms, frame_ms, outdir, runs=1):
    """rtgi with as many frames as fit in budget_ms: (frames, base, stats). The count
    comes from frame_ms and is cut while the render takes longer (the median of
    `runs` renders)."""
    n = max(1, int(budget_ms // frame_ms))
    while True:
        base, stats = timed(view, scene, extra, ["--frames", str(n)], outdir, f"rtgi_within_{n}",
                            runs)
        if stats["total_ms"] <= budget_ms or n == 1:
            return n, base, stats
        n = max(1, min(n - 1, int(n * budget_ms / stats["total_ms"])))


def plot(rows, views, outdir):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    cols = min(3, len(views))
    nrows = (len(views) + cols - 1) // cols
    fig, axes = plt.subplots(nrows, cols, figsize=(5 * cols, 4 * nrows), squeeze=False)
    for ax in axes.flat[len(views):]:
        ax.set_visible(False)
    for ax, view in zip(axes.flat, views):
        for kind, style in (("rtgi", "o-"), ("rtgi, not denoised", "o:"), ("pathtrace", "s--"),
                            ("rtgi, previous", "x"), ("Mitsuba 3", "^--"),
                            ("rtgi within Mitsuba's time", "D")):
            pts = [(r["ms"], r["flip"]) for r in rows if r["view"] == view and r["kind"] == kind]
            if pts:
                ax.plot([p[0] for p in pts], [p[1] for p in pts], style, label=kind)
        ax.set(xscale="log", xlabel="time to the image (ms)", ylabel="FLIP", title=view)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.tight_layout()
    path = os.path.join(outdir, "convergence.png")
    fig.savefig(path, dpi=80)
    return path


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n".join(__doc__.splitlines()[1:]))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "bench-convergence"))
    ap.add_argument("--ref-spp", type=int, default=4096,
                    help="spp of a reference rendered because none exists (default 4096; the "
                    "committed references in tests/data/reference are 4096 spp)")
    ap.add_argument("--view", action="append", choices=validation_set.names(),
                    help="only this view of the validation set (repeatable; default: all)")
    ap.add_argument("--quick", action="store_true",
                    help="rtgi at 1, 16 and 64 frames and pathtrace at 16 and 64 spp only")
    ap.add_argument("--against-mitsuba", action="store_true",
                    help="also Mitsuba 3 at 16 and 64 spp, and rtgi within each of its times")
    ap.add_argument("--race-runs", type=int, default=3,
                    help="with --against-mitsuba: each side's time in the race is the median "
                    "of this many renders (default 3; a single render's time scatters by "
                    "tens of percent here)")
    ap.add_argument("--held-out", type=int, default=0, metavar="N",
                    help="N viewpoints drawn at random in the set's scenes instead of the set's "
                    "views (besides those given with --view)")
    ap.add_argument("--held-out-seed", type=int, metavar="S",
                    help="the seed that draws them (default: from the clock; printed)")
    ap.add_argument("--scene", action="append", default=[], metavar="FILE",
                    help="a glTF file outside the set, raced the same way (repeatable; instead "
                    "of the set's views, besides those given with --view)")
    ap.add_argument("--look-from", metavar="X,Y,Z",
                    help="with --scene: the viewpoint, instead of the file's camera")
    ap.add_argument("--look-at", metavar="X,Y,Z", help="with --scene: the point it looks at")
    a = ap.parse_args(argv)
    if (a.look_from is None) != (a.look_at is None):
        ap.error("--look-from and --look-at go together")
    if a.look_from is not None and not a.scene:
        ap.error("--look-from and --look-at place the camera of a --scene")
    if a.held_out < 0:
        ap.error(f"--held-out must be 0 or more, not {a.held_out}")
    if a.race_runs < 1:
        ap.error(f"--race-runs must be 1 or more, not {a.race_runs}")
    if not os.path.exists(voxgi()):
        raise SystemExit("bench-convergence: error: build/voxgi missing (tools/build)")
    if a.against_mitsuba and subprocess.run([sys.executable, "-c", "import mitsuba"],
                                            capture_output=True).returncode != 0:
        raise SystemExit("bench-convergence: error: --against-mitsuba needs Mitsuba 3 in .venv "
                         "(tools/setup --mitsuba)")
    os.makedirs(a.out, exist_ok=True)
    rows = []
    lines = ["| view | renderer | setting | time to the image (ms) | FLIP | RMSE | mean luminance "
             "ratio | FLIP on mirrors | FLIP on glossy |",
             "|---|---|---|---:|---:|---:|---:|---:|---:|"]
    frames, spps = ([1, 16, 64], [16, 64]) if a.quick else (FRAMES, SPP)
    own = a.held_out or a.scene
    views = validation_set.views(a.view) if a.view or not own else []
    place = ["--look-from", a.look_from, "--look-at", a.look_at] if a.look_from else []
    views += validation_set.user_scenes(a.scene, place)
    held = []
    if a.held_out:
        seed = a.held_out_seed if a.held_out_seed is not None else int(time.time()) % 1000000
        held = validation_set.held_out(a.held_out, seed)
        print(f"bench-convergence: {a.held_out} held-out views, --held-out-seed {seed}:", flush=True)
        for view, scene, extra in held:
            print(f"  {view}: {os.path.relpath(scene, ROOT)} {' '.join(extra)}", flush=True)
        views += held
    race = ["| view | Mitsuba 3 | its time (ms) | its FLIP | rtgi within it | rtgi's time (ms) | "
            "rtgi's FLIP | closer | on mirrors (Mitsuba, rtgi) | on glossy (Mitsuba, rtgi) |",
            "|---|---|---:|---:|---|---:|---:|---|---:|---:|"]

    def record(view, kind, setting, ms, m):
        row = {"view": view, "kind": kind, "setting": setting, "ms": ms, **m}
        rows.append(row)
        line = (f"| {view} | {kind} | {setting} | {ms:.0f} | {m['flip']:.4f} | "
                f"{m['rmse']:.4f} | {m['lum']:.3f} | " +
                " | ".join(f"{m[k]:.4f}" if k in m else "" for k in
                           ("flip_" + c for c in regions.CLASSES)) + " |")
        lines.append(line)
        print(line, flush=True)
        return row

    for view, scene, extra in views:
        ref_exr, ref_png, ref_spp = refs.get(view, scene, extra, SIZE, a.ref_spp)
        masks = regions.masks(view, scene, extra, SIZE, os.path.join(a.out, "regions"))
        jobs = [("rtgi", f"{f} frames", ["--frames", str(f)]) for f in frames]
        jobs += [("rtgi, not denoised", f"{f} frames, --denoise off",
                  ["--frames", str(f), "--denoise", "off"]) for f in frames]
        jobs.append(("rtgi, previous", "64 frames, " + " ".join(ANCHOR),
                     ["--frames", "64"] + ANCHOR))
        jobs += [("pathtrace", f"{s} spp", ["--mode", "pathtrace", "--spp", str(s)] + PT_DEPTH)
                 for s in spps]
        frame_ms = None
        warm_up(view, scene, extra, a.out)
        for kind, setting, args in jobs:
            tag = re.sub(r"[^a-z0-9]+", "_", f"{kind}_{setting}")
            base, stats = run(view, scene, extra, args, a.out, tag)
            record(view, kind, setting, stats["total_ms"], metrics.measure(base, ref_exr, ref_png, masks))
            if kind == "rtgi" and setting == "16 frames":
                frame_ms = stats["total_ms"] / 16
        if a.against_mitsuba:
            # The same seed gives the same image each time: the runs measure the time.
            renders = [mitsuba(view, scene, extra, [16, 64], a.out) for _ in range(a.race_runs)]
            for i, (spp, _, exr) in enumerate(renders[-1]):
                ms = statistics.median(r[i][1] for r in renders)
                png = exr[:-4] + ".png"
                subprocess.run(["oiiotool", exr, "--ch", "R,G,B", "--colorconvert", "linear",
                                "sRGB", "-d", "uint8", "-o", png], check=True, capture_output=True)
                theirs = record(view, "Mitsuba 3", f"{spp} spp", ms, metrics.measure(exr[:-4], ref_exr,
                                                                               ref_png, masks))
                n, base, stats = frames_within(view, scene, extra, ms, frame_ms, a.out,
                                               a.race_runs)
                ours = record(view, "rtgi within Mitsuba's time", f"{n} frames",
                              stats["total_ms"], metrics.measure(base, ref_exr, ref_png, masks))
                closer = "rtgi" if ours["flip"] < theirs["flip"] else "Mitsuba"
                if ours["ms"] > ms:  # one frame alone takes longer
                    closer = "Mitsuba (rtgi's first frame comes later)"
                race.append(f"| {view} | {spp} spp | {ms:.0f} | {theirs['flip']:.4f} | {n} frames "
                            f"| {ours['ms']:.0f} | {ours['flip']:.4f} | {closer} | " + " | ".join(
                                f"{theirs[k]:.4f}, {ours[k]:.4f}" if k in ours else "" for k in
                                ("flip_" + c for c in regions.CLASSES)) + " |")
        lines.append(f"| {view} | reference | {ref_spp} spp, seed {refs.SEED} | | | | | "
                     + " | ".join(f"{masks[c].sum()} px" if c in masks else "none"
                                  for c in regions.CLASSES) + " |")
    table = "\n".join(lines) + "\n"
    if held:
        table += (f"\nHeld-out views (--held-out {a.held_out} --held-out-seed {seed}):\n\n" +
                  "\n".join(f"- {view}: `{os.path.relpath(scene, ROOT)} {' '.join(extra)}`"
                            for view, scene, extra in held) + "\n")
    if a.against_mitsuba:
        table += (f"\nThe race: rtgi within Mitsuba's time (each time the median of "
                  f"{a.race_runs} renders)\n\n" + "\n".join(race) + "\n")
    with open(os.path.join(a.out, "table.md"), "w") as f:
        f.write(table)
    print(table)
    print("bench-convergence: wrote", os.path.join(a.out, "table.md"), "and", plot(rows, [v[0] for v in views], a.out))


if __name__ == "__main__":
    sys.exit(main())
