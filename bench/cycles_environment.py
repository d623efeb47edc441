"""Blender Cycles render of a glTF scene lit by an equirectangular environment map, so that an
environment-lit scene can be compared with penumbra (bench/cycles_comparison.py --environment).

Not a test and not part of the build: a benchmark helper for Blender's Python. It runs the peer
harness's cycles_render.py (../shared/peers; see its README) unchanged, with every argument after
this script's own, and gives the world the environment just before the render starts (the harness
makes it black):

    blender -b --factory-startup -P bench/cycles_environment.py -- \
        --peers ../shared/peers [--environment FILE] [--environment-scale S] \
        [--environment-rotation DEG] [--portal P ...] CYCLES_RENDER_ARGS...

Without --environment, the map is the scene's own, read as penumbra reads it (docs/lights.md,
"Environment light"): `scenes[0].extras.mitsuba_environment[0]` of the glTF file given by
--scene (its file, scale and toWorld_rowmajor). --environment-scale multiplies the scale;
--environment-rotation turns the map about +Y after its own frame, as penumbra's option does.
Each --portal (penumbra's form: a corner and its two neighbouring corners, nine numbers in the
glTF file's frame, as `penumbra info` prints the openings it finds) becomes a Cycles portal: a
rectangular area light marked as a portal, facing the camera's side of its plane (Cycles samples
the world through portals it is given; the peer harness gives it none).

The map is looked up in penumbra's orientation (docs/lights.md): for a world direction d (glTF
axes, +Y up) and d' = R^T d in the map's frame, u = atan2(d'.x, -d'.z) / 2 pi and v = acos(d'.y)
/ pi from the top row. Blender's world is the glTF one with (x, y, z) -> (x, -z, y), and its
equirectangular lookup of a vector e is u = 1/2 - atan2(e.y, e.x) / 2 pi, v = acos(e.z) / pi from
the top row (Cycles' direction_to_equirectangular), so e = (d'.z, d'.x, d'.y). The world shader
computes e from the ray direction with three dot products (one matrix, no Euler angles) and
samples the image with linear interpolation, as penumbra's bilinear lookup; its strength is the
scale, since Cycles' pixel values are the radiance numbers of the map (the harness's COMPAT
lighting mode keeps cd/m2 numbers 1:1).
"""
import argparse
import json
import math
import os
import sys

import bpy
from mathutils import Matrix, Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_harness import run_harness, to_blender  # noqa: E402


def parse_own_args():
    """This script's options, and the rest of the arguments after "--" for cycles_render.py."""
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser(prog="cycles_environment.py")
    ap.add_argument("--peers", required=True, help="the folder holding cycles_render.py")
    ap.add_argument("--environment", default=None,
                    help="equirectangular map (default: the scene's own, from its extras)")
    ap.add_argument("--environment-scale", type=float, default=1.0)
    ap.add_argument("--environment-rotation", type=float, default=0.0,
                    help="degrees about +Y, counter-clockwise seen from above")
    ap.add_argument("--portal", action="append", default=[],
                    help="x0,y0,z0,x1,y1,z1,x2,y2,z2: a corner and its two neighbours (glTF)")
    own, rest = ap.parse_known_args(argv)
    scene = rest[rest.index("--scene") + 1] if "--scene" in rest else None
    return own, rest, scene


def scene_environment(gltf_path):
    """File, scale and 3 x 3 rotation (rows) of the glTF scene's own environment."""
    with open(gltf_path) as f:
        document = json.load(f)
    try:
        record = document["scenes"][0]["extras"]["mitsuba_environment"][0]
    except (KeyError, IndexError, TypeError):
        raise SystemExit("%s: no environment in scenes[0].extras and no --environment"
                         % gltf_path)
    m = record.get("toWorld_rowmajor", [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1])
    rotation = [m[0:3], m[4:7], m[8:11]]
    path = os.path.join(os.path.dirname(os.path.abspath(gltf_path)), record["file"])
    return path, float(record.get("scale", 1.0)), rotation


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def transpose(a):
    return [[a[j][i] for j in range(3)] for i in range(3)]


def about_y(degrees):
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    return [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]


# Blender's direction to glTF's: (x, y, z)_Blender = (x, -z, y)_glTF.
BLENDER_TO_GLTF = [[1, 0, 0], [0, 0, 1], [0, -1, 0]]
# penumbra's map frame to the vector Cycles' equirectangular lookup takes: e = (d'.z, d'.x, d'.y).
MAP_TO_CYCLES = [[0, 0, 1], [1, 0, 0], [0, 1, 0]]


def environment_world(path, scale, to_world):
    """A world whose background is the map, looked up as penumbra does; to_world: the map's frame
    in glTF world axes (rows)."""
    lookup = matmul(MAP_TO_CYCLES, matmul(transpose(to_world), BLENDER_TO_GLTF))
    world = bpy.data.worlds.new("penumbra environment")
    world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    nodes.clear()
    coordinates = nodes.new("ShaderNodeTexCoord")
    combine = nodes.new("ShaderNodeCombineXYZ")
    for row, axis in zip(lookup, ("X", "Y", "Z")):
        dot = nodes.new("ShaderNodeVectorMath")
        dot.operation = "DOT_PRODUCT"
        links.new(coordinates.outputs["Generated"], dot.inputs[0])
        dot.inputs[1].default_value = row
        links.new(dot.outputs["Value"], combine.inputs[axis])
    texture = nodes.new("ShaderNodeTexEnvironment")
    texture.image = bpy.data.images.load(path, check_existing=True)
    try:
        texture.image.colorspace_settings.name = "Linear"
    except TypeError:
        texture.image.colorspace_settings.name = "Linear Rec.709"
    texture.interpolation = "Linear"
    texture.projection = "EQUIRECTANGULAR"
    links.new(combine.outputs["Vector"], texture.inputs["Vector"])
    background = nodes.new("ShaderNodeBackground")
    background.inputs["Strength"].default_value = scale
    links.new(texture.outputs["Color"], background.inputs["Color"])
    output = nodes.new("ShaderNodeOutputWorld")
    links.new(background.outputs["Background"], output.inputs["Surface"])
    return world


def add_portal(scene, spec, index):
    """A Cycles portal light over penumbra's portal `spec`, facing the camera."""
    v = [float(x) for x in spec.split(",")]
    if len(v) != 9:
        raise SystemExit("cycles_environment.py: --portal %s: expected nine numbers" % spec)
    p0, p1, p2 = (Vector(to_blender(v[i:i + 3])) for i in (0, 3, 6))
    u, w = p1 - p0, p2 - p0
    centre = p0 + 0.5 * (u + w)
    z = u.cross(w).normalized()
    # An area light shines along its -Z: towards the camera, inside the room.
    if z.dot(scene.camera.matrix_world.translation - centre) > 0.0:
        z = -z
    x = u.normalized()
    y = z.cross(x)
    light = bpy.data.lights.new("penumbra portal %d" % index, type="AREA")
    light.shape = "RECTANGLE"
    light.size, light.size_y = u.length, w.length
    light.cycles.is_portal = True
    portal = bpy.data.objects.new(light.name, light)
    frame = Matrix((x, y, z)).transposed().to_4x4()
    frame.translation = centre
    portal.matrix_world = frame
    scene.collection.objects.link(portal)


def main():
    own, rest, gltf = parse_own_args()
    if own.environment:
        path, scale, to_world = own.environment, 1.0, [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    elif gltf:
        path, scale, to_world = scene_environment(gltf)
    else:
        raise SystemExit("cycles_environment.py: --environment or --scene is needed")
    if not os.path.exists(path):
        raise SystemExit("cycles_environment.py: %s: no such file" % path)
    to_world = matmul(about_y(own.environment_rotation), to_world)
    world = environment_world(path, scale * own.environment_scale, to_world)
    print("environment %s, scale %g, frame rows %s" % (path, scale * own.environment_scale,
                                                       [[round(x, 6) for x in r] for r in to_world]))

    # The harness clears the scene and blacks its world, imports, sets the render up, then
    # renders: the world is swapped in, and the portals added, as the render begins.
    def use_environment(scene, *_):
        scene.world = world
        for index, spec in enumerate(own.portal):
            add_portal(scene, spec, index)

    bpy.app.handlers.render_init.append(use_environment)
    run_harness(own.peers, rest)


main()
