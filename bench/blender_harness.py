"""What the benchmark's Blender scripts (cycles_environment.py, cycles_medium.py) share: the glTF
frame in Blender's, and running the peer harness's cycles_render.py (../shared/peers; see its
README) unchanged after a script has hooked what it adds to the scene.

Not a test and not part of the build: imported by those scripts inside Blender's Python.
"""
import os
import sys


def to_blender(p):
    """A glTF point or direction in Blender's frame: (x, y, z) -> (x, -z, y)."""
    return (p[0], -p[2], p[1])


def run_harness(peers, harness_args):
    """Runs peers/cycles_render.py with `harness_args` (the arguments after its "--")."""
    harness = os.path.join(peers, "cycles_render.py")
    sys.argv = [sys.argv[0], harness, "--"] + harness_args
    with open(harness) as f:
        code = compile(f.read(), harness, "exec")
    exec(code, {"__name__": "__main__", "__file__": harness})
