"""tools/bench-terms' scene copy for the terms without specular
(bench_terms.without_mirrors): the materials smoother than rtgi's mirror roughness
become black and diffuse, every other material is kept as it was, the copy's folder
reaches the scene's buffers, and a scene without mirrors is used as it is."""
import json
import os
import tempfile

from tool_support import ROOT, fail
from voxgi_tools import bench_terms  # noqa: E402


def materials(path):
    with open(path) as f:
        return json.load(f)["materials"]


def main():
    scene = os.path.join(ROOT, "scenes", "cornell_room", "cornell_room.gltf")
    with tempfile.TemporaryDirectory() as out:
        copy = bench_terms.without_mirrors(scene, out)
        if copy == scene:
            fail("cornell_room has a mirror sphere, but no copy was made")
        before, after = materials(scene), materials(copy)
        if len(before) != len(after):
            fail("the copy has another number of materials")
        darkened = 0
        for b, a in zip(before, after):
            rough = b.get("pbrMetallicRoughness", {}).get("roughnessFactor", 1.0)
            if rough < bench_terms.MIRROR_ROUGHNESS:
                pbr = a["pbrMetallicRoughness"]
                if pbr["baseColorFactor"][:3] != [0.0, 0.0, 0.0] or pbr["metallicFactor"] != 0.0:
                    fail(f"mirror {b.get('name')} is not black and diffuse in the copy: {pbr}")
                darkened += 1
            elif a != b:
                fail(f"material {b.get('name')} changed, but it is not a mirror")
        if darkened != 1:
            fail(f"expected cornell_room's one mirror material, darkened {darkened}")
        with open(copy) as f:
            for buf in json.load(f)["buffers"]:
                if not os.path.isfile(os.path.join(os.path.dirname(copy), buf["uri"])):
                    fail(f"the copy's folder does not reach buffer {buf['uri']}")
        # Again into the same folder: the links are there already.
        if bench_terms.without_mirrors(scene, out) != copy:
            fail("a second call wrote elsewhere")
        # No mirror: the scene itself.
        plain = os.path.join(out, "plain.gltf")
        g = {"asset": {"version": "2.0"},
             "materials": [{"pbrMetallicRoughness": {"roughnessFactor": 0.5}}]}
        with open(plain, "w") as f:
            json.dump(g, f)
        if bench_terms.without_mirrors(plain, out) != plain:
            fail("a scene without mirrors was copied")
    print("ok")


if __name__ == "__main__":
    main()
