"""rtgi term by term against the path tracer, and light leaks, on the validation set.

For each view (scenes/validation_set.json; --view picks some), renders rtgi with
--frames F (default 64) and --denoise off, one term at a time, and the path tracer
at the matching depth:

  direct           rtgi --effects -indirect,-specular   pathtrace --max-depth 2
  direct + 1       rtgi --bounces 1 --effects -specular pathtrace --max-depth 3
  all              rtgi (every effect)                  pathtrace --max-depth 64

The terms without specular render a copy of the scene whose mirrors (materials
smoother than roughness 0.05, what rtgi's specular stage alone lights) are black and
diffuse: the path tracer's depth-limited image of a mirror holds what the mirror
shows at that depth, which those terms leave out by design, so both images are dark
there and the comparison is of the light the term does carry. Each pair is measured
with `voxgi compare --blocks 16`: mean luminance ratio, the lowest and highest
16x16-block ratio, and the share of blocks off by more than 3%, plus FLIP. A bias
shows where it lives: in the direct term, or only once light bounces.

Both images are noisy: at 64 frames and 256 spp a block of a dim or small-lamp-lit
region scatters by several percent. With --seeds 2, rtgi and the path tracer each
render a second seed, and the row gives the same share of blocks off by more than 3%
between each renderer's two seeds: the share that noise alone makes. A bias shows as
a share of blocks off against the path tracer well above those two.

Leaks: for each pair of the set's "leaks" (a sealed room rendered with the light on
the other side of its wall on, then off; nothing can pass the wall, so the two
references are the same image), rtgi renders both at the same seed and the blocks of
one are compared with the other's: a block over 1.10 is light that came through the
wall. The path tracer does the same at --pt-spp as the control.

Writes out/bench-terms/table.md and prints it. Path-traced images are kept in
out/reference/ (VIEW_TERM_WxH_Nspp) and reused.
"""
import argparse
import json
import os
import re
import subprocess
import sys

from voxgi_tools import ROOT, metrics, regions, validation_set, voxgi
from voxgi_tools import reference as refs

SIZE = "256x256"
SEED = 7
# rtgi's kMirrorRoughness (rtgi_shared.h): smoother surfaces are mirrors, which only
# its specular stage lights (regions.py).
MIRROR_ROUGHNESS = regions.MIRROR_ROUGHNESS
TERMS = [
    ("direct", ["--effects", "-indirect,-specular"], ["--max-depth", "2"]),
    ("direct + 1", ["--bounces", "1", "--effects", "-specular"], ["--max-depth", "3"]),
    ("all", [], ["--max-depth", str(refs.DEPTH)]),
]


def render(scene, flags, base):
    subprocess.run([voxgi(), "render", scene, "--size", SIZE, "--out", base + ".exr", "--out",
                    base + ".png", "--stats", base + ".json", "--no-progress", "-q"] + flags,
                   check=True)
    with open(base + ".json") as f:
        return json.load(f)


def compare(test, ref):
    m = metrics.compare(test + ".exr", ref + ".exr", blocks=16)
    m["flip"] = metrics.flip(test + ".png", ref + ".png")
    return m


def pathtraced(view, term, scene, extra, flags, spp, seed=refs.SEED, variant=""):
    """The path tracer's image of `view` for `term` (its depth in `flags`), made once
    into out/reference and made again where the one there has another depth. A
    variant of the view's scene (`variant`, e.g. "mirrors_dark": without_mirrors) and
    a seed other than the references' are named in the file's name."""
    tag = re.sub(r"[^a-z0-9]+", "_", term)
    if variant:
        tag += "_" + variant
    if seed != refs.SEED:
        tag += f"_seed{seed}"
    base = os.path.join(refs.MADE, f"{view}_{tag}_{SIZE}_{spp}spp")
    depth = int(flags[flags.index("--max-depth") + 1])
    if not os.path.exists(base + ".exr") or refs.depth_of(base + ".exr") != depth:
        print(f"bench-terms: path tracing {view}, {term} ({spp} spp, seed {seed})", flush=True)
        refs.render(scene, extra, SIZE, spp, base, flags, seed=seed)
    return base


def without_mirrors(scene, out):
    """`scene`, or where it has mirrors (materials smoother than MIRROR_ROUGHNESS) a
    copy of it in out/mirrors-dark/ whose mirrors are black and diffuse; the copy's
    folder links the scene's other files (buffers, images)."""
    return regions.scene_copy(scene, out, ("mirrors",), tag="mirrors-dark")


def row(cells):
    return "| " + " | ".join(cells) + " |"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n".join(__doc__.splitlines()[1:]))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "bench-terms"))
    ap.add_argument("--view", action="append", choices=validation_set.names(),
                    help="only this view of the set (repeatable; default: every view)")
    ap.add_argument("--frames", type=int, default=64, help="rtgi frames (default 64)")
    ap.add_argument("--pt-spp", type=int, default=256,
                    help="path tracer samples per pixel (default 256)")
    ap.add_argument("--no-terms", action="store_true", help="only the leak pairs")
    ap.add_argument("--term", action="append", choices=[t[0] for t in TERMS],
                    help="only this term (repeatable; default: every term)")
    ap.add_argument("--no-leaks", action="store_true", help="only the terms")
    ap.add_argument("--seeds", type=int, choices=(1, 2), default=1,
                    help="2: each renderer renders a second seed too, and the rows give "
                    "the share of blocks off between its two seeds (default 1)")
    a = ap.parse_args(argv)
    if not os.path.exists(voxgi()):
        raise SystemExit("bench-terms: error: build/voxgi missing (tools/build)")
    runs = os.path.join(a.out, "runs")
    os.makedirs(runs, exist_ok=True)
    lines = []
    if not a.no_terms:
        header = ["view", "term", "rtgi ms", "FLIP", "mean ratio", "worst blocks (min, max)",
                  "blocks off > 3%"]
        if a.seeds == 2:
            header += ["rtgi seed to seed", "path tracer seed to seed"]
        lines += [f"rtgi, {a.frames} frames, --denoise off, seed {SEED}, against the path tracer "
                  f"at {a.pt_spp} spp and the matching depth ({SIZE}); the terms without "
                  "specular with the scene's mirrors black:", "",
                  row(header), "|---|---|---:|---:|---:|---|" + "---:|" * (len(header) - 6)]
        for view, scene, extra in validation_set.views(a.view, make=False):
            for term, rtgi_flags, pt_flags in [t for t in TERMS if t[0] in (a.term or [t[0]])]:
                shown = without_mirrors(scene, a.out) if "-specular" in " ".join(rtgi_flags) \
                    else scene
                tag = re.sub(r"[^a-z0-9]+", "_", f"{view}_{term}")
                base = os.path.join(runs, tag)
                flags = extra + rtgi_flags + ["--frames", str(a.frames), "--denoise", "off"]
                stats = render(shown, flags + ["--seed", str(SEED)], base)
                variant = "mirrors_dark" if shown != scene else ""
                ref = pathtraced(view, term, shown, extra, pt_flags, a.pt_spp, variant=variant)
                m = compare(base, ref)
                cells = [view, term, f"{stats['total_ms']:.0f}", f"{m['flip']:.4f}",
                         f"{m['mean_luminance_ratio']:.3f}",
                         f"{m['block_ratio_min']:.2f}, {m['block_ratio_max']:.2f}",
                         f"{100 * m['blocks_off_3_percent']:.0f}%"]
                if a.seeds == 2:
                    render(shown, flags + ["--seed", str(SEED + 1)], base + "_seed2")
                    ref2 = pathtraced(view, term, shown, extra, pt_flags, a.pt_spp,
                                      seed=refs.SEED + 1, variant=variant)
                    for x, y in ((base + "_seed2", base), (ref2, ref)):
                        off = metrics.compare(x + ".exr", y + ".exr", blocks=16)
                        cells.append(f"{100 * off['blocks_off_3_percent']:.0f}%")
                lines.append(row(cells))
                print(lines[-1], flush=True)
        lines.append("")
    if not a.no_leaks:
        lines += ["Leaks: the sealed room with the light beyond its wall on against off, "
                  "block by block (16x16); 1.00 is no leak:", "",
                  row(["view", "renderer", "mean ratio", "worst blocks (min, max)",
                       "blocks off > 10%"]), "|---|---|---:|---|---:|"]
        chosen = set(a.view or validation_set.names())
        for pair in validation_set.load().get("leaks", []):
            for view in pair["views"]:
                if view not in chosen:
                    continue
                entry = next(e for e in validation_set.load()["views"] if e["view"] == view)
                extra = validation_set.camera_flags(entry)
                for renderer, flags in (
                        (f"rtgi, {a.frames} frames", ["--frames", str(a.frames)]),
                        (f"pathtrace, {a.pt_spp} spp",
                         ["--mode", "pathtrace", "--spp", str(a.pt_spp), "--max-depth",
                          str(refs.DEPTH)])):
                    bases = []
                    for side in ("lit", "dark"):
                        tag = re.sub(r"[^a-z0-9]+", "_", f"leak_{view}_{renderer}_{side}")
                        bases.append(os.path.join(runs, tag))
                        render(os.path.join(ROOT, pair[side]),
                               extra + flags + ["--seed", str(SEED)], bases[-1])
                    m = compare(bases[0], bases[1])
                    lines.append(row([view, renderer, f"{m['mean_luminance_ratio']:.3f}",
                                      f"{m['block_ratio_min']:.2f}, {m['block_ratio_max']:.2f}",
                                      f"{100 * m['blocks_off_10_percent']:.0f}%"]))
                    print(lines[-1], flush=True)
    table = "\n".join(lines) + "\n"
    with open(os.path.join(a.out, "table.md"), "w") as f:
        f.write(table)
    print(table)
    print("bench-terms: wrote", os.path.join(a.out, "table.md"))


if __name__ == "__main__":
    sys.exit(main())
