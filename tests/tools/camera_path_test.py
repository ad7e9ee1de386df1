"""tools/bench-screen's and bench-motion's camera paths (bench_motion.path_scene):
the camera holds its start pose for `settle` frames, orbits into the view over `move`
frames at 30 fps, and holds the end pose after; with settle 0 the move starts at
t = 0, as before the option existed. Checked on the glTF it writes, without GL."""
import base64
import json
import math
import struct
import tempfile

from tool_support import fail
from voxgi_tools import bench_motion as motion  # noqa: E402


def keys(path):
    """The camera animation's key times and positions."""
    with open(path) as f:
        g = json.load(f)
    anim = next(a for a in g["animations"] if a["name"] == "camera move")
    sampler = anim["samplers"][0]
    out = []
    for acc_index in (sampler["input"], sampler["output"]):
        acc = g["accessors"][acc_index]
        view = g["bufferViews"][acc["bufferView"]]
        uri = g["buffers"][view["buffer"]]["uri"]
        blob = base64.b64decode(uri.split(",", 1)[1])
        raw = blob[view["byteOffset"]:view["byteOffset"] + view["byteLength"]]
        n = {"SCALAR": 1, "VEC3": 3}[acc["type"]]
        vals = struct.unpack(f"<{acc['count'] * n}f", raw)
        out.append([vals[i * n:(i + 1) * n] for i in range(acc["count"])])
    return [t[0] for t in out[0]], out[1]


def close(a, b):
    return all(abs(x - y) < 1e-5 for x, y in zip(a, b))


def main():
    _, eye, target = motion.VIEWS["cornell_room"]
    start = motion.orbit(eye, target, -10.0)
    with tempfile.TemporaryDirectory() as tmp:
        for settle in (0, 30):
            times, pos = keys(motion.path_scene("cornell_room", 5, 3, 10.0, tmp, settle))
            # settle > 0: a key at t = 0 on the start pose, then the move's five keys
            # from settle / 30 s, then the end pose held.
            expect = ([0.0] if settle else []) + [(settle + k) / 30.0 for k in range(5)] + \
                [(settle + 5 + 3 + 1) / 30.0]
            if not close(times, expect):
                fail(f"settle {settle}: key times {times}, expected {expect}")
            if not close(pos[0], start):
                fail(f"settle {settle}: first pose {pos[0]}, expected the start {start}")
            first_move = 1 if settle else 0
            if not close(pos[first_move], start):
                fail(f"settle {settle}: the move starts at {pos[first_move]}, not {start}")
            if not close(pos[-1], eye) or not close(pos[-2], eye):
                fail(f"settle {settle}: the path ends at {pos[-2:]}, not the view's eye {eye}")
    print("camera paths: settle 0 and 30 as expected")


if __name__ == "__main__":
    main()
