"""What accuracy costs in time: a grid of render settings on both reference scenes.

For every mode that `voxgi render --help` offers, renders each grid point, records
per-stage times (the stats JSON), and measures the error against a high-spp
path-traced reference (`voxgi compare --json`: RMSE, relMSE, PSNR, SSIM, mean
luminance ratio; tools/flip: FLIP on sRGB 8-bit). Writes under --out:
  sweep.csv                one row per render
  tables.md                spp -> time, RMSE, FLIP; render mode -> average frame time
  error_vs_time_SCENE.png  RMSE against frame time per mode, with each mode's Pareto front
  time_vs_spp.png          path tracer frame time against spp, and against pixels
References live in out/reference/ (not in git); a missing one is rendered first by
tools/make-reference (--quick: 128 spp, otherwise 2048 spp).
"""
import argparse
import csv
import json
import os
import re
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tools"))
import flip as fliptool  # noqa: E402

SCENES = ["cornell_room", "dark_plane"]
REF_SIZE = "256x256"
SEED = 7  # test renders; the references use another seed

# Grid axes per mode: (flag, values). Axes whose flag the binary does not offer are
# skipped, so modes and knobs join the sweep as they land.
FULL = {
    "pathtrace": {"spp": [1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096],
                  "sizes": ["100x100", "256x256", "640x360", "1280x720", "1920x1080"],
                  "size_spp": 1},
    "raster": {"sizes": ["100x100", "256x256", "640x360", "1280x720", "1920x1080"]},
    "rtgi": {"axes": [("--frames", [1, 4, 16, 64, 256]), ("--voxels", [64, 128, 256]),
                      ("--bounces", [0, 1, 2, 3, "all"]), ("--interleave", [4, 16]),
                      ("--inject-rays", [16, 64]), ("--refine-rays", [0, 2]),
                      ("--no-jitter", [""])]},
    "points": {"axes": [("--voxels", [64, 128, 256, 512])]},
    "dvr": {"axes": [("--voxels", [64, 128, 256, 512])]},
}
QUICK = {
    "pathtrace": {"spp": [1, 2, 4, 8, 16], "sizes": ["100x100", "256x256"], "size_spp": 1},
    "raster": {"sizes": ["100x100", "256x256"]},
    "rtgi": {"axes": [("--voxels", [64, 128]), ("--frames", [4, 16])]},
    "points": {"axes": [("--voxels", [64, 128])]},
    "dvr": {"axes": [("--voxels", [64, 128])]},
}


def voxgi():
    return os.path.join(ROOT, "build", "voxgi")


def offered():
    """Modes and flags that `voxgi render --help` lists."""
    text = subprocess.run([voxgi(), "render", "--help"], capture_output=True, text=True,
                          check=True).stdout
    m = re.search(r"--mode M\s+render mode: ([a-z, ]+)", text)
    modes = [x.strip() for x in m.group(1).split(",")] if m else ["raster"]
    flags = set(re.findall(r"(--[a-z][a-z-]*)", text))
    return modes, flags


def reference(scene, quick):
    os.makedirs(os.path.join(ROOT, "out", "reference"), exist_ok=True)
    best = None
    for name in os.listdir(os.path.join(ROOT, "out", "reference")):
        m = re.fullmatch(rf"{scene}_{REF_SIZE}_(\d+)spp\.exr", name)
        if m and (best is None or int(m.group(1)) > best[0]):
            best = (int(m.group(1)), name)
    if best is None:
        spp = "128" if quick else "2048"
        subprocess.run([os.path.join(ROOT, "tools", "make-reference"), spp, REF_SIZE, scene],
                       check=True)
        best = (int(spp), f"{scene}_{REF_SIZE}_{spp}spp.exr")
    exr = os.path.join(ROOT, "out", "reference", best[1])
    return exr, exr[:-4] + ".png", best[0]


def render(scene, mode, size, extra, outdir, tag):
    base = os.path.join(outdir, "runs", f"{scene}_{mode}_{size}_{tag}")
    os.makedirs(os.path.dirname(base), exist_ok=True)
    cmd = [voxgi(), "render", os.path.join(ROOT, "scenes", scene, f"{scene}.gltf"),
           "--mode", mode, "--size", size, "--out", base + ".exr", "--out", base + ".png",
           "--stats", base + ".json", "-q"] + extra
    subprocess.run(cmd, check=True)
    with open(base + ".json") as f:
        return base, json.load(f)


def metrics(base, ref_exr, ref_png):
    out = subprocess.run([voxgi(), "compare", base + ".exr", ref_exr, "--json"],
                         capture_output=True, text=True, check=True).stdout
    m = json.loads(out)
    m["flip"] = fliptool.flip(base + ".png", ref_png)
    return m


def grid(mode, spec, flags):
    """(size, extra args, tag, spp) for each point of the grid."""
    points = []
    if mode == "pathtrace":
        for spp in spec["spp"]:
            points.append((REF_SIZE, ["--spp", str(spp), "--seed", str(SEED), "--no-progress"],
                           f"spp{spp}", spp))
        for size in spec["sizes"]:
            if size == REF_SIZE:
                continue
            s = spec["size_spp"]
            points.append((size, ["--spp", str(s), "--seed", str(SEED), "--no-progress"],
                           f"spp{s}", s))
    elif mode == "raster":
        for size in spec["sizes"]:
            points.append((size, ["--frames", "5"], "f5", ""))
    else:
        axes = [(flag, vals) for flag, vals in spec.get("axes", []) if flag in flags]
        if not axes:
            points.append((REF_SIZE, ["--frames", "5"], "default", ""))
        # One axis at a time around the binary's defaults (a full product is too big).
        # rtgi accumulates its frames into one image (its default count unless the
        # axis is --frames); the other modes render --frames 5 for a median.
        frames = [] if mode == "rtgi" else ["--frames", "5"]
        for flag, vals in axes:
            for v in vals:
                # A switch (value ""): the flag alone.
                extra = [flag] + ([str(v)] if v != "" else []) + ([] if flag == "--frames" else frames)
                points.append((REF_SIZE, extra, f"{flag.strip('-')}{v}", ""))
    return points


def pareto(points):
    """The points no other point beats in both time and error."""
    front, best = [], float("inf")
    for t, e in sorted(points):
        if e < best:
            front.append((t, e))
            best = e
    return front


def image_ms(r):
    """Time to make the image: rtgi accumulates all its frames into it."""
    return float(r["total_ms"]) if r["mode"] == "rtgi" else float(r["frame_ms"])


def plot(rows, outdir):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    for scene in SCENES:
        fig, ax = plt.subplots(figsize=(6, 4.2), dpi=100)
        for mode in sorted({r["mode"] for r in rows}):
            pts = [(image_ms(r), float(r["rmse"])) for r in rows
                   if r["scene"] == scene and r["mode"] == mode and r["rmse"] != ""]
            if not pts:
                continue
            line = ax.scatter(*zip(*pts), label=mode, s=18)
            front = pareto(pts)
            ax.plot(*zip(*front), color=line.get_facecolor()[0], lw=1)
            if mode == "pathtrace":
                for r in rows:
                    if r["scene"] == scene and r["mode"] == mode and r["rmse"] != "":
                        ax.annotate(str(r["spp"]), (float(r["frame_ms"]), float(r["rmse"])),
                                    fontsize=6, xytext=(2, 2), textcoords="offset points")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("time to the image (ms, wall clock; rtgi: all its frames)")
        ax.set_ylabel("RMSE vs path-traced reference (linear)")
        ax.set_title(f"{scene} {REF_SIZE}: error against time\n(lines: each mode's Pareto front)",
                     fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(outdir, f"error_vs_time_{scene}.png"))
        plt.close(fig)

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9, 3.8), dpi=100)
    for scene in SCENES:
        pt = [r for r in rows if r["scene"] == scene and r["mode"] == "pathtrace"]
        spp = sorted((int(r["spp"]), float(r["frame_ms"])) for r in pt
                     if f"{r['width']}x{r['height']}" == REF_SIZE)
        if spp:
            a1.plot(*zip(*spp), marker="o", ms=3, label=scene)
        px = sorted((int(r["width"]) * int(r["height"]), float(r["frame_ms"]) / int(r["spp"]))
                    for r in pt if f"{r['width']}x{r['height']}" != REF_SIZE or
                    int(r["spp"]) == min(int(x["spp"]) for x in pt))
        if px:
            a2.plot(*zip(*px), marker="o", ms=3, label=scene)
    a1.set(xscale="log", yscale="log", xlabel="samples per pixel", ylabel="frame time (ms)",
           title=f"path tracer, {REF_SIZE}")
    a2.set(xscale="log", yscale="log", xlabel="pixels", ylabel="ms per spp",
           title="path tracer, time per spp against pixels")
    for a in (a1, a2):
        a.grid(True, which="both", alpha=0.3)
        a.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "time_vs_spp.png"))
    plt.close(fig)


def tables(rows, refs, outdir):
    lines = []
    for scene in SCENES:
        pt = sorted((r for r in rows if r["scene"] == scene and r["mode"] == "pathtrace"
                     and r["rmse"] != ""), key=lambda r: int(r["spp"]))
        if not pt:
            continue
        lines += [f"**{scene}**, {REF_SIZE}, against a {refs[scene]}-spp reference", "",
                  "| spp | time (ms) | RMSE | FLIP |", "|---:|---:|---:|---:|"]
        for r in pt:
            lines.append(f"| {r['spp']} | {float(r['frame_ms']):.0f} | {float(r['rmse']):.4f} | "
                         f"{float(r['flip']):.4f} |")
        lines.append("")
    lines += ["| render mode | " + " | ".join(f"{s} {REF_SIZE} frame ms" for s in SCENES) + " |",
              "|---|" + "---:|" * len(SCENES)]
    modes = sorted({r["mode"] for r in rows}, key=lambda m: (m != "raster", m == "pathtrace", m))
    for mode in modes:
        cells = []
        for scene in SCENES:
            sel = [r for r in rows if r["scene"] == scene and r["mode"] == mode and
                   f"{r['width']}x{r['height']}" == REF_SIZE]
            if mode == "pathtrace":
                sel = [r for r in sel if int(r["spp"]) == 1]
            cells.append(f"{sum(float(r['frame_ms']) for r in sel) / len(sel):.1f}" if sel
                         else "-")
        name = "pathtrace 1 spp" if mode == "pathtrace" else mode
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    text = "\n".join(lines) + "\n"
    with open(os.path.join(outdir, "tables.md"), "w") as f:
        f.write(text)
    return text


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n".join(__doc__.splitlines()[1:]))
    ap.add_argument("--quick", action="store_true", help="the CI grid (under 5 minutes)")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "sweep"))
    ap.add_argument("--scene", action="append", choices=SCENES,
                    help="only this scene (repeatable); the other scene's rows are kept "
                         "from an earlier sweep.csv in --out")
    ap.add_argument("--mode", action="append", dest="modes",
                    help="only this mode (repeatable); other modes' rows are kept from an "
                         "earlier sweep.csv in --out")
    ap.add_argument("--max-spp", type=int, default=None,
                    help="drop path tracer points above this spp (time-boxed runs)")
    a = ap.parse_args()
    if not os.path.exists(voxgi()):
        raise SystemExit("sweep: error: build/voxgi missing (tools/build)")
    os.makedirs(a.out, exist_ok=True)
    modes, flags = offered()
    spec = QUICK if a.quick else FULL
    print(f"sweep: modes offered: {', '.join(modes)}"
          f" (not offered, skipped: {', '.join(m for m in spec if m not in modes) or 'none'})")
    start = time.time()
    rows, refs = [], {}
    scenes = a.scene or SCENES
    kept = []
    old_csv = os.path.join(a.out, "sweep.csv")
    if (a.scene or a.modes) and os.path.exists(old_csv):
        with open(old_csv) as f:
            kept = [r for r in csv.DictReader(f)
                    if r["scene"] not in scenes or (a.modes and r["mode"] not in a.modes)]
        for r in kept:
            for k, v in r.items():
                if v not in ("", None):
                    try:
                        r[k] = float(v) if k not in ("scene", "mode", "params") else v
                    except ValueError:
                        pass
            if r.get("spp") not in ("", None):
                r["spp"] = int(r["spp"])
            for k in ("width", "height"):
                r[k] = int(r[k])
            if r.get("total_ms") in ("", None):
                r["total_ms"] = r["frame_ms"]
            refs[r["scene"]] = int(r.get("reference_spp") or 0)
    for scene in scenes:
        ref_exr, ref_png, ref_spp = reference(scene, a.quick)
        refs[scene] = ref_spp
        for mode in [m for m in spec if m in modes and (not a.modes or m in a.modes)]:
            for size, extra, tag, spp in grid(mode, spec[mode], flags):
                if a.max_spp and spp != "" and spp > a.max_spp:
                    continue
                base, stats = render(scene, mode, size, extra, a.out, tag)
                row = {"scene": scene, "mode": mode, "reference_spp": ref_spp,
                       "width": stats["size"]["width"],
                       "height": stats["size"]["height"], "params": " ".join(extra),
                       "spp": stats.get("spp", ""), "frame_ms": stats["frame_ms"],
                       "total_ms": stats["total_ms"], "frames": stats["frames"],
                       "startup_ms": stats["startup_ms"],
                       "samples_per_second": stats.get("samples_per_second", "")}
                for k, v in stats["stages"].items():
                    row[f"stage_{k}_ms"] = v
                for k, v in stats.get("startup_stages", {}).items():
                    row[f"startup_{k}_ms"] = v
                for k in ("rmse", "rel_mse", "psnr", "ssim", "mean_luminance_ratio", "flip"):
                    row[k] = ""
                if size == REF_SIZE:
                    m = metrics(base, ref_exr, ref_png)
                    for k in ("rmse", "rel_mse", "psnr", "ssim", "mean_luminance_ratio", "flip"):
                        row[k] = m[k] if m[k] is not None else ""
                rows.append(row)
                print(f"  {scene:12s} {mode:9s} {size:9s} {' '.join(extra):40s} "
                      f"{stats['frame_ms']:9.1f} ms  rmse {row['rmse'] if row['rmse'] == '' else round(row['rmse'], 5)}",
                      flush=True)
    rows = kept + rows
    keys = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    with open(os.path.join(a.out, "sweep.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    plot(rows, a.out)
    print(tables(rows, refs, a.out))
    print(f"sweep: {len(rows)} renders in {time.time() - start:.0f} s; wrote {a.out}/sweep.csv, "
          "tables.md, error_vs_time_*.png, time_vs_spp.png")


if __name__ == "__main__":
    main()
