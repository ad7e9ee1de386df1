"""Image metrics against a reference: FLIP on sRGB 8-bit, and `voxgi compare`'s.

FLIP: linear images (.exr) are converted the way `voxgi render --out x.png` converts
them (clamp to [0, 1], the sRGB transfer function, 8 bits) by oiiotool; 8-bit
images (.png) are read as they are. FLIP's LDR mode then compares them at its
default viewing condition (67 pixels per degree).
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

from voxgi_tools import voxgi


def srgb8(path, tmp):
    """Float HxWx3 array in [0, 1] of the sRGB 8-bit version of `path`."""
    import matplotlib.image as mpimg

    if not os.path.isfile(path):
        raise SystemExit(f"flip: error: {path}: no such file")
    if path.lower().endswith(".exr"):
        png = os.path.join(tmp, f"{len(os.listdir(tmp))}.png")
        subprocess.run(["oiiotool", path, "--ch", "R,G,B", "--colorconvert", "linear", "sRGB",
                        "-d", "uint8", "-o", png], check=True, capture_output=True)
        path = png
    img = mpimg.imread(path)
    if img.dtype != np.float32 and img.dtype != np.float64:
        img = img.astype(np.float32) / 255.0
    if img.ndim == 2:
        img = np.stack([img] * 3, axis=-1)
    return np.ascontiguousarray(img[..., :3], dtype=np.float32)


def flip_map(test, ref):
    """FLIP's per-pixel error (HxW) of `test` against `ref`."""
    import flip_evaluator

    with tempfile.TemporaryDirectory() as tmp:
        t = srgb8(test, tmp)
        r = srgb8(ref, tmp)
        if t.shape != r.shape:
            raise SystemExit(f"flip: error: {test} vs {ref}: images differ in size: "
                             f"{t.shape[1]}x{t.shape[0]} vs {r.shape[1]}x{r.shape[0]}")
        err, _, _ = flip_evaluator.evaluate(r, t, "LDR", inputsRGB=True, applyMagma=False)
    return np.asarray(err, dtype=np.float64).reshape(r.shape[:2])


def flip(test, ref, error_map=None, regions=None):
    """Mean FLIP of `test` against `ref`; with `regions` ({name: HxW bool mask}),
    (mean, {name: the mean over that region's pixels})."""
    err = flip_map(test, ref)
    if error_map:
        import flip_evaluator
        import matplotlib.image as mpimg

        with tempfile.TemporaryDirectory() as tmp:
            magma, _, _ = flip_evaluator.evaluate(srgb8(ref, tmp), srgb8(test, tmp), "LDR",
                                                  inputsRGB=True, applyMagma=True)
        mpimg.imsave(error_map, np.clip(magma, 0, 1))
    if regions is None:
        return float(err.mean())
    return float(err.mean()), {k: float(err[m].mean()) for k, m in regions.items()}


def compare(test_exr, ref_exr, blocks=None):
    """`voxgi compare TEST REF --json` (RMSE, relMSE, PSNR, SSIM, mean luminance ratio;
    with `blocks`, the worst blocks of that many pixels a side)."""
    cmd = [voxgi(), "compare", test_exr, ref_exr, "--json"]
    if blocks:
        cmd += ["--blocks", str(blocks)]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise SystemExit(f"voxgi compare {test_exr} {ref_exr}: exited {p.returncode}: "
                         f"{(p.stderr or p.stdout).strip()}")
    return json.loads(p.stdout)


def measure(base, ref_exr, ref_png, regions=None):
    """The benchmarks' three figures of base.exr/base.png against a reference: FLIP,
    RMSE and the mean luminance ratio; with `regions` ({name: mask}, regions.py), FLIP
    over each region too, as "flip_NAME"."""
    m = compare(base + ".exr", ref_exr)
    f = flip(base + ".png", ref_png, regions=regions or {})
    out = {"flip": f[0], "rmse": m["rmse"], "lum": m["mean_luminance_ratio"]}
    out.update({f"flip_{k}": v for k, v in f[1].items()})
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description="FLIP of TEST against REFERENCE, on their sRGB "
                                 "8-bit versions (NVIDIA's perceptual error, flip-evaluator)")
    ap.add_argument("test")
    ap.add_argument("reference")
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--map", help="write the FLIP error map (magma) as PNG")
    a = ap.parse_args(argv)
    value = flip(a.test, a.reference, a.map)
    if a.json:
        print(json.dumps({"test": a.test, "reference": a.reference, "flip": value}))
    else:
        print(f"flip {value:.6f}")


if __name__ == "__main__":
    sys.exit(main())
