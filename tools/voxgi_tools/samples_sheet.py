"""Render the glTF samples in every mode and tile them into one contact sheet.

Each sample (the Khronos and textured samples of scenes/, plus every sample found
in the --samples folders) is rendered with `voxgi render SAMPLE --mode M --size S`
once per mode; the images are tiled, one row per mode and one column per sample,
with labels, into OUT/samples.png. With --flip the path tracer's image is a
reference (--ref-spp samples per pixel, seed 1000003, CPU device by default), each
cell is written as EXR too, and FLIP of rtgi against the path tracer per sample
goes to OUT/flip.csv and OUT/flip.md.

Every file written lies under --out (cells/ holds the renders); nothing else is
touched. A sample voxgi refuses gets a grey cell with the error, and the exit
status is then 1.
"""
import argparse
import csv
import os
import re
import shlex
import subprocess
import sys
import tempfile
import time

from voxgi_tools import ROOT

# The samples of scenes/ that are Khronos glTF samples or textured assets, in the
# sheet's column order.
BUILTIN = [
    "avocado",
    "duck",
    "lights_punctual_lamp",
    "emissive_strength_test",
    "normal_tangent_mirror_test",
    "texture_transform_test",
    "texture_coordinate_test",
    "vertex_color_test",
    "metal_rough_spheres_no_textures",
    "box",
]

# Render options a sample needs to be legible at the sheet's size, every mode, e.g.
# {"name": ["--exposure", "2"]}. None of the built-in samples needs any at 160x160.
SAMPLE_OPTIONS = {}

MODE_LABELS = {
    "raster": "raster",
    "rtgi": "rtgi",
    "pathtrace": "pathtrace",
    "dvr": "dvr",
    "points": "points",
}


def find_gltf(folder):
    """The sample file of `folder`: its .gltf (else .glb), directly or in the glTF/
    (glTF-Binary/) subfolder of the Khronos sample-assets layout; None if none."""
    for sub, ext in (("", ".gltf"), ("", ".glb"), ("glTF", ".gltf"), ("glTF-Binary", ".glb")):
        d = os.path.join(folder, sub)
        if not os.path.isdir(d):
            continue
        files = sorted(f for f in os.listdir(d) if f.lower().endswith(ext))
        if files:
            return os.path.join(d, files[0])
    return None


def collect(builtin, extra_dirs):
    """[(name, path)]: the built-in samples, then each --samples folder's (the folder
    itself when it holds a sample, else each subfolder that does)."""
    samples = []
    for name in builtin:
        path = find_gltf(os.path.join(ROOT, "scenes", name))
        if path is None:
            raise SystemExit(f"samples-sheet: error: scenes/{name}: no .gltf or .glb")
        samples.append((name, path))
    for d in extra_dirs:
        if not os.path.isdir(d):
            raise SystemExit(f"samples-sheet: error: --samples {d}: not a folder")
        path = find_gltf(d)
        if path is not None:
            samples.append((os.path.basename(os.path.normpath(d)), path))
            continue
        found = False
        for sub in sorted(os.listdir(d)):
            path = find_gltf(os.path.join(d, sub))
            if path is not None:
                samples.append((sub, path))
                found = True
        if not found:
            raise SystemExit(f"samples-sheet: error: --samples {d}: no sample in it or its "
                             "subfolders")
    # Unique file names for the cells.
    seen, unique = set(), []
    for name, path in samples:
        base = re.sub(r"[^A-Za-z0-9_.-]", "_", name) or "sample"
        key, n = base, 2
        while key.lower() in seen:
            key, n = f"{base}-{n}", n + 1
        seen.add(key.lower())
        unique.append((key, path))
    return unique


def render(args, sample_path, options, mode, outputs):
    """Runs voxgi render; returns (seconds, error line or None)."""
    cmd = [args.voxgi, "render", sample_path, "--mode", mode, "--size", args.size, "--quiet"]
    if mode == "pathtrace":
        spp = args.ref_spp if args.flip else args.spp
        cmd += ["--spp", str(spp), "--seed", str(args.seed), "--pt-device", args.pt_device]
    if mode == "rtgi" and args.frames:
        cmd += ["--frames", str(args.frames)]
    cmd += options
    for o in outputs:
        cmd += ["--out", o]
    t0 = time.monotonic()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout)
    except subprocess.TimeoutExpired:
        return time.monotonic() - t0, f"timed out after {args.timeout} s"
    dt = time.monotonic() - t0
    if p.returncode != 0:
        lines = [l for l in (p.stderr + p.stdout).splitlines() if l.strip()]
        line = lines[-1] if lines else f"exit {p.returncode}"
        return dt, line.replace("voxgi: error: ", "").replace(sample_path + ": ", "")
    return dt, None


def label_lines(name, width, font, draw):
    """`name` broken at underscores into lines that fit `width` pixels."""
    lines, cur = [], ""
    for part in re.split(r"(?<=_)", name):
        if cur and draw.textlength(cur + part, font=font) > width:
            lines.append(cur)
            cur = part
        else:
            cur += part
    lines.append(cur)
    return lines


def tile(cells, samples, modes, out_png, size):
    """One labelled sheet: rows are modes, columns samples. `cells[(name, mode)]` is
    a PNG path or an error string."""
    from PIL import Image, ImageDraw, ImageFont

    w, h = (int(v) for v in size.split("x"))
    try:
        font = ImageFont.load_default(size=13)
    except TypeError:  # Pillow without scalable default font
        font = ImageFont.load_default()
    scratch = ImageDraw.Draw(Image.new("RGB", (1, 1)))
    pad, line_h = 4, 16
    headers = [label_lines(n, w - 2 * pad, font, scratch) for n, _ in samples]
    top = pad + line_h * max(len(l) for l in headers) + pad
    left = int(max(scratch.textlength(MODE_LABELS.get(m, m), font=font) for m in modes)) + 3 * pad
    sheet = Image.new("RGB", (left + w * len(samples), top + h * len(modes)), (255, 255, 255))
    draw = ImageDraw.Draw(sheet)
    for c, lines in enumerate(headers):
        for k, text in enumerate(lines):
            draw.text((left + c * w + pad, pad + k * line_h), text, fill=(0, 0, 0), font=font)
    for r, mode in enumerate(modes):
        y = top + r * h
        draw.text((pad, y + h // 2 - line_h // 2), MODE_LABELS.get(mode, mode), fill=(0, 0, 0),
                  font=font)
        for c, (name, _) in enumerate(samples):
            x = left + c * w
            cell = cells.get((name, mode))
            if cell and os.path.isfile(cell):
                img = Image.open(cell).convert("RGB")
                if img.size != (w, h):
                    img = img.resize((w, h))
                sheet.paste(img, (x, y))
            else:
                draw.rectangle([x, y, x + w - 1, y + h - 1], fill=(96, 96, 96))
                msg = "failed: " + (cell or "not rendered")
                words, lines, cur = [], [], ""
                for word in msg.split():  # words too long for a line are cut
                    while len(word) > 18:
                        words.append(word[:18])
                        word = word[18:]
                    words.append(word)
                for word in words:
                    if cur and draw.textlength(cur + " " + word, font=font) > w - 2 * pad:
                        lines.append(cur)
                        cur = word
                    else:
                        cur = (cur + " " + word).strip()
                lines.append(cur)
                for k, text in enumerate(lines[: h // line_h]):
                    draw.text((x + pad, y + pad + k * line_h), text, fill=(255, 255, 255), font=font)
    # Grid lines between the cells.
    for c in range(len(samples) + 1):
        draw.line([left + c * w, top, left + c * w, top + h * len(modes)], fill=(255, 255, 255))
    for r in range(len(modes) + 1):
        draw.line([left, top + r * h, left + w * len(samples), top + r * h], fill=(255, 255, 255))
    tmp = out_png + ".part.png"
    sheet.save(tmp, optimize=True)
    os.replace(tmp, out_png)


def flip_over_lit(test, ref):
    """(mean FLIP over the pixels that are not black in either image, their share of
    the image): the samples float on a black background, which is no error in every
    mode and dilutes the image's mean by how little of the frame a sample fills."""
    import flip_evaluator
    import numpy as np
    from voxgi_tools.metrics import srgb8

    with tempfile.TemporaryDirectory() as tmp:
        t, r = srgb8(test, tmp), srgb8(ref, tmp)
    err, _, _ = flip_evaluator.evaluate(r, t, "LDR", inputsRGB=True, applyMagma=False)
    err = np.asarray(err).reshape(t.shape[:2])
    lit = (t.max(axis=2) > 0) | (r.max(axis=2) > 0)
    if not lit.any():
        return 0.0, 0.0
    return float(err[lit].mean()), float(lit.mean())


def main(argv=None):
    ap = argparse.ArgumentParser(
        prog="tools/samples-sheet", description=__doc__.split("\n\n")[0],
        epilog="Example: tools/samples-sheet --out out/samples --flip --ref-spp 512")
    ap.add_argument("--out", required=True, help="folder for every file written (made if missing)")
    ap.add_argument("--samples", action="append", default=[], metavar="DIR",
                    help="also render the sample in DIR, or each subfolder of DIR holding one "
                    "(X/*.gltf, X/glTF/*.gltf or X/glTF-Binary/*.glb); repeatable")
    ap.add_argument("--no-builtin", action="store_true",
                    help="leave out the samples of scenes/ (only the --samples ones)")
    ap.add_argument("--only", default="", metavar="A,B",
                    help="only the samples with these names (folder names)")
    ap.add_argument("--modes", default="raster,rtgi,pathtrace",
                    help="rows, from raster, rtgi, pathtrace, dvr, points (default %(default)s)")
    ap.add_argument("--size", default="160x160", help="cell size WxH (default %(default)s)")
    ap.add_argument("--spp", type=int, default=128,
                    help="path tracer samples per pixel for the sheet (default %(default)s)")
    ap.add_argument("--frames", type=int, default=0,
                    help="rtgi frames (default: voxgi's, 64)")
    ap.add_argument("--seed", type=int, default=1000003, help="path tracer seed (default %(default)s)")
    ap.add_argument("--pt-device", default="cpu", choices=["cpu", "gl", "auto"],
                    help="path tracer device (default %(default)s)")
    ap.add_argument("--flip", action="store_true",
                    help="path tracer at --ref-spp as the reference, EXR cells, FLIP of rtgi "
                    "against it into flip.csv and flip.md")
    ap.add_argument("--ref-spp", type=int, default=512,
                    help="with --flip: the reference's samples per pixel (default %(default)s)")
    ap.add_argument("--reuse", action="store_true",
                    help="keep cells already rendered in OUT/cells instead of rendering them again")
    ap.add_argument("--timeout", type=int, default=900, help="seconds per render (default %(default)s)")
    ap.add_argument("--voxgi", default=os.path.join(ROOT, "build", "voxgi"),
                    help="the voxgi binary (default build/voxgi)")
    args = ap.parse_args(argv)

    if not re.fullmatch(r"\d+x\d+", args.size):
        ap.error(f"--size {args.size}: expected WxH")
    modes = [m for m in args.modes.split(",") if m]
    for m in modes:
        if m not in MODE_LABELS:
            ap.error(f"--modes: unknown mode {m}")
    if args.flip and not {"rtgi", "pathtrace"} <= set(modes):
        ap.error("--flip needs the rtgi and pathtrace rows")
    if not os.access(args.voxgi, os.X_OK):
        raise SystemExit(f"samples-sheet: error: {args.voxgi}: not built (tools/build)")

    samples = collect([] if args.no_builtin else BUILTIN, args.samples)
    if args.only:
        wanted = set(args.only.split(","))
        samples = [s for s in samples if s[0] in wanted]
        missing = wanted - {s[0] for s in samples}
        if missing:
            raise SystemExit(f"samples-sheet: error: --only: no sample {', '.join(sorted(missing))}")
    if not samples:
        raise SystemExit("samples-sheet: error: no samples")

    out = os.path.abspath(args.out)
    cells_dir = os.path.join(out, "cells")
    os.makedirs(cells_dir, exist_ok=True)
    with open(os.path.join(out, "command.txt"), "w") as f:
        f.write(" ".join(shlex.quote(a) for a in ["tools/samples-sheet"] + sys.argv[1:]) + "\n")

    # Render times, kept across --reuse runs.
    times_csv = os.path.join(out, "times.csv")
    times = {}
    if os.path.isfile(times_csv):
        with open(times_csv) as f:
            for r in csv.DictReader(f):
                times[(r["sample"], r["mode"])] = float(r["seconds"])
    cells, failed = {}, False
    total, i = len(samples) * len(modes), 0
    for name, path in samples:
        options = SAMPLE_OPTIONS.get(name, [])
        for mode in modes:
            i += 1
            png = os.path.join(cells_dir, f"{name}_{mode}.png")
            outputs = [png]
            if args.flip and mode in ("rtgi", "pathtrace"):
                outputs.append(os.path.join(cells_dir, f"{name}_{mode}.exr"))
            if args.reuse and all(os.path.isfile(o) for o in outputs):
                print(f"[{i}/{total}] {name} {mode}: kept", flush=True)
                cells[(name, mode)] = png
                continue
            print(f"[{i}/{total}] {name} {mode} ...", end="", flush=True)
            dt, err = render(args, path, options, mode, outputs)
            times[(name, mode)] = dt
            if err:
                failed = True
                print(f" failed ({dt:.1f} s): {err}", flush=True)
                for o in outputs:
                    if os.path.isfile(o):
                        os.remove(o)
                cells[(name, mode)] = err
            else:
                print(f" {dt:.1f} s", flush=True)
                cells[(name, mode)] = png

    with open(times_csv, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["sample", "mode", "seconds"])
        for (name, mode), dt in sorted(times.items()):
            w.writerow([name, mode, f"{dt:.1f}"])

    sheet = os.path.join(out, "samples.png")
    tile(cells, samples, modes, sheet, args.size)
    print(f"sheet: {sheet} ({len(modes)} rows x {len(samples)} columns, "
          f"{os.path.getsize(sheet) / 1e6:.2f} MB)", flush=True)

    if args.flip:
        from voxgi_tools.metrics import flip as flip_of

        rows = []
        for name, path in samples:
            ref = os.path.join(cells_dir, f"{name}_pathtrace.exr")
            test = os.path.join(cells_dir, f"{name}_rtgi.exr")
            if not (os.path.isfile(ref) and os.path.isfile(test)):
                continue
            value = flip_of(test, ref)
            lit_value, lit_share = flip_over_lit(test, ref)
            rows.append({
                "sample": name,
                "file": os.path.relpath(path, ROOT) if path.startswith(ROOT + os.sep) else path,
                "size": args.size,
                "ref_spp": args.ref_spp,
                "ref_seconds": round(times.get((name, "pathtrace"), float("nan")), 1),
                "rtgi_frames": args.frames or 64,
                "rtgi_seconds": round(times.get((name, "rtgi"), float("nan")), 1),
                "flip": round(value, 4),
                "lit_share": round(lit_share, 3),
                "flip_lit": round(lit_value, 4),
            })
            print(f"flip {name}: {value:.4f} (over its lit pixels, {100 * lit_share:.0f}% of "
                  f"the image: {lit_value:.4f})", flush=True)
        with open(os.path.join(out, "flip.csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0].keys()) if rows else ["sample"])
            w.writeheader()
            w.writerows(rows)
        with open(os.path.join(out, "flip.md"), "w") as f:
            f.write("| sample | path tracer (s) | rtgi (s) | FLIP | lit pixels | FLIP over "
                    "them |\n")
            f.write("|---|---:|---:|---:|---:|---:|\n")
            for r in rows:
                f.write(f"| {r['sample']} | {r['ref_seconds']} | {r['rtgi_seconds']} | "
                        f"{r['flip']:.3f} | {100 * r['lit_share']:.0f}% | {r['flip_lit']:.3f} |\n")
        print(f"flip: {os.path.join(out, 'flip.csv')}, {os.path.join(out, 'flip.md')}", flush=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
