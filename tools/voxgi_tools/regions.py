"""The pixels of a view that show its mirrors, and those that show its glossy surfaces:
where rtgi's specular stage carries the light, measured apart from the whole image.

A material's class follows its factors (textures are not read), by rtgi's own rule
(shaders/include/brdf_shared.h isSpecular, rtgi_shared.h kMirrorRoughness):
  mirrors  roughness below MIRROR_ROUGHNESS (0.05)
  glossy   the rest of what the specular stage traces: metals (metallic over 0.5) and
           dielectrics smoother than GLOSSY_ROUGHNESS (0.6)
A region's mask comes from two renders of a copy of the scene with only the camera's
rays (`--mode pathtrace --max-depth 1`): the class's materials black in one, black
and emitting white in the other. A pixel is in the region where the two differ by
more than half: it sees the class's surfaces directly over most of its area.
"""
import json
import os
import subprocess

import numpy as np

from voxgi_tools import voxgi

MIRROR_ROUGHNESS = 0.05
GLOSSY_ROUGHNESS = 0.6
CLASSES = ("mirrors", "glossy")
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def material_class(m):
    """'mirrors', 'glossy' or None for glTF material `m`, by its factors."""
    pbr = m.get("pbrMetallicRoughness", {})
    rough = pbr.get("roughnessFactor", 1.0)
    metal = pbr.get("metallicFactor", 1.0)
    if rough < MIRROR_ROUGHNESS:
        return "mirrors"
    if metal > 0.5 or rough < GLOSSY_ROUGHNESS:
        return "glossy"
    return None


def scene_copy(scene, out, classes, emit=False, tag=None):
    """`scene`, or where it has materials of `classes` a copy of it in out/TAG/ whose
    such materials are black and diffuse (and, with `emit`, emit white at strength 1);
    the copy's folder links the scene's other files (buffers, images)."""
    with open(scene) as f:
        gltf = json.load(f)
    hits = [m for m in gltf.get("materials", []) if material_class(m) in classes]
    if not hits:
        return scene
    for m in hits:
        m["pbrMetallicRoughness"] = {"baseColorFactor": [0.0, 0.0, 0.0, 1.0],
                                     "metallicFactor": 0.0, "roughnessFactor": 1.0}
        for key in ("extensions", "normalTexture", "occlusionTexture", "emissiveTexture",
                    "emissiveFactor"):
            m.pop(key, None)
        if emit:
            m["emissiveFactor"] = [1.0, 1.0, 1.0]
    src = os.path.dirname(os.path.abspath(scene))
    dst = os.path.join(out, tag or "-".join(classes) + ("-emitting" if emit else "-dark"),
                       os.path.basename(src))
    os.makedirs(dst, exist_ok=True)
    for name in os.listdir(src):
        link = os.path.join(dst, name)
        if not name.endswith(".gltf") and not os.path.lexists(link):
            os.symlink(os.path.join(src, name), link)
    copy = os.path.join(dst, os.path.basename(scene))
    with open(copy, "w") as f:
        json.dump(gltf, f)
    return copy


def read_luminance(exr):
    """Linear luminance of `exr`, clamped to [0, 1] (a 16-bit linear PNG that oiiotool
    writes, which matplotlib reads: no EXR reader needed in the venv)."""
    import matplotlib.image as mpimg

    png = exr[:-4] + "_linear16.png"
    subprocess.run(["oiiotool", exr, "--ch", "R,G,B", "-d", "uint16", "-o", png], check=True,
                   capture_output=True)
    return np.asarray(mpimg.imread(png), dtype=np.float64)[..., :3] @ LUMINANCE


def masks(view, scene, flags, size, out, binary=None):
    """{class: HxW bool array} of `view` (scene and its camera `flags`) at `size`, for
    each class with at least one pixel."""
    found = {}
    for cls in CLASSES:
        images = []
        for emit in (False, True):
            copy = scene_copy(scene, out, (cls,), emit)
            if copy == scene:
                break
            exr = os.path.join(os.path.dirname(copy), f"{view}_{size}.exr")
            subprocess.run([binary or voxgi(), "render", copy] + list(flags) + [
                "--mode", "pathtrace", "--max-depth", "1", "--spp", "16", "--size", size,
                "--out", exr, "--no-progress", "-q"], check=True)
            images.append(read_luminance(exr))
        if len(images) == 2:
            mask = images[1] - images[0] > 0.5
            if mask.any():
                found[cls] = mask
    return found
