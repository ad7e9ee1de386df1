"""Every triangle of the hall's meshes is wound counter-clockwise seen from the side
its vertex normals point to (a file whose winding disagrees with its normals shows
renderers its back faces; tools/make-hall once wrote its spheres that way)."""
import json
import os
import sys

import numpy as np

HALL = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scenes", "hall")


def main():
    g = json.load(open(os.path.join(HALL, "hall.gltf")))
    blob = open(os.path.join(HALL, g["buffers"][0]["uri"]), "rb").read()

    def accessor(i, dtype, n):
        a = g["accessors"][i]
        view = g["bufferViews"][a["bufferView"]]
        return np.frombuffer(blob, dtype, a["count"] * n, view["byteOffset"]).reshape(-1, n)

    bad = 0
    for mesh in g["meshes"]:
        for prim in mesh["primitives"]:
            p = accessor(prim["attributes"]["POSITION"], np.float32, 3)
            n = accessor(prim["attributes"]["NORMAL"], np.float32, 3)
            tri = accessor(prim["indices"], np.uint32, 1).reshape(-1, 3)
            face = np.cross(p[tri[:, 1]] - p[tri[:, 0]], p[tri[:, 2]] - p[tri[:, 0]])
            inward = int(((face * n[tri].sum(1)).sum(1) < 0).sum())
            if inward:
                print(f"hall_winding_check: {mesh['name']}: {inward} of {len(tri)} triangles "
                      "wound against their normals", file=sys.stderr)
                bad += 1
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
