"""The mirror and glossy regions of a view (tools/voxgi_tools/regions.py), which
tools/bench-convergence measures FLIP over: each class's materials by rtgi's rule,
masks that hold the surfaces a view shows and nothing else, and FLIP over a region
that sees an error inside it and not one outside it.

Usage: regions_test.py VOXGI"""
import json
import os
import sys
import tempfile

import numpy as np

from tool_support import fail
from voxgi_tools import metrics, regions, validation_set  # noqa: E402

SIZE = "64x64"


def classes():
    cases = [({"pbrMetallicRoughness": {"roughnessFactor": 0.0, "metallicFactor": 1.0}}, "mirrors"),
             ({"pbrMetallicRoughness": {"roughnessFactor": 0.35, "metallicFactor": 1.0}}, "glossy"),
             ({"pbrMetallicRoughness": {"roughnessFactor": 0.3, "metallicFactor": 0.0}}, "glossy"),
             ({"pbrMetallicRoughness": {"roughnessFactor": 0.9, "metallicFactor": 0.0}}, None),
             ({"pbrMetallicRoughness": {"roughnessFactor": 0.9}}, "glossy"),  # metallic 1
             ({}, "glossy")]  # glTF's defaults: metallic 1, roughness 1
    for m, want in cases:
        got = regions.material_class(m)
        if got != want:
            fail(f"material {m}: class {got}, expected {want}")


def erode(mask, n):
    """`mask` less the pixels within n of a pixel outside it."""
    m = mask.copy()
    for _ in range(n):
        p = np.pad(m, 1)
        m = m & p[:-2, 1:-1] & p[2:, 1:-1] & p[1:-1, :-2] & p[1:-1, 2:]
    return m


def save(path, rgb):
    import matplotlib.image as mpimg
    mpimg.imsave(path, np.clip(rgb, 0.0, 1.0))


def main():
    binary = sys.argv[1]
    classes()
    views = dict((v, (s, f)) for v, s, f in validation_set.views(["cornell_room", "hall"],
                                                                   make=False))
    with tempfile.TemporaryDirectory() as out:
        # cornell_room: its mirror sphere, no glossy material.
        scene, flags = views["cornell_room"]
        room = regions.masks("cornell_room", scene, flags, SIZE, out, binary)
        if set(room) != {"mirrors"}:
            fail(f"cornell_room's regions are {sorted(room)}, expected its mirror sphere alone")
        share = room["mirrors"].mean()
        # The sphere covers 7.9% of the 256x256 image (5,169 pixels).
        if not 0.05 < share < 0.11:
            fail(f"cornell_room's mirror region holds {share:.1%} of the pixels, not about 8%")
        # The hall: its mirror ball and its bronze knot, apart.
        scene, flags = views["hall"]
        hall = regions.masks("hall", scene, flags, SIZE, out, binary)
        if set(hall) != {"mirrors", "glossy"}:
            fail(f"the hall's regions are {sorted(hall)}, expected mirrors and glossy")
        if (hall["mirrors"] & hall["glossy"]).any():
            fail("a pixel of the hall is in both regions")
        # The copies: only the class's materials changed, and they reach the buffers.
        copy = regions.scene_copy(scene, out, ("glossy",), emit=True)
        with open(scene) as f:
            before = json.load(f)["materials"]
        with open(copy) as f:
            after = json.load(f)["materials"]
        for b, a in zip(before, after):
            if regions.material_class(b) == "glossy":
                if a.get("emissiveFactor") != [1.0, 1.0, 1.0]:
                    fail(f"glossy material {b.get('name')} does not emit in the copy: {a}")
            elif a != b:
                fail(f"material {b.get('name')} changed, but it is not glossy")
        # FLIP over a region sees an error inside it, and none outside it.
        mask = room["mirrors"]
        ref = np.full(mask.shape + (3,), 0.4)
        inside, outside = ref.copy(), ref.copy()
        inside[mask] = 0.9
        outside[~mask] = 0.9
        for name, img in (("ref", ref), ("inside", inside), ("outside", outside)):
            save(os.path.join(out, name + ".png"), img)
        r = os.path.join(out, "ref.png")
        whole_in, reg_in = metrics.flip(os.path.join(out, "inside.png"), r, regions=room)
        whole_out = metrics.flip(os.path.join(out, "outside.png"), r)
        if not reg_in["mirrors"] > 0.2:
            fail(f"an error inside the mirror region: FLIP over it {reg_in['mirrors']:.3f}")
        if not whole_in < reg_in["mirrors"] * 0.5:
            fail(f"the region's FLIP ({reg_in['mirrors']:.3f}) is not the region's alone "
                 f"(whole image {whole_in:.3f})")
        # FLIP spreads an edge over a few pixels, so an error outside reaches the region's
        # rim: the region's inside, 4 pixels from its rim, sees next to none of it.
        core = erode(mask, 4)
        if not core.any():
            fail("the mirror region has no pixel 4 pixels from its rim")
        _, reg_core = metrics.flip(os.path.join(out, "outside.png"), r, regions={"core": core})
        if not reg_core["core"] < 0.01 * whole_out:
            fail(f"an error outside the mirror region: FLIP inside it {reg_core['core']:.3f}, "
                 f"the whole image {whole_out:.3f}")
    print("ok")


if __name__ == "__main__":
    main()
