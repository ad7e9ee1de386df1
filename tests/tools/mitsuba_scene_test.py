"""voxgi_tools.mitsuba_scene's copy of a glTF scene for Mitsuba 3, checked without
Mitsuba (CI does not install it): the day hall converted with a stand-in for the one
Mitsuba call the conversion makes (a look-at transform). Every material must land on
the BSDF voxgi's path tracer gives it, every emitter and punctual light must carry
its power, the camera its field of view, and the meshes their normals and texture
coordinates, with nothing left out. Run with the tools' .venv python (numpy)."""
import os
import tempfile
import types

from tool_support import ROOT, fail
from voxgi_tools import mitsuba_scene  # noqa: E402


class LookAt:
    def look_at(self, origin, target, up):
        return {"origin": list(origin), "target": list(target), "up": list(up)}


def main():
    mi = types.SimpleNamespace(ScalarTransform4f=LookAt)
    hall = os.path.join(ROOT, "scenes", "hall", "hall.gltf")
    with tempfile.TemporaryDirectory() as ply_dir:
        scene, dropped = mitsuba_scene.convert(mi, hall, 64, 48, ply_dir,
                                               look_from=[9.0, 5.6, 5.2], look_at=[-3.0, 0.6, -1.5])
        if dropped:
            fail(f"the hall lost {dropped}")
        sensor = scene["sensor"]
        if abs(sensor["fov"] - 60.0) > 1e-6 or sensor["fov_axis"] != "y":
            fail(f"field of view {sensor['fov']} (the hall's camera: 60 degrees vertical)")
        if sensor["to_world"]["origin"] != [9.0, 5.6, 5.2] or sensor["film"]["width"] != 64:
            fail(f"camera {sensor}")
        if sensor["film"]["rfilter"]["type"] != "box":
            fail("voxgi jitters over the pixel: a box filter")
        if scene["integrator"] != {"type": "path", "max_depth": 8, "rr_depth": 5}:
            fail(f"integrator {scene['integrator']} (voxgi's path tracer: depth 8, rr from 5)")

        shapes = [v for k, v in scene.items() if k.startswith("shape")]
        kinds = {}
        for s in shapes:
            b = s["bsdf"]
            kind = b["type"] if b["type"] != "twosided" else b["bsdf"]["type"]
            kinds[kind] = kinds.get(kind, 0) + 1
            with open(s["filename"], "rb") as f:
                header = f.read(400).split(b"end_header")[0].decode()
            if "property float nx" not in header:
                fail(f"{s['filename']}: no normals")
        glossy = [s["bsdf"] for s in shapes if s["bsdf"]["type"] == "voxgi_gltf"]
        # floor tiles (textured, 0.9), gallery wood (0.7), bronze (metal, 0.35)
        got = sorted((b["metallic"], b["roughness"]) for b in glossy)
        if got != [(0.0, 0.7), (0.0, 0.9), (1.0, 0.35)]:
            fail(f"glossy materials {got}")
        tiles = [b for b in glossy if b["roughness"] == 0.9][0]["base_color"]
        if tiles["type"] != "bitmap" or tiles["raw"] or not tiles["filename"].endswith(
                "hall_tiles.png"):
            fail(f"the floor's texture {tiles} (sRGB bitmap)")
        mirrors = [s["bsdf"]["bsdf"] for s in shapes
                   if s["bsdf"]["type"] == "twosided" and s["bsdf"]["bsdf"]["type"] == "conductor"]
        if len(mirrors) != 1 or mirrors[0]["material"] != "none":
            fail(f"mirror {mirrors} (a conductor without Fresnel)")
        if kinds.get("diffuse", 0) < 5:
            fail(f"Lambert materials {kinds}")

        emitters = sorted(tuple(round(c, 4) for c in s["emitter"]["radiance"]["value"])
                          for s in shapes if "emitter" in s)
        if emitters != [(4.0, 4.2, 4.6), (160.0, 130.0, 90.0)]:
            fail(f"emitters {emitters} (emissiveFactor x emissiveStrength)")

        lights = [v for k, v in scene.items() if k.startswith("light")]
        types_ = sorted(l["type"] for l in lights)
        if types_ != ["directional", "point", "point", "point", "point", "spot"]:
            fail(f"lights {types_}")
        sun = [l for l in lights if l["type"] == "directional"][0]
        if [round(c, 4) for c in sun["irradiance"]["value"]] != [6.0, 5.7, 5.1]:
            fail(f"sun {sun}")
        spot = [l for l in lights if l["type"] == "spot"][0]
        if abs(spot["cutoff_angle"] - 20.0535) > 1e-3 or abs(spot["beam_width"] - 11.4592) > 1e-3:
            fail(f"spot cones {spot}")
    print(f"mitsuba_scene: {len(shapes)} shapes ({kinds}), {len(lights)} lights: ok")


if __name__ == "__main__":
    main()
