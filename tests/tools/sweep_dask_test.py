#!/usr/bin/env python3
"""tools/sweep on a two-worker Dask LocalCluster: a grid of three tiny renders (two
compared with a reference) and one row that fails (an option voxgi refuses). The
finished rows must reach sweep.csv with their metrics, the failed row must be
reported with its parameters and retried exactly once, and the sweep must exit 1.
Usage: sweep_dask_test.py VOXGI. Exit 77 (skipped) where .venv lacks dask, or 1 with
VOXGI_REQUIRE_TOOLS=1 (tools/test), where the skip would hide a missing set-up."""
import csv
import json
import os
import subprocess
import sys
import tempfile
import time

from tool_support import ROOT, fail

PY = os.path.join(ROOT, ".venv", "bin", "python")
BAD = ["--frames", "2", "--bounces", "17"]


def main():
    voxgi = os.path.abspath(sys.argv[1])
    if not os.path.exists(PY) or subprocess.run(
            [PY, "-c", "import dask.distributed, flip_evaluator, matplotlib"],
            capture_output=True).returncode != 0:
        why = ".venv with dask[distributed], flip-evaluator and matplotlib missing (run tools/setup)"
        if os.environ.get("VOXGI_REQUIRE_TOOLS") == "1":
            fail(why + "; VOXGI_REQUIRE_TOOLS=1 forbids the skip")
        print("SKIP: " + why)
        sys.exit(77)
    start = time.time()
    with tempfile.TemporaryDirectory(prefix="voxgi-sweep-dask-") as tmp:
        ref = os.path.join(tmp, "ref.exr")
        subprocess.run([voxgi, "render", os.path.join(ROOT, "scenes", "cornell_room",
                                                       "cornell_room.gltf"),
                        "--mode", "pathtrace", "--size", "32x32", "--spp", "4", "--no-progress",
                        "--out", ref, "--out", ref[:-4] + ".png", "-q"], check=True)
        # The failing row first: its retry overlaps the other renders.
        points = [
            {"scene": "cornell_room", "mode": "rtgi", "size": "32x32", "params": BAD,
             "reference": ref},
            {"scene": "cornell_room", "mode": "raster", "size": "32x32",
             "params": ["--frames", "2"], "reference": ref},
            {"scene": "cornell_room", "mode": "pathtrace", "size": "32x32",
             "params": ["--spp", "1", "--no-progress"], "reference": ref},
            {"scene": "dark_plane", "mode": "raster", "size": "32x32",
             "params": ["--frames", "2"]},
        ]
        grid = os.path.join(tmp, "grid.json")
        with open(grid, "w") as f:
            json.dump(points, f)
        out = os.path.join(tmp, "out")
        p = subprocess.run([os.path.join(ROOT, "tools", "sweep"), "--grid", grid,
                            "--voxgi", voxgi, "--workers", "2", "--out", out],
                           capture_output=True, text=True, timeout=240)
        log = p.stdout + p.stderr
        print(log)
        if p.returncode != 1:
            fail(f"sweep exited {p.returncode}, expected 1 (one task failed)")
        if "local cluster of 2 workers" not in log:
            fail("no two-worker local cluster")
        with open(os.path.join(out, "sweep.csv")) as f:
            rows = list(csv.DictReader(f))
        got = [(r["scene"], r["mode"], r["params"]) for r in rows]
        want = [(pt["scene"], pt["mode"], " ".join(pt["params"])) for pt in points
                if pt["params"] is not BAD]
        if got != want:
            fail(f"sweep.csv rows {got}, expected {want}")
        for r in rows:
            if (r["width"], r["height"]) != ("32", "32") or float(r["frame_ms"]) <= 0:
                fail(f"row {r['scene']} {r['mode']}: size {r['width']}x{r['height']}, "
                     f"frame_ms {r['frame_ms']}")
            compared = r["scene"] == "cornell_room"
            for k in ("rmse", "flip"):
                if (r[k] != "") != compared:
                    fail(f"row {r['scene']} {r['mode']}: {k} {r[k]!r}")
        with open(os.path.join(out, "failed.csv")) as f:
            failed = list(csv.DictReader(f))
        if len(failed) != 1:
            fail(f"failed.csv has {len(failed)} rows, expected 1")
        f0 = failed[0]
        if (f0["task"], f0["scene"], f0["mode"], f0["size"], f0["params"], f0["attempts"]) != \
                ("0", "cornell_room", "rtgi", "32x32", " ".join(BAD), "2"):
            fail(f"failed.csv row {f0}")
        if "--bounces" not in f0["error"]:
            fail(f"failed.csv error does not say why: {f0['error']!r}")
        row = f"cornell_room rtgi 32x32 {' '.join(BAD)}"
        retries = [ln for ln in log.splitlines() if "retrying once" in ln]
        finals = [ln for ln in log.splitlines() if "FAILED after 2 attempts" in ln]
        if len(retries) != 1 or row not in retries[0]:
            fail(f"expected one retry of '{row}', got {retries}")
        if len(finals) != 1 or row not in finals[0]:
            fail(f"expected one final failure of '{row}', got {finals}")
        if len([ln for ln in log.splitlines() if ln.lstrip().startswith("[")]) != 4:
            fail("expected one progress line per task")
    print(f"PASS in {time.time() - start:.0f} s")


if __name__ == "__main__":
    main()
