"""What `voxgi view` shows while the camera moves: rtgi at the viewer's size under
its frame budget, against the path tracer at the same pose.

For each view of bench_motion.py, the camera orbits into the view over --move
frames played at 30 fps (a glTF camera path), then holds still. rtgi renders the
sequence at --size with `--target-fps 30` and `--sparse-start` (the viewer's
defaults: the frame budget sets the share of pixels that trace each frame, the
first frame included), with the denoiser off and on.
Measured, FLIP on sRGB 8-bit against a path-traced reference at that pose:

  - moving: the frame half way through the move (which starts as the viewer
    opens, or --settle frames later);
  - 1 s after: --after frames (default 30, one second) after the camera stopped;
  - still: the end pose rendered still for 64 frames with every pixel traced and
    denoised (render's defaults: the converged image the viewer approaches).

With --render-scale (repeatable), each scale gets its rows: rtgi renders at that
share of the size and the temporal upsampler rebuilds the output (the still
image stays at scale 1, the converged image the viewer approaches).

Each row also gives the median frame time and traced share of the run. The frame
times are this machine's: run it on a quiet machine. References come from
out/reference/ (VIEW_POSE_SIZE_Nspp.exr); a missing one is rendered with --ref-spp.
Writes out/bench-screen/table.md and prints it.
"""
import argparse
import json
import os
import re
import subprocess
import sys

from voxgi_tools import ROOT, bench_motion as motion, metrics, scene_path, voxgi
from voxgi_tools import reference as refs

SEED = 7


def pose_of(view, move, orbit, frame):
    """The eye and target of the camera path at frame `frame`."""
    _, eye, target = motion.VIEWS[view]
    u = min(frame, move - 1) / (move - 1)
    return motion.orbit(eye, target, -orbit * (1.0 - u)), target


def reference(view, pose, eye, target, size, spp):
    """The path-traced reference of `view` at this pose and size (VIEW_POSE_SIZE)."""
    extra = ["--look-from", ",".join(f"{c:.6f}" for c in eye),
             "--look-at", ",".join(f"{c:.6f}" for c in target)]
    exr, png, _ = refs.get(f"{view}_{pose}", scene_path(motion.VIEWS[view][0]), extra, size, spp)
    return exr, png


def render(scene, size, frames, flags, base):
    os.makedirs(os.path.dirname(base), exist_ok=True)
    subprocess.run([voxgi(), "render", scene, "--mode", "rtgi", "--size", size, "--seed",
                    str(SEED), "--fps", str(motion.FPS), "--frames", str(frames), "--out",
                    base + ".exr", "--out", base + ".png", "--stats", base + ".json", "-q"]
                   + flags, check=True)
    with open(base + ".json") as f:
        return json.load(f)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n".join(__doc__.splitlines()[1:]))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "bench-screen"))
    ap.add_argument("--size", default="640x360", help="the viewer's size (default 640x360)")
    ap.add_argument("--move", type=int, default=30, help="frames of the move (default 30)")
    ap.add_argument("--orbit", type=float, default=10.0,
                    help="degrees the camera turns about the target (default 10)")
    ap.add_argument("--settle", type=int, default=0,
                    help="frames the camera holds its start pose before it moves (default "
                         "0: the move starts as the viewer opens; 30: a second after)")
    ap.add_argument("--after", type=int, default=30,
                    help="frames after the camera stopped (default 30: 1 s at 30 fps)")
    ap.add_argument("--ref-spp", type=int, default=512,
                    help="spp of a reference rendered because none exists (default 512)")
    ap.add_argument("--view", action="append", choices=list(motion.VIEWS),
                    help="only this view (repeatable)")
    ap.add_argument("--render-scale", action="append", type=float, dest="scales",
                    help="rtgi's render scale, 0.25 to 1 (repeatable; default 1)")
    ap.add_argument("--denoise", action="append", choices=["off", "on"],
                    help="the denoiser off, on (repeatable; default both)")
    a = ap.parse_args(argv)
    if not os.path.exists(voxgi()):
        raise SystemExit("bench-screen: error: build/voxgi missing (tools/build)")
    if a.move < 3 or a.after < 1:
        raise SystemExit("bench-screen: error: --move must be at least 3 and --after at least 1")
    if a.settle < 0:
        raise SystemExit("bench-screen: error: --settle must be at least 0")
    if not re.fullmatch(r"\d+x\d+", a.size):
        raise SystemExit(f"bench-screen: error: --size {a.size}: not WxH")
    scales = a.scales or [1.0]
    if any(not 0.25 <= x <= 1.0 for x in scales):
        raise SystemExit("bench-screen: error: --render-scale must be in [0.25, 1]")
    mid = a.move // 2
    settled = f", after {a.settle} frames still" if a.settle else ""
    lines = [f"rtgi at {a.size} under `--target-fps 30`, the camera orbiting {a.orbit:g} degrees "
             f"over {a.move} frames at 30 fps{settled}; FLIP against the path tracer at each pose.",
             "",
             "| view | scale | denoiser | moving (frame %d) | %d frames after it stopped "
             "| still, 64 frames | frame ms, median | frame ms, 95th percentile "
             "| traced share, median |" % (mid + 1, a.after),
             "|---|---:|---|---:|---:|---:|---:|---:|---:|"]
    print("\n".join(lines), flush=True)
    for view in motion.VIEWS:
        if a.view and view not in a.view:
            continue
        scene = motion.path_scene(view, a.move, a.after + 1, a.orbit, a.out, a.settle)
        eye_mid, target = pose_of(view, a.move, a.orbit, mid)
        eye_end, _ = pose_of(view, a.move, a.orbit, a.move - 1)
        ref_mid = reference(view, f"orbit{a.orbit:g}_{mid}of{a.move}", eye_mid, target, a.size,
                            a.ref_spp)
        ref_end = reference(view, "end", eye_end, target, a.size, a.ref_spp)
        runs = os.path.join(a.out, "runs")
        # The still image: the file's scene seen from the end pose, 64 frames with
        # every pixel traced, denoised (render's defaults).
        base = os.path.join(runs, f"{view}_still")
        render(scene_path(motion.VIEWS[view][0]), a.size, 64,
               ["--look-from", ",".join(f"{c:.6f}" for c in eye_end),
                "--look-at", ",".join(f"{c:.6f}" for c in target)], base)
        still_flip = metrics.measure(base, *ref_end)["flip"]
        for scale in scales:
            for denoise in a.denoise or ["off", "on"]:
                # The viewer's settings: its budget, and its sparse start (the first
                # frame traces the budget's share, like the others).
                flags = ["--target-fps", "30", "--sparse-start", "--denoise", denoise,
                         "--render-scale", f"{scale:g}"]
                tag = os.path.join(runs, f"{view}_s{scale:g}_{denoise}_settle{a.settle}")
                render(scene, a.size, a.settle + mid + 1, flags, tag + "_moving")
                moving = metrics.measure(tag + "_moving", *ref_mid)["flip"]
                stats = render(scene, a.size, a.settle + a.move - 1 + a.after + 1, flags,
                               tag + "_after")
                after = metrics.measure(tag + "_after", *ref_end)["flip"]
                budget = stats.get("budget", {})
                each = sorted(budget.get("frame_ms_each", [stats["frame_ms"]])[1:] or
                              [stats["frame_ms"]])
                p95 = each[min(len(each) - 1, int(round(0.95 * (len(each) - 1))))]
                line = (f"| {view} | {scale:g} | {denoise} | {moving:.4f} | {after:.4f} | "
                        f"{still_flip:.4f} | "
                        f"{budget.get('frame_ms_median', stats['frame_ms']):.1f} | {p95:.1f} | "
                        f"{budget.get('traced_fraction_median', 1.0):.3f} |")
                lines.append(line)
                print(line, flush=True)
    with open(os.path.join(a.out, "table.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    sys.exit(main())
