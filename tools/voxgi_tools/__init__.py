"""voxgi's benchmarks and tools, one package: `python -m voxgi_tools COMMAND` (the
shell scripts in tools/ are thin wrappers around it; `python -m voxgi_tools --help`
lists the commands).

Shared here: where the checkout is (ROOT), the voxgi binary and the built-in scenes.
The path-traced references live in voxgi_tools.reference, the image metrics in
voxgi_tools.metrics, the validation set in voxgi_tools.validation_set.
"""
import os

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TOOLS = os.path.join(ROOT, "tools")

# Commands run by a tool (another tool's module in a child python, a Dask worker on
# this machine) find the package too.
if TOOLS not in os.environ.get("PYTHONPATH", "").split(os.pathsep):
    os.environ["PYTHONPATH"] = os.pathsep.join(
        p for p in (TOOLS, os.environ.get("PYTHONPATH", "")) if p)


def voxgi():
    """The voxgi binary of this checkout (tools/build makes it)."""
    return os.path.join(ROOT, "build", "voxgi")


def scene_path(scene):
    """The glTF of a built-in scene, by its folder's name."""
    return os.path.join(ROOT, "scenes", scene, f"{scene}.gltf")
