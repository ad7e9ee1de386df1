"""The headline accuracy figures, pinned: a CI-sized check that they do not get worse.

For three views of the validation set (cornell_room from its camera and from a
second viewpoint, dark_plane), at 256x256 with seed 7 and the defaults, renders
  rtgi at 1 and at 16 accumulated frames, and the path tracer at 64 spp (as deep
  as the references: voxgi_tools.reference),
and measures FLIP (tools/flip: sRGB 8-bit) against the view's committed 4096-spp
path-traced reference (tests/data/reference/VIEW_256x256_4096spp.png).

Each figure is checked against tests/data/reference/figures.json: the committed
value (seed 7) and its seed-to-seed noise (the standard deviation over seeds 3-7,
measured by --update). A figure more than 3 of its standard deviations above
the committed one (at least 0.001 of FLIP) fails the check: exit 1, with the rows
that failed. About 40 s on 2 cores.

  --update    re-measures every figure at seeds 3-7 and rewrites figures.json; for a
              change that moves the figures on purpose (say why in the commit)
  --reference renders the three references again (4096 spp; ~8 min)
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

from voxgi_tools import ROOT, metrics, validation_set, voxgi
from voxgi_tools import reference as refs

SIZE = "256x256"
# The views whose figures are pinned (of the validation set): the two rooms' references
# are committed.
VIEWS = validation_set.views(["cornell_room", "cornell_room_side", "dark_plane"])
SEED = 7
NOISE_SEEDS = [3, 4, 5, 6, 7]
REF_SPP = 4096
DATA = refs.COMMITTED
FIGURES = os.path.join(DATA, "figures.json")
# (figure name, voxgi render flags)
FIGURES_RUN = [
    ("rtgi, 1 frame", ["--frames", "1"]),
    ("rtgi, 16 frames", ["--frames", "16"]),
    ("pathtrace, 64 spp", ["--mode", "pathtrace", "--spp", "64", "--max-depth", str(refs.DEPTH)]),
]
SIGMAS = 3.0
FLOOR = 0.001


def reference_png(view):
    return os.path.join(DATA, f"{view}_{SIZE}_{REF_SPP}spp.png")


def render(binary, scene, extra, flags, seed, out):
    cmd = [binary, "render", scene, "--size", SIZE, "--seed", str(seed), "--out",
           out, "--no-progress", "-q"] + extra + flags
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise SystemExit(f"bench-regression: error: {' '.join(cmd)} exited {p.returncode}: "
                         f"{(p.stderr or p.stdout).strip()}")


def measure(binary, view, scene, extra, flags, seed, tmp):
    out = os.path.join(tmp, f"{view}_{seed}.png")
    render(binary, scene, extra, flags, seed, out)
    return metrics.flip(out, reference_png(view))


def make_references(binary):
    """The references, as the 8-bit sRGB image FLIP reads and as linear radiance in
    half floats (what tools/bench-convergence's RMSE and mean ratio read)."""
    for view, scene, extra in VIEWS:
        print(f"bench-regression: rendering the {view} reference ({REF_SPP} spp)", flush=True)
        base = reference_png(view)[:-4]
        refs.render(scene, extra, SIZE, REF_SPP, base, binary=binary)
        subprocess.run(["oiiotool", base + ".exr", "-d", "half", "--compression", "zip", "-o",
                        base + ".exr"], check=True)
        os.remove(base + ".json")


def update(binary, tmp):
    figures = {"size": SIZE, "seed": SEED, "reference_spp": REF_SPP, "views": {}}
    for view, scene, extra in VIEWS:
        figures["views"][view] = {}
        for name, flags in FIGURES_RUN:
            values = [measure(binary, view, scene, extra, flags, s, tmp) for s in NOISE_SEEDS]
            mean = sum(values) / len(values)
            sd = math.sqrt(sum((v - mean) ** 2 for v in values) / (len(values) - 1))
            at_seed = values[NOISE_SEEDS.index(SEED)]
            figures["views"][view][name] = {"flip": round(at_seed, 5), "noise": round(sd, 5)}
            print(f"{view:18s} {name:18s} FLIP {at_seed:.4f} (seeds {min(values):.4f}-"
                  f"{max(values):.4f}, sd {sd:.4f})", flush=True)
    with open(FIGURES, "w") as f:
        json.dump(figures, f, indent=1)
        f.write("\n")
    print("bench-regression: wrote", os.path.relpath(FIGURES, ROOT))


def check(binary, tmp):
    with open(FIGURES) as f:
        figures = json.load(f)["views"]
    failed = []
    print("| view | figure | committed | noise (sd) | bound | now | |")
    print("|---|---|---:|---:|---:|---:|---|")
    for view, scene, extra in VIEWS:
        for name, flags in FIGURES_RUN:
            fig = figures[view][name]
            bound = fig["flip"] + max(SIGMAS * fig["noise"], FLOOR)
            now = measure(binary, view, scene, extra, flags, SEED, tmp)
            ok = now <= bound
            print(f"| {view} | {name} | {fig['flip']:.4f} | {fig['noise']:.4f} | {bound:.4f} | "
                  f"{now:.4f} | {'ok' if ok else 'WORSE'} |", flush=True)
            if not ok:
                failed.append(f"{view}, {name}: FLIP {now:.4f} > {bound:.4f}")
    if failed:
        print("bench-regression: FAIL: worse than the committed figures by more than their "
              "noise:\n  " + "\n  ".join(failed))
        return 1
    print("bench-regression: every figure within its noise of the committed one")
    return 0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n".join(__doc__.splitlines()[1:]))
    ap.add_argument("--voxgi", default=voxgi())
    ap.add_argument("--update", action="store_true")
    ap.add_argument("--reference", action="store_true")
    a = ap.parse_args(argv)
    if not os.path.exists(a.voxgi):
        raise SystemExit(f"bench-regression: error: {a.voxgi} missing (tools/build)")
    if a.reference:
        make_references(a.voxgi)
    for view, _, _ in VIEWS:
        if not os.path.exists(reference_png(view)):
            raise SystemExit(f"bench-regression: error: {reference_png(view)} missing "
                             "(--reference renders it)")
    with tempfile.TemporaryDirectory(prefix="voxgi-bench-regression-") as tmp:
        if a.update:
            update(a.voxgi, tmp)
            return 0
        if not os.path.exists(FIGURES):
            raise SystemExit(f"bench-regression: error: {FIGURES} missing (--update makes it)")
        return check(a.voxgi, tmp)


if __name__ == "__main__":
    sys.exit(main())
