"""Path-traced references: found where they were made before, rendered where none is.

A reference of a view at a size is VIEW_WxH_Nspp.exr (linear radiance) with its .png
(sRGB 8-bit, what FLIP reads) and, when rendered here, its stats .json. The
committed ones live in tests/data/reference/ (4096 spp; the EXR in half floats), the
others in out/reference/ (not in git). The highest spp of either folder is used.

Every reference is rendered the same way: voxgi's path tracer with seed SEED, kept
out of the benchmarks' seeds so a test image never shares samples with its
reference, and paths to depth DEPTH. rtgi's voxels hold every bounce, so a reference
cut at the path tracer's default depth 8 is 0.02-3.3% darker than what rtgi converges
to (docs/measurements.md#2026-12-06-reference-depth); Russian roulette ends most
paths long before depth 64.
"""
import json
import os
import re
import subprocess

from voxgi_tools import ROOT, voxgi

SEED = 1000003
DEPTH = 64
COMMITTED = os.path.join(ROOT, "tests", "data", "reference")
MADE = os.path.join(ROOT, "out", "reference")


def depth_of(exr):
    """The path depth a reference was rendered with, from the stats JSON beside it
    (DEPTH for a committed one, which has none)."""
    try:
        with open(exr[:-4] + ".json") as f:
            return json.load(f).get("max_depth", DEPTH)
    except FileNotFoundError:
        return DEPTH


def find(view, size, folders=(COMMITTED, MADE), depth=DEPTH):
    """(exr, png, spp) of the highest-spp reference of `view` at `size` in `folders`
    rendered to `depth`, or None. One cut at another depth (made before the depth
    was raised) is passed over."""
    best = None
    for d in folders:
        for name in sorted(os.listdir(d)) if os.path.isdir(d) else []:
            m = re.fullmatch(rf"{re.escape(view)}_{size}_(\d+)spp\.exr", name)
            if not m or depth_of(os.path.join(d, name)) != depth:
                continue
            if best is None or int(m.group(1)) > best[0]:
                best = (int(m.group(1)), os.path.join(d, name))
    if best is None:
        return None
    return best[1], best[1][:-4] + ".png", best[0]


def render(scene, extra, size, spp, base, flags=(), binary=None, seed=SEED):
    """Renders the reference of `scene` (with its view's flags `extra`) into base.exr,
    base.png and base.json. `flags` add to the path tracer's; a --max-depth among
    them (a term's depth cut) replaces DEPTH. `seed`: another than SEED gives an
    image of the same expectation with other samples (its noise)."""
    os.makedirs(os.path.dirname(base), exist_ok=True)
    depth = [] if "--max-depth" in flags else ["--max-depth", str(DEPTH)]
    cmd = [binary or voxgi(), "render", scene] + list(extra) + [
        "--mode", "pathtrace", "--size", size, "--spp", str(spp), "--seed", str(seed)
    ] + depth + list(flags) + [
        "--out", base + ".exr", "--out", base + ".png", "--stats", base + ".json",
        "--no-progress", "-q"]
    subprocess.run(cmd, check=True)
    return base + ".exr", base + ".png", spp


def get(view, scene, extra, size, spp):
    """(exr, png, spp) of `view`'s reference at `size`: the best one made before, or
    one rendered now at `spp` into out/reference/."""
    found = find(view, size)
    if found:
        return found
    print(f"rendering the {view} reference ({size}, {spp} spp)", flush=True)
    return render(scene, extra, size, spp, os.path.join(MADE, f"{view}_{size}_{spp}spp"))


def main(argv=None):
    import argparse

    from voxgi_tools import validation_set

    ap = argparse.ArgumentParser(
        description="Renders path-traced references of views of the validation set into "
        "out/reference/ (VIEW_WxH_Nspp.exr, .png and the stats .json), with seed "
        f"{SEED}, kept out of the benchmarks' seeds.")
    ap.add_argument("spp", nargs="?", type=int, default=2048,
                    help="samples per pixel (default %(default)s)")
    ap.add_argument("size", nargs="?", default="256x256", help="WxH (default %(default)s)")
    ap.add_argument("views", nargs="*", metavar="VIEW",
                    help="views of scenes/validation_set.json, or 'all' "
                    "(default: cornell_room dark_plane)")
    ap.add_argument("--max-depth", type=int, default=DEPTH,
                    help="path depth (default %(default)s: uncut, as rtgi's voxels hold every "
                    "bounce)")
    a = ap.parse_args(argv)
    if not os.path.exists(voxgi()):
        raise SystemExit("make-reference: error: build/voxgi missing (tools/build)")
    names = a.views or ["cornell_room", "dark_plane"]
    if names == ["all"]:
        names = validation_set.names()
    for view, scene, extra in validation_set.views(names):
        base = os.path.join(MADE, f"{view}_{a.size}_{a.spp}spp")
        print(f"make-reference: {view} at {a.size}, {a.spp} spp, depth {a.max_depth} -> "
              f"{os.path.relpath(base, ROOT)}.exr", flush=True)
        render(scene, extra, a.size, a.spp, base, ["--max-depth", str(a.max_depth)])
    return 0
