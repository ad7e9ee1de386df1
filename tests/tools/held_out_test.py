"""The held-out viewpoints of tools/bench-convergence --held-out
(tools/voxgi_tools/validation_set.py, held_out): the same views for the same seed and
others for another, each where its space says (eye in an eye box and out of the
avoid spheres, target in the target box, far enough, not straight up or down), and
every eye box free of the scenes' triangles (but those of the objects the avoid
spheres hold), so that no camera is drawn inside a wall or a column.

With them, the names of --scene's files (validation_set.user_scenes): a new one
once the file or its viewpoint changes, so that no reference of another is reused,
and a clear exit for a file that is not there or is not a .gltf.

Usage: held_out_test.py"""
import math
import os
import shutil
import tempfile

import numpy as np

from tool_support import ROOT, fail
from voxgi_tools import mitsuba_scene, validation_set


def world_triangles(path):
    """[n, 3, 3] float64: every triangle of the glTF file at `path`, in world space."""
    gltf, accessor, world = mitsuba_scene.read_gltf(path)
    out = []
    for i, node in enumerate(gltf["nodes"]):
        if "mesh" not in node:
            continue
        m = world(i)
        for prim in gltf["meshes"][node["mesh"]]["primitives"]:
            p = accessor(prim["attributes"]["POSITION"]).astype(np.float64)
            p = p @ m[:3, :3].T + m[:3, 3]
            idx = (accessor(prim["indices"]).reshape(-1) if "indices" in prim
                   else np.arange(len(p)))
            out.append(p[idx.reshape(-1, 3)])
    return np.concatenate(out)


def overlap_box(tris, lo, hi):
    """[n] bool: which triangles overlap the box [lo, hi] (the separating axis test of
    Akenine-Moller 2001, "Fast 3D triangle-box overlap testing": the box's 3 axes, the
    triangle's normal, and the 9 cross products of their edges)."""
    c = (np.asarray(lo) + np.asarray(hi)) / 2.0
    h = (np.asarray(hi) - np.asarray(lo)) / 2.0
    v = tris - c  # [n, 3, 3]
    e = np.stack([v[:, 1] - v[:, 0], v[:, 2] - v[:, 1], v[:, 0] - v[:, 2]], 1)
    axes = [np.broadcast_to(np.eye(3)[k], (len(v), 3)) for k in range(3)]
    axes.append(np.cross(e[:, 0], e[:, 1]))
    axes += [np.cross(np.eye(3)[k], e[:, j]) for k in range(3) for j in range(3)]
    hit = np.ones(len(v), bool)
    for a in axes:
        p = np.einsum("nvk,nk->nv", v, a)
        r = np.abs(a) @ h
        hit &= ~((p.min(1) > r + 1e-9) | (p.max(1) < -r - 1e-9))
    return hit


def user_scenes():
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "my scene.gltf")
        shutil.copy(os.path.join(ROOT, "scenes/box/Box.gltf"), path)
        first = validation_set.user_scenes([path])
        name = first[0][0]
        if not name.startswith("scene_my_scene_") or first[0][2] != []:
            fail(f"user scene: {first}")
        if validation_set.user_scenes([path]) != first:
            fail("user scene: two names for one file")
        placed = validation_set.user_scenes([path], ["--look-from", "1,2,3", "--look-at", "0,0,0"])
        if placed[0][0] == name or placed[0][2][1] != "1,2,3":
            fail(f"user scene: another viewpoint kept the name {name}")
        with open(path, "a") as f:
            f.write("\n")
        if validation_set.user_scenes([path])[0][0] == name:
            fail(f"user scene: a changed file kept the name {name}")
        glb = os.path.join(tmp, "packed.glb")
        open(glb, "wb").close()
        for bad, says in ((os.path.join(tmp, "missing.gltf"), "missing.gltf: no such file"),
                          (glb, "packed.glb: not a .gltf file")):
            try:
                validation_set.user_scenes([bad])
            except SystemExit as e:
                if says not in str(e):
                    fail(f"user scene: {bad} said {e}")
            else:
                fail(f"user scene: {bad} was taken")


def main():
    user_scenes()
    section = validation_set.load()["held_out"]
    set_names = set(validation_set.names())

    a, b = validation_set.held_out(10, 3), validation_set.held_out(10, 3)
    if a != b:
        fail("held_out(10, 3) drew two different lists")
    if validation_set.held_out(10, 4) == a:
        fail("held_out(10, 4) drew the same views as seed 3")

    views = validation_set.held_out(200, 11)
    names = [v[0] for v in views]
    if len(set(names)) != len(names) or set(names) & set_names:
        fail("held-out names repeat or collide with the set's views")
    for i, (name, scene, flags) in enumerate(views):
        entry = section["scenes"][i % len(section["scenes"])]
        space = section["spaces"][entry["space"]]
        if scene != os.path.join(ROOT, entry["scene"]):
            fail(f"{name}: scene {scene}, expected {entry['scene']} (the scenes in turn)")
        eye = [float(x) for x in flags[1].split(",")]
        target = [float(x) for x in flags[3].split(",")]
        tol = 0.0051  # the 1 cm rounding

        def within(p, box):
            return all(lo - tol <= x <= hi + tol for x, lo, hi in zip(p, *box))

        if not any(within(eye, box) for box in space["eye"]):
            fail(f"{name}: eye {eye} outside every eye box")
        if any(math.dist(eye, c) < r - tol for c, r in space["avoid"]):
            fail(f"{name}: eye {eye} inside an avoid sphere")
        if not within(target, space["target"]):
            fail(f"{name}: target {target} outside the target box")
        d = math.dist(eye, target)
        if d < space["min_distance"] - 2 * tol or abs(target[1] - eye[1]) > 0.9 * d + 2 * tol:
            fail(f"{name}: target {target} too near {eye} or straight above or below it")

    checked = 0
    for entry in section["scenes"]:
        space = section["spaces"][entry["space"]]
        tris = world_triangles(os.path.join(ROOT, entry["scene"]))
        held = np.zeros(len(tris), bool)  # the objects the avoid spheres keep out
        for c, r in space["avoid"]:
            held |= (np.linalg.norm(tris - np.asarray(c), axis=2) < r).all(1)
        for lo, hi in space["eye"]:
            bad = overlap_box(tris, lo, hi) & ~held
            if bad.any():
                t = tris[np.argmax(bad)].round(2).tolist()
                fail(f"{entry['scene']}: eye box {lo}-{hi} holds {bad.sum()} triangles, "
                     f"the first {t}")
            checked += 1
    # The test of the test: a box around a known wall finds it.
    wall = world_triangles(os.path.join(ROOT, "scenes/cornell_room/cornell_room.gltf"))
    if not overlap_box(wall, [-1.1, 0.5, -0.5], [-0.9, 1.5, 0.5]).any():
        fail("the overlap test misses cornell_room's left wall")
    print(f"PASS: {len(views)} held-out views where their spaces say; {checked} eye boxes "
          "free of triangles")


if __name__ == "__main__":
    main()
