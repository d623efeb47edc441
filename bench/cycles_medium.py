"""Blender Cycles render of a glTF scene filled with a homogeneous participating medium, as a
penumbra pass script's [[medium]] gives it (docs/media.md), so that penumbra's volumetric path
tracer can be compared with Cycles' (docs/benchmarks.md, "Participating media").

Not a test and not part of the build: a benchmark helper for Blender's Python. It runs the peer
harness's cycles_render.py (../shared/peers; see its README) unchanged, with every argument after
this script's own, and adds the medium just before the render starts:

    blender -b --factory-startup -P bench/cycles_medium.py -- \
        --peers ../shared/peers --sigma-a R,G,B --sigma-s R,G,B [--g G] \
        [--box X0,Y0,Z0,X1,Y1,Z1 | --density FILE.vdb [--density-grid NAME]] \
        CYCLES_RENDER_ARGS...

The medium is a box (--box in the glTF file's frame, metres; by default the bounding box of the
scene's meshes, as penumbra's default, widened by 1e-5 of its diagonal) whose surface is invisible and whose volume shader is Cycles' Volume Scatter
(colour sigma_s / D_s, density D_s = the largest channel of sigma_s, anisotropy g: Cycles'
phase function is Henyey-Greenstein's) plus Volume Absorption (colour 1 - sigma_a / D_a, density
D_a = the largest channel of sigma_a), so that Cycles' coefficients per metre, density times
colour and density times one less the colour, are penumbra's. The material is marked
homogeneous (Cycles then samples distances analytically, not by ray marching), and the volume
bounce limit, which the harness sets to 0, is raised to its --max-bounces (default 64).

With --density, the medium is instead the OpenVDB file's grid (--density-grid, default
"density") as a Volume object placed by the file's voxel transform in the glTF frame (a quarter
turn about X into Blender's), both densities multiplied by the grid's value (an Attribute node),
read at full precision with linear interpolation and moved back by half a voxel to where
OpenVDB puts its values (add_density_volume says why); Cycles ray-marches it, with steps of a quarter
of a voxel (--step-rate, default 0.25) to keep its marching error small. A box stretching the
grid (penumbra's `box` with `density`) is not supported here.
"""
import argparse
import os
import sys
import traceback

import bpy
from mathutils import Matrix, Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_harness import run_harness, to_blender  # noqa: E402


def triple(text):
    values = [float(x) for x in text.split(",")]
    if len(values) != 3 or min(values) < 0.0:
        raise argparse.ArgumentTypeError("expected three numbers >= 0: %s" % text)
    return values


def parse_own_args():
    """This script's options, and the rest of the arguments after "--" for cycles_render.py."""
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser(prog="cycles_medium.py")
    ap.add_argument("--peers", required=True, help="the folder holding cycles_render.py")
    ap.add_argument("--sigma-a", type=triple, default=[0.0, 0.0, 0.0], help="per metre")
    ap.add_argument("--sigma-s", type=triple, default=[0.0, 0.0, 0.0], help="per metre")
    ap.add_argument("--g", type=float, default=0.0, help="Henyey-Greenstein asymmetry")
    ap.add_argument("--box", default=None, help="x0,y0,z0,x1,y1,z1 in the glTF frame")
    ap.add_argument("--density", default=None, help="an OpenVDB file whose grid scales both")
    ap.add_argument("--density-grid", default="density", help="the grid's name")
    ap.add_argument("--step-rate", type=float, default=0.25, help="Cycles' volume step rate")
    own, rest = ap.parse_known_args(argv)
    bounces = rest[rest.index("--max-bounces") + 1] if "--max-bounces" in rest else 64
    return own, rest, int(bounces)


def scene_bounds(scene):
    """The corners of the bounding box of the scene's meshes, in Blender's frame, widened by a
    hundred-thousandth of its diagonal: penumbra's medium ends at the bounds, which no surface
    marks, where Cycles' ends at the box's faces, and faces in the planes of the scene's walls
    would meet their rays at the same distances."""
    lo, hi = [float("inf")] * 3, [float("-inf")] * 3
    for obj in scene.objects:
        if obj.type != "MESH":
            continue
        for corner in obj.bound_box:
            p = obj.matrix_world @ Vector(corner)
            lo = [min(a, b) for a, b in zip(lo, p)]
            hi = [max(a, b) for a, b in zip(hi, p)]
    margin = 1e-5 * sum((b - a) ** 2 for a, b in zip(lo, hi)) ** 0.5
    return [a - margin for a in lo], [b + margin for b in hi]


def volume_material(sigma_a, sigma_s, g, grid=None):
    """Volume Scatter + Volume Absorption with the coefficients per metre given, both scaled by
    the volume's attribute `grid` when one is named."""
    material = bpy.data.materials.new("penumbra medium")
    material.use_nodes = True
    material.cycles.homogeneous_volume = grid is None
    material.cycles.volume_interpolation = "LINEAR"
    nodes, links = material.node_tree.nodes, material.node_tree.links
    nodes.clear()
    total = nodes.new("ShaderNodeAddShader")
    scatter_density, absorb_density = max(sigma_s), max(sigma_a)
    scatter = nodes.new("ShaderNodeVolumeScatter")
    scatter.inputs["Density"].default_value = scatter_density
    scatter.inputs["Anisotropy"].default_value = g
    scatter.inputs["Color"].default_value = [
        s / scatter_density if scatter_density > 0.0 else 0.0 for s in sigma_s] + [1.0]
    absorb = nodes.new("ShaderNodeVolumeAbsorption")
    absorb.inputs["Density"].default_value = absorb_density
    absorb.inputs["Color"].default_value = [
        1.0 - a / absorb_density if absorb_density > 0.0 else 1.0 for a in sigma_a] + [1.0]
    if grid is not None:
        attribute = nodes.new("ShaderNodeAttribute")
        attribute.attribute_name = grid
        for shader, density in ((scatter, scatter_density), (absorb, absorb_density)):
            scale = nodes.new("ShaderNodeMath")
            scale.operation = "MULTIPLY"
            scale.inputs[1].default_value = density
            links.new(attribute.outputs["Fac"], scale.inputs[0])
            links.new(scale.outputs["Value"], shader.inputs["Density"])
    links.new(scatter.outputs["Volume"], total.inputs[0])
    links.new(absorb.outputs["Volume"], total.inputs[1])
    output = nodes.new("ShaderNodeOutputMaterial")
    links.new(total.outputs["Shader"], output.inputs["Volume"])
    return material


def add_medium_box(scene, lo, hi, material):
    """A box from lo to hi (Blender's frame) with the volume material and no surface."""
    mesh = bpy.data.meshes.new("penumbra medium")
    corners = [(x, y, z) for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    mesh.from_pydata(corners, [], faces)
    mesh.materials.append(material)
    box = bpy.data.objects.new("penumbra medium", mesh)
    scene.collection.objects.link(box)


def add_density_volume(scene, path, grid_name, material):
    """The OpenVDB file as a Volume object, its voxel transform's frame (glTF's) turned into
    Blender's: (x, y, z) -> (x, -z, y), and moved back by half a voxel on each axis: Blender 3.4
    samples a voxel's value half a voxel past the centre OpenVDB gives it (measured: the
    silhouette of an absorbing plume, 16 x 16 blocks of 128 x 128 pixels, differs by 0.79-1.23
    from penumbra's, which matches OpenVDB's own BoxSampler, tests/core/vdb_reader_test.cpp;
    by 0.95-1.02 with this shift, and by 0.65-1.52 with the opposite one)."""
    volume = bpy.data.volumes.new("penumbra density")
    volume.filepath = path
    volume.render.precision = "FULL"
    volume.grids.load()
    volume.materials.append(material)
    names = [grid.name for grid in volume.grids]
    obj = bpy.data.objects.new("penumbra density", volume)
    half_voxel = Vector((0.0, 0.0, 0.0))
    if grid_name in names:
        index_to_object = volume.grids[grid_name].matrix_object
        half_voxel = index_to_object.to_3x3() @ Vector((0.5, 0.5, 0.5))
    obj.matrix_world = (Matrix(((1, 0, 0, 0), (0, 0, -1, 0), (0, 1, 0, 0), (0, 0, 0, 1))) @
                        Matrix.Translation(-half_voxel))
    scene.collection.objects.link(obj)
    return names


def main():
    own, rest, bounces = parse_own_args()

    # The harness clears the scene (its materials too), imports it, sets the render up, then
    # renders: the medium is made, and the volume bounces allowed, as the render begins. A
    # failure there ends Blender at once: Blender would otherwise render without the medium.
    def add_medium(scene, *_):
        try:
            add(scene)
        except Exception:
            traceback.print_exc()
            os._exit(1)

    def add(scene):
        if own.density:
            if own.box:
                raise RuntimeError("--box with --density is not supported")
            material = volume_material(own.sigma_a, own.sigma_s, own.g, own.density_grid)
            grids = add_density_volume(scene, own.density, own.density_grid, material)
            if own.density_grid not in grids:
                raise RuntimeError("%s: no grid %s (%s)" % (own.density, own.density_grid, grids))
            scene.cycles.volume_bounces = bounces
            scene.cycles.volume_step_rate = own.step_rate
            print("medium sigma_a %s, sigma_s %s, g %g, density %s (grids %s), volume bounces %d"
                  % (own.sigma_a, own.sigma_s, own.g, own.density, grids, bounces))
            return
        if own.box:
            v = [float(x) for x in own.box.split(",")]
            a, b = to_blender(v[0:3]), to_blender(v[3:6])
            lo = [min(p, q) for p, q in zip(a, b)]
            hi = [max(p, q) for p, q in zip(a, b)]
        else:
            lo, hi = scene_bounds(scene)
        add_medium_box(scene, lo, hi, volume_material(own.sigma_a, own.sigma_s, own.g))
        scene.cycles.volume_bounces = bounces
        print("medium sigma_a %s, sigma_s %s, g %g, box %s to %s, volume bounces %d" %
              (own.sigma_a, own.sigma_s, own.g, lo, hi, bounces))

    bpy.app.handlers.render_init.append(add_medium)
    run_harness(own.peers, rest)


main()
