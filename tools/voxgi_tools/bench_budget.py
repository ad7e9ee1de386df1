"""The frame budget: does the viewer's controller hold its target, and does the work
mask spend the budget where it pays?

On cornell_room at 640x360 with 1 bounce:
  1. `voxgi render --target-fps FPS --frames 350`: the median frame time of frames
     50..349 against 1000/FPS;
  2. the same target, as many frames as fit in 1 s of frame time, selecting the
     budget's pixels by the work mask and uniformly at random: relMSE and RMSE
     against a path-traced reference at 640x360 (voxgi_tools.reference, rendered
     once into out/reference), and the frames' mean traced share (their cost).
Writes out/bench-budget/ (the images, the mask, the stats) and prints the figures.
"""
import argparse
import json
import os
import statistics
import subprocess

from voxgi_tools import ROOT, metrics, scene_path, voxgi
from voxgi_tools import reference as refs

SIZE = "640x360"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n".join(__doc__.splitlines()[1:]))
    ap.add_argument("fps", nargs="?", type=float, default=8.0,
                    help="the frame budget's target (default %(default)g)")
    ap.add_argument("ref_spp", nargs="?", type=int, default=256,
                    help="spp of the reference when one is rendered (default %(default)s)")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "bench-budget"))
    a = ap.parse_args(argv)
    if not os.path.exists(voxgi()):
        raise SystemExit("bench-budget: error: build/voxgi missing (tools/build)")
    os.makedirs(a.out, exist_ok=True)
    print("load: " + " ".join(f"{x:.2f}" for x in os.getloadavg()), flush=True)
    scene = scene_path("cornell_room")
    ref_exr, _, _ = refs.get("cornell_room", scene, [], SIZE, a.ref_spp)
    common = [voxgi(), "render", scene, "--size", SIZE, "--bounces", "1", "--target-fps",
              f"{a.fps:g}", "-q"]

    hold = os.path.join(a.out, "hold.json")
    subprocess.run(common + ["--frames", "350", "--stats", hold], check=True)
    with open(hold) as f:
        h = json.load(f)["budget"]
    settled = h["frame_ms_each"][50:]
    med, target = statistics.median(settled), 1000.0 / a.fps
    print(f"hold: target {target:.1f} ms, median of frames 50..{len(h['frame_ms_each']) - 1}: "
          f"{med:.1f} ms ({100 * (med - target) / target:+.1f}%), "
          f"median traced share {statistics.median(h['traced_fraction_each'][50:]):.3f}")

    frames = max(2, round(a.fps))  # 1 s of frames at the target
    for sel in ("mask", "uniform"):
        base = os.path.join(a.out, sel)
        extra = ["--out-mask", os.path.join(a.out, "mask.png")] if sel == "mask" else []
        subprocess.run(common + ["--frames", str(frames), "--budget-select", sel, "--out",
                                 base + ".exr", "--out", base + ".png", "--stats",
                                 base + ".json"] + extra, check=True)
        with open(base + ".json") as f:
            s = json.load(f)
        m = metrics.compare(base + ".exr", ref_exr)
        tr = s["budget"]["traced_fraction_each"][1:]
        print(f"{sel:8s}: {s['frames']} frames, {sum(s['budget']['frame_ms_each']):.0f} ms in "
              f"all, mean traced share {sum(tr) / len(tr):.3f}, relMSE {m['rel_mse']:.4f}, "
              f"RMSE {m['rmse']:.4f}")
    return 0
