"""The validation set (scenes/validation_set.json): the views every rtgi change is
judged on, for the benchmarks to share. A view is (name, scene path, the flags that
place its camera)."""
import hashlib
import json
import math
import os
import random
import subprocess
import sys

from voxgi_tools import ROOT

SET = os.path.join(ROOT, "scenes", "validation_set.json")


def load():
    with open(SET) as f:
        return json.load(f)


def camera_flags(entry):
    """The render flags of a view's viewpoint: none for the file's camera."""
    if "look_from" not in entry:
        return []
    return ["--look-from", ",".join(map(str, entry["look_from"])),
            "--look-at", ",".join(map(str, entry["look_at"]))]


def views(names=None, make=True):
    """[(view, absolute scene path, flags)] of the set, or of `names` in the set's
    order; a scene kept out of git is made first (its entry's make command) when
    `make`, and its views are left out otherwise."""
    out = []
    entries = load()["views"]
    known = [e["view"] for e in entries]
    for n in names or []:
        if n not in known:
            raise SystemExit(f"validation set: no view '{n}' (views: {', '.join(known)})")
    for e in entries:
        if names and e["view"] not in names:
            continue
        path = os.path.join(ROOT, e["scene"])
        if not os.path.exists(path):
            if not (make and "make" in e):
                continue
            # On stderr: stdout is the scene and flags tools/make-reference reads.
            print(f"validation set: making {e['scene']} ({e['make']})", file=sys.stderr, flush=True)
            subprocess.run(e["make"].split(), cwd=ROOT, check=True, stdout=subprocess.DEVNULL)
        out.append((e["view"], path, camera_flags(e)))
    return out


def held_out(count, seed):
    """[(view, absolute scene path, flags)] of `count` viewpoints drawn at random, with
    `seed`, in the spaces of the set's "held_out" section: the scenes taken in turn,
    each view's eye uniform over its space's eye boxes (a box by its volume) and out
    of its avoid spheres, the point it looks at uniform over the target box and at
    least min_distance away, and not straight up or down (the camera's up is +y).
    Each name holds the scene and a hash of the viewpoint, so a reference rendered
    for one (out/reference/, by name) is never taken for another's."""
    section = load()["held_out"]
    rng = random.Random(seed)
    out = []
    for i in range(count):
        entry = section["scenes"][i % len(section["scenes"])]
        space = section["spaces"][entry["space"]]
        eye, target = draw_viewpoint(space, rng)
        flags = ["--look-from", ",".join(f"{c:.2f}" for c in eye),
                 "--look-at", ",".join(f"{c:.2f}" for c in target)]
        stem = os.path.splitext(os.path.basename(entry["scene"]))[0]
        tag = hashlib.sha1(" ".join(flags).encode()).hexdigest()[:6]
        out.append((f"held_{stem}_{tag}", os.path.join(ROOT, entry["scene"]), flags))
    return out


def draw_viewpoint(space, rng, tries=10000):
    """(eye, target) drawn in `space` (held_out's spaces), each rounded to 1 cm."""
    def volume(box):
        return math.prod(max(hi - lo, 0.0) for lo, hi in zip(*box))

    def inside(box):
        return [round(rng.uniform(lo, hi), 2) for lo, hi in zip(*box)]

    boxes = space["eye"]
    for _ in range(tries):
        eye = inside(rng.choices(boxes, weights=[volume(b) for b in boxes])[0])
        if any(math.dist(eye, c) < r for c, r in space["avoid"]):
            continue
        target = inside(space["target"])
        d = math.dist(eye, target)
        if d < space["min_distance"] or abs(target[1] - eye[1]) > 0.9 * d:
            continue
        return eye, target
    raise SystemExit(f"validation set: no viewpoint drawn in {tries} tries ({space})")


def user_scenes(paths, flags=()):
    """[(view, absolute scene path, flags)] of glTF files outside the set, each from its
    own camera or the one `flags` place (--look-from, --look-at). Each name holds the
    file's stem and a hash of its path, size, modification time and the flags, so a
    reference rendered for it (out/reference/, by name) is made again once the file
    or the viewpoint changes."""
    out = []
    for p in paths:
        path = os.path.abspath(p)
        if not os.path.isfile(path):
            raise SystemExit(f"validation set: {p}: no such file")
        if not path.lower().endswith(".gltf"):
            # The tools' own readers (regions.py, mitsuba_scene.py) take JSON glTF.
            raise SystemExit(f"validation set: {p}: not a .gltf file (a .glb can be "
                             "unpacked into one with gltf-pipeline or Blender)")
        st = os.stat(path)
        key = f"{path} {st.st_size} {st.st_mtime_ns} {' '.join(flags)}"
        stem = os.path.splitext(os.path.basename(path))[0]
        stem = "".join(c if c.isalnum() or c in "-_" else "_" for c in stem)
        out.append((f"scene_{stem}_{hashlib.sha1(key.encode()).hexdigest()[:6]}", path,
                    list(flags)))
    return out


def names():
    return [e["view"] for e in load()["views"]]


def main(argv=None):
    """usage: validation-set [VIEW...] | --names

Prints each view's scene and the flags that place its camera, one per line (every
view's without arguments; tools/make-reference's lookup); with --names, the names
of the set's views."""
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] in (["-h"], ["--help"]):
        print(main.__doc__)
        return 0
    if argv[:1] == ["--names"]:
        print("\n".join(names()))
        return 0
    for view, scene, flags in views(argv):
        print("\n".join([scene] + flags))
    return 0


if __name__ == "__main__":
    sys.exit(main())
