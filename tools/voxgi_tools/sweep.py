"""What accuracy costs in time: a grid of render settings on both reference scenes.

For every mode that `voxgi render --help` offers, renders each grid point, records
per-stage times (the stats JSON), and measures the error against a high-spp
path-traced reference (`voxgi compare --json`: RMSE, relMSE, PSNR, SSIM, mean
luminance ratio; tools/flip: FLIP on sRGB 8-bit). Writes under --out:
  sweep.csv                one row per render
  tables.md                spp -> time, RMSE, FLIP; render mode -> average frame time
  error_vs_time_SCENE.png  RMSE against frame time per mode, with each mode's Pareto front
  time_vs_spp.png          path tracer frame time against spp, and against pixels
References are the highest-spp ones in tests/data/reference/ or out/reference/
(voxgi_tools.reference); a missing one is rendered first (--quick: 128 spp,
otherwise 2048 spp).

The grid runs as Dask tasks, each one render plus its comparison: on a LocalCluster
of --workers processes here (default 1, one thread each), or with --scheduler
tcp://HOST:PORT on a cluster whose workers have this checkout (built voxgi, .venv,
out/reference/) at --worker-root. A failed task is reported with its row and
retried once; the rows that finished are kept (sweep.csv), the failed ones listed in
failed.csv, and the exit status is 1. docs/study.md says how to start a cluster.

`tools/sweep tables [--check] [FILE...]` rewrites the tables between
`<!-- begin sweep-table ... -->` and `<!-- end sweep-table ... -->` markers in
README.md, docs/study.md and docs/measurements.md (or FILEs) from the CSV each
marker names; --check only reports the blocks that differ (exit 1).
"""
import argparse
import csv
import json
import os
import re
import socket
import subprocess
import sys
import time

from voxgi_tools import ROOT, scene_path, voxgi
from voxgi_tools import reference as references

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
                      ("--no-jitter", [""]), ("--denoise", ["off"]), ("--indirect", ["cones"]),
                      ("--voxel-rays", [""])]},
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


def offered(binary):
    """Modes and flags that `voxgi render --help` lists."""
    text = subprocess.run([binary, "render", "--help"], capture_output=True, text=True,
                          check=True).stdout
    m = re.search(r"--mode M\s+render mode: ([a-z, ]+)", text)
    modes = [x.strip() for x in m.group(1).split(",")] if m else ["raster"]
    flags = set(re.findall(r"(--[a-z][a-z-]*)", text))
    return modes, flags


def reference(scene, quick):
    """(exr, png, spp) of the scene's reference at REF_SIZE, rendered if missing."""
    return references.get(scene, scene_path(scene), [], REF_SIZE, 128 if quick else 2048)


def _parent_death_signal():
    """prctl(PR_SET_PDEATHSIG, SIGTERM), looked up before any fork: what runs between
    fork and exec in a threaded worker must not load libraries."""
    try:
        import ctypes
        prctl = ctypes.CDLL(None, use_errno=True).prctl
        return lambda: prctl(1, 15)
    except (OSError, AttributeError):
        return None


def run_tool(cmd):
    """Runs cmd; a non-zero exit raises with the tail of what it printed. The child
    gets SIGTERM when the worker thread waiting for it dies (Ctrl-C, a closed
    cluster), so no voxgi outlives the sweep."""
    p = subprocess.run(cmd, capture_output=True, text=True, preexec_fn=_parent_death_signal())
    if p.returncode != 0:
        tail = " / ".join((p.stderr or p.stdout).strip().splitlines()[-3:])
        raise RuntimeError(f"{os.path.basename(cmd[0])} {cmd[1]} exited {p.returncode}: {tail}")
    return p.stdout


def task_row(t):
    """One task of the grid, run on a Dask worker: the render, then its comparison
    with the reference. Paths in t are the worker's. Returns (index, row, where)."""
    tools = os.path.join(t["root"], "tools")
    if tools not in sys.path:
        sys.path.insert(0, tools)
    from voxgi_tools import metrics

    base = os.path.join(t["out"], "runs", f"{t['scene_name']}_{t['mode']}_{t['size']}_{t['tag']}")
    os.makedirs(os.path.dirname(base), exist_ok=True)
    run_tool([t["voxgi"], "render", t["scene"], "--mode", t["mode"], "--size", t["size"],
              "--out", base + ".exr", "--out", base + ".png", "--stats", base + ".json", "-q"]
             + t["extra"])
    with open(base + ".json") as f:
        stats = json.load(f)
    row = {"scene": t["scene_name"], "mode": t["mode"], "reference_spp": t["ref_spp"],
           "width": stats["size"]["width"],
           "height": stats["size"]["height"], "params": " ".join(t["extra"]),
           "spp": stats.get("spp", ""), "frame_ms": stats["frame_ms"],
           "total_ms": stats["total_ms"], "frames": stats["frames"],
           "startup_ms": stats["startup_ms"],
           "samples_per_second": stats.get("samples_per_second", "")}
    for k, v in stats["stages"].items():
        row[f"stage_{k}_ms"] = v
    for k, v in stats.get("startup_stages", {}).items():
        row[f"startup_{k}_ms"] = v
    for k in METRICS:
        row[k] = ""
    if t["ref_exr"]:
        m = json.loads(run_tool([t["voxgi"], "compare", base + ".exr", t["ref_exr"], "--json"]))
        m["flip"] = metrics.flip(base + ".png", t["ref_png"])
        for k in METRICS:
            row[k] = m[k] if m[k] is not None else ""
    return t["index"], row, f"{socket.gethostname()}:{os.getpid()}"


METRICS = ("rmse", "rel_mse", "psnr", "ssim", "mean_luminance_ratio", "flip")


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


def at_ref_size(r):
    return f"{r['width']}x{r['height']}" == REF_SIZE


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
                   if r["scene"] == scene and r["mode"] == mode and r["rmse"] != ""
                   and at_ref_size(r)]
            if not pts:
                continue
            line = ax.scatter(*zip(*pts), label=mode, s=18)
            front = pareto(pts)
            ax.plot(*zip(*front), color=line.get_facecolor()[0], lw=1)
            if mode == "pathtrace":
                for r in rows:
                    if r["scene"] == scene and r["mode"] == mode and r["rmse"] != "" \
                            and at_ref_size(r):
                        ax.annotate(str(r["spp"]), (float(r["frame_ms"]), float(r["rmse"])),
                                    fontsize=6, xytext=(2, 2), textcoords="offset points")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("time to the image (ms, wall clock; rtgi: all its frames)")
        ax.set_ylabel("RMSE vs path-traced reference (linear)")
        ax.set_title(f"{scene} {REF_SIZE}: error against time\n(lines: each mode's Pareto front)",
                     fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
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
        if a.get_legend_handles_labels()[0]:
            a.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "time_vs_spp.png"))
    plt.close(fig)


def spp_table(rows, scene):
    """The path tracer at REF_SIZE on one scene: spp -> time, RMSE, FLIP."""
    pt = sorted((r for r in rows if r["scene"] == scene and r["mode"] == "pathtrace"
                 and r["rmse"] != "" and at_ref_size(r)), key=lambda r: int(r["spp"]))
    lines = ["| spp | time (ms) | RMSE | FLIP |", "|---:|---:|---:|---:|"]
    for r in pt:
        lines.append(f"| {r['spp']} | {float(r['frame_ms']):.0f} | {float(r['rmse']):.4f} | "
                     f"{float(r['flip']):.4f} |")
    return lines if pt else []


def rtgi_table(rows, scene):
    """rtgi at REF_SIZE on one scene, one row per grid point in sweep order."""
    sel = [r for r in rows if r["scene"] == scene and r["mode"] == "rtgi" and
           f"{r['width']}x{r['height']}" == REF_SIZE and r.get("rel_mse", "") != ""]
    lines = ["| setting | frame ms | time to the image (ms) | relMSE | FLIP |",
             "|---|---:|---:|---:|---:|"]
    for r in sel:
        lines.append(f"| `{r['params']}` | {float(r['frame_ms']):.1f} | "
                     f"{float(r['total_ms']):.0f} | {float(r['rel_mse']):.4f} | "
                     f"{float(r['flip']):.4f} |")
    return lines if sel else []


def mode_table(rows):
    """Render mode -> average frame time at REF_SIZE (the voxel paper's table)."""
    lines = ["| render mode | " + " | ".join(f"{s} {REF_SIZE} frame ms" for s in SCENES) + " |",
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
    return lines


# The README's summary: (label, mode, params of the grid point; None: the mean over
# the mode's points at REF_SIZE, frame time only).
SUMMARY = [
    ("raster", "raster", "--frames 5"),
    ("points (mean over its grid points)", "points", None),
    ("dvr (mean over its grid points)", "dvr", None),
    ("rtgi, 1 frame", "rtgi", "--frames 1"),
    ("rtgi, 16 frames", "rtgi", "--frames 16"),
    ("rtgi, 64 frames (the default)", "rtgi", "--frames 64"),
    ("rtgi, 256 frames", "rtgi", "--frames 256"),
    ("rtgi, 64 frames, `--denoise off`", "rtgi", "--denoise off"),
    ("rtgi, 64 frames, `--indirect cones`", "rtgi", "--indirect cones"),
    ("rtgi, 64 frames, `--voxel-rays`", "rtgi", "--voxel-rays"),
    ("rtgi, 64 frames, `--interleave 16`", "rtgi", "--interleave 16"),
] + [(f"pathtrace, {n} spp", "pathtrace", f"--spp {n} --seed {SEED} --no-progress")
     for n in (1, 16, 256, 1024, 4096)]


def summary_table(rows):
    """One row per SUMMARY setting, both scenes: time to the image, RMSE, FLIP."""
    head = "| setting, " + REF_SIZE + " | " + " | ".join(
        f"{s}: time (ms) | {s}: RMSE | {s}: FLIP" for s in SCENES) + " |"
    lines = [head, "|---|" + "---:|---:|---:|" * len(SCENES)]
    for label, mode, params in SUMMARY:
        cells, found = [], False
        for scene in SCENES:
            sel = [r for r in rows if r["scene"] == scene and r["mode"] == mode and
                   at_ref_size(r) and (params is None or r["params"] == params)]
            if not sel:
                cells += ["-", "-", "-"]
                continue
            found = True
            if params is None:
                ms = sum(float(r["frame_ms"]) for r in sel) / len(sel)
                cells += [f"{ms:.1f}", "-", "-"]
                continue
            r = sel[0]
            err = [f"{float(r[k]):.4f}" if r[k] != "" else "-" for k in ("rmse", "flip")]
            cells += [f"{image_ms(r):.0f}"] + err
        if found:
            lines.append(f"| {label} | " + " | ".join(cells) + " |")
    return lines


def tables(rows, refs, outdir):
    lines = []
    for scene in SCENES:
        spp = spp_table(rows, scene)
        if spp:
            lines += [f"**{scene}**, {REF_SIZE}, against a {refs[scene]}-spp reference", ""]
            lines += spp + [""]
    lines += mode_table(rows) + [""] + summary_table(rows)
    for scene in SCENES:
        rt = rtgi_table(rows, scene)
        if rt:
            lines += ["", f"**{scene}**, rtgi at {REF_SIZE}, against a {refs[scene]}-spp "
                      "reference", ""] + rt
    text = "\n".join(lines) + "\n"
    with open(os.path.join(outdir, "tables.md"), "w") as f:
        f.write(text)
    return text


# The documents' generated tables: each block names what it shows and the CSV it
# is made from (relative to the checkout), and `tools/sweep tables` rewrites it.
BLOCK = re.compile(r"<!-- begin sweep-table (\S+) from (\S+) -->\n.*?"
                   r"<!-- end sweep-table \1 -->", re.S)
DOCS = ["README.md", "docs/study.md", "docs/measurements.md"]


def block_text(name, rows):
    kind, _, scene = name.partition(":")
    if kind == "pathtrace-spp" and scene in SCENES:
        lines = spp_table(rows, scene)
    elif kind == "rtgi-knobs" and scene in SCENES:
        lines = rtgi_table(rows, scene)
    elif kind == "modes" and not scene:
        lines = mode_table(rows)
    elif kind == "summary" and not scene:
        lines = summary_table(rows)
    else:
        raise SystemExit(f"sweep tables: error: unknown table {name!r} (pathtrace-spp:SCENE, "
                         f"rtgi-knobs:SCENE, modes, summary; SCENE one of "
                         f"{', '.join(SCENES)})")
    if not lines:
        raise SystemExit(f"sweep tables: error: {name}: no rows for it in the CSV")
    return "\n".join(lines)


def tables_main(argv):
    ap = argparse.ArgumentParser(prog="tools/sweep tables",
                                 description="Rewrites the tables between sweep-table markers "
                                 "from the CSV each marker names.")
    ap.add_argument("files", nargs="*", help=f"documents (default: {' '.join(DOCS)})")
    ap.add_argument("--check", action="store_true",
                    help="change nothing; list the blocks that differ from their CSV, exit 1 "
                         "if any do")
    a = ap.parse_args(argv)
    files = a.files or [os.path.join(ROOT, d) for d in DOCS]
    csvs, stale, count = {}, [], 0
    for path in files:
        with open(path) as f:
            text = f.read()

        def regenerate(m):
            nonlocal count
            name, src = m.group(1), m.group(2)
            if src not in csvs:
                with open(os.path.join(ROOT, src)) as f:
                    csvs[src] = list(csv.DictReader(f))
            new = (f"<!-- begin sweep-table {name} from {src} -->\n\n"
                   f"{block_text(name, csvs[src])}\n\n<!-- end sweep-table {name} -->")
            count += 1
            if new != m.group(0):
                shown = os.path.relpath(path, ROOT) if path.startswith(ROOT + os.sep) else path
                stale.append(f"{shown}: {name} (from {src})")
            return new
        new_text = BLOCK.sub(regenerate, text)
        if not a.check and new_text != text:
            with open(path, "w") as f:
                f.write(new_text)
    for s in stale:
        print(f"sweep tables: {'differs from its CSV' if a.check else 'rewrote'}: {s}")
    print(f"sweep tables: {count} tables, {len(stale)} "
          f"{'differ' if a.check else 'rewritten'}")
    return 1 if a.check and stale else 0


def tasks_of_grid(a, modes, flags, spec, binary, root, out):
    """The sweep's own grid: (task, refs) for every scene, mode and point."""
    def here(path):
        # A path in this checkout, as the workers see it.
        return os.path.join(root, os.path.relpath(path, ROOT)) if path.startswith(ROOT) else path
    tasks, refs = [], {}
    for scene in a.scene or SCENES:
        ref_exr, ref_png, ref_spp = reference(scene, a.quick)
        refs[scene] = ref_spp
        for mode in [m for m in spec if m in modes and (not a.modes or m in a.modes)]:
            for size, extra, tag, spp in grid(mode, spec[mode], flags):
                if a.max_spp and spp != "" and spp > a.max_spp:
                    continue
                compare = size == REF_SIZE
                tasks.append({"scene_name": scene, "mode": mode, "size": size, "extra": extra,
                              "tag": tag, "ref_spp": ref_spp,
                              "scene": os.path.join(root, "scenes", scene, f"{scene}.gltf"),
                              "ref_exr": here(ref_exr) if compare else "",
                              "ref_png": here(ref_png) if compare else ""})
    for t in tasks:
        t.update(voxgi=binary, root=root, out=out)
    return tasks, refs


def tasks_of_file(path, binary, root, out):
    """A grid from a JSON file: a list of {"scene", "mode", "size", "params": [...],
    "reference": EXR (optional; its PNG beside it)}. scene is a name under scenes/ or
    a .gltf path."""
    with open(path) as f:
        points = json.load(f)
    tasks, refs = [], {}
    for n, p in enumerate(points):
        scene = p["scene"]
        name = os.path.splitext(os.path.basename(scene))[0]
        gltf = scene if scene.endswith((".gltf", ".glb")) else \
            os.path.join(root, "scenes", scene, f"{scene}.gltf")
        ref = p.get("reference", "")
        tasks.append({"scene_name": name, "mode": p["mode"], "size": p["size"],
                      "extra": [str(x) for x in p.get("params", [])], "tag": f"p{n}",
                      "ref_spp": p.get("reference_spp", ""), "scene": gltf,
                      "ref_exr": ref, "ref_png": ref[:-4] + ".png" if ref else "",
                      "voxgi": binary, "root": root, "out": out})
        refs[name] = p.get("reference_spp", "")
    return tasks, refs


def describe(t):
    return f"{t['scene_name']} {t['mode']} {t['size']} {' '.join(t['extra'])}".strip()


def run_grid(tasks, a):
    """Runs every task on Dask; each failed one once more. Returns the rows that
    finished, in grid order, the failures (task, attempts, error), and whether
    Ctrl-C stopped it (the tasks left are cancelled, the cluster closed)."""
    import logging
    try:
        from dask.distributed import Client, LocalCluster, as_completed
    except ImportError:
        raise SystemExit("sweep: error: dask.distributed missing from the venv (run tools/setup)")
    cluster = None
    if a.scheduler:
        client = Client(a.scheduler, timeout="30s")
        workers = len(client.scheduler_info()["workers"])
        print(f"sweep: {len(tasks)} tasks on {a.scheduler} ({workers} workers"
              f"{'; the tasks wait for one to join' if not workers else ''})", flush=True)
    else:
        # One thread a worker: each task is a voxgi process with its own GL context,
        # and llvmpipe already spreads one frame over every core.
        cluster = LocalCluster(n_workers=a.workers, threads_per_worker=1, processes=True,
                               dashboard_address=None, silence_logs=logging.CRITICAL)
        client = Client(cluster)
        print(f"sweep: {len(tasks)} tasks on a local cluster of {a.workers} "
              f"worker{'s' if a.workers != 1 else ''}", flush=True)
    rows, failures, pending, interrupted = {}, [], {}, False
    try:
        for t in tasks:
            pending[client.submit(task_row, t, pure=False)] = (t, 1)
        done = as_completed(list(pending))
        for fut in done:
            t, attempt = pending.pop(fut)
            if fut.status == "finished":
                index, row, where = fut.result()
                rows[index] = row
                rmse = row["rmse"] if row["rmse"] == "" else round(row["rmse"], 5)
                print(f"  [{len(rows) + len(failures)}/{len(tasks)}] {t['scene_name']:12s} "
                      f"{t['mode']:9s} {t['size']:9s} {' '.join(t['extra']):40s} "
                      f"{row['frame_ms']:9.1f} ms  rmse {rmse}  ({where})", flush=True)
                continue
            err = fut.exception() if fut.status == "error" else fut.status
            if attempt < 2:
                print(f"sweep: task {t['index']} failed ({describe(t)}): {err}; retrying once",
                      file=sys.stderr, flush=True)
                retry = client.submit(task_row, t, pure=False)
                pending[retry] = (t, attempt + 1)
                done.add(retry)
            else:
                failures.append((t, attempt, str(err)))
                print(f"  [{len(rows) + len(failures)}/{len(tasks)}] FAILED after {attempt} "
                      f"attempts: task {t['index']} ({describe(t)}): {err}",
                      file=sys.stderr, flush=True)
    except KeyboardInterrupt:
        print("sweep: interrupted; cancelling the tasks left", file=sys.stderr, flush=True)
        client.cancel(list(pending), force=True)
        interrupted = True
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    return [rows[i] for i in sorted(rows)], failures, interrupted


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["tables"]:
        return tables_main(argv[1:])
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
    ap.add_argument("--grid", metavar="JSON",
                    help="render these points instead of the sweep's grid (a list of "
                         '{"scene", "mode", "size", "params": [...], "reference": EXR})')
    ap.add_argument("--voxgi", default=voxgi(), help="the voxgi binary (default: build/voxgi)")
    ap.add_argument("--workers", type=int, default=1,
                    help="worker processes of the local cluster (default 1: renders already "
                         "use every core)")
    ap.add_argument("--scheduler", metavar="tcp://HOST:PORT",
                    help="run the tasks on this Dask scheduler's workers instead")
    ap.add_argument("--worker-root", metavar="DIR",
                    help="with --scheduler: where the workers have this checkout (built "
                         "voxgi, .venv, out/reference/); default: the same path as here")
    a = ap.parse_args(argv)
    binary = os.path.abspath(a.voxgi)
    if not os.path.exists(binary):
        raise SystemExit(f"sweep: error: {binary} missing (tools/build)")
    out = os.path.abspath(a.out)
    os.makedirs(out, exist_ok=True)
    root = ROOT
    if a.scheduler and a.worker_root:
        root = a.worker_root
        binary = os.path.join(root, os.path.relpath(binary, ROOT)) \
            if binary.startswith(ROOT) else binary
        out = os.path.join(root, os.path.relpath(out, ROOT)) if out.startswith(ROOT) else out
    start = time.time()
    if a.grid:
        tasks, refs = tasks_of_file(a.grid, binary, root, out)
    else:
        modes, flags = offered(os.path.abspath(a.voxgi))
        spec = QUICK if a.quick else FULL
        print(f"sweep: modes offered: {', '.join(modes)}"
              f" (not offered, skipped: {', '.join(m for m in spec if m not in modes) or 'none'})")
        tasks, refs = tasks_of_grid(a, modes, flags, spec, binary, root, out)
    for i, t in enumerate(tasks):
        t["index"] = i
    kept = []
    old_csv = os.path.join(a.out, "sweep.csv")
    scenes = a.scene or SCENES
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
            refs.setdefault(r["scene"], int(r.get("reference_spp") or 0))
    rows, failures, interrupted = run_grid(tasks, a)
    rows = kept + rows
    keys = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    with open(os.path.join(a.out, "sweep.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    failed_csv = os.path.join(a.out, "failed.csv")
    if failures:
        with open(failed_csv, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["task", "scene", "mode", "size", "params", "attempts", "error"])
            for t, attempts, err in failures:
                w.writerow([t["index"], t["scene_name"], t["mode"], t["size"],
                            " ".join(t["extra"]), attempts, err])
    elif os.path.exists(failed_csv):
        os.remove(failed_csv)
    if interrupted:
        print(f"sweep: interrupted after {len(rows) - len(kept)} of {len(tasks)} tasks; the "
              "rows that finished are in sweep.csv", file=sys.stderr)
        sys.exit(130)
    wrote = "sweep.csv"
    if any(at_ref_size(r) for r in rows):
        plot(rows, a.out)
        print(tables(rows, refs, a.out))
        wrote += ", tables.md, error_vs_time_*.png, time_vs_spp.png"
    else:
        print(f"sweep: no rows at {REF_SIZE}: no tables or plots")
    print(f"sweep: {len(rows)} renders in {time.time() - start:.0f} s; wrote {a.out}/{wrote}")
    if failures:
        print(f"sweep: {len(failures)} of {len(tasks)} tasks failed twice, listed in "
              f"{failed_csv}; the {len(rows)} rows that finished are in sweep.csv",
              file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    sys.exit(main())
