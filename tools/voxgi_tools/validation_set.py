"""The validation set (scenes/validation_set.json): the views every rtgi change is
judged on, for the benchmarks to share. A view is (name, scene path, the flags that
place its camera)."""
import json
import os
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
