"""Variants of the measured Cornell box for the regression scenes (scenes/glossy,
scenes/caustic-spheres): the published walls, floor, ceiling, paints and camera of
make_cornell_box.py, without the two blocks, with spheres of any material inside and a square
ceiling light of any size and luminance.

The paints and the light's colour are read from the committed cornell-box.gltf (so the variants
need neither the spectral data nor a re-run of the spectral conversion); the geometry helpers,
the winding checks and the glTF writer are make_cornell_box.py's own.
"""

import base64
import json
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import make_cornell_box as cb  # noqa: E402  (the folder is put on the path just above)

CORNELL_GLTF = os.path.join(HERE, "cornell-box.gltf")
# Cornell box light: emissiveStrength 83.263996 gives a luminance of exactly 50 cd/m^2 with its
# emissiveFactor (README.md, "Colours"); a variant's strength scales with its luminance.
CORNELL_LIGHT_LUMINANCE = 50.0
# Sphere tessellation: segments around the vertical axis, rings from pole to pole. At 128 x 128
# pixels a sphere of radius 0.1 m covers about 40 pixels, so facets stay below a pixel on the
# silhouette; smooth vertex normals make the shading continuous.
SPHERE_SEGMENTS, SPHERE_RINGS = 64, 32


def cornell_materials():
    """The committed box's materials by name (white, red, green, light)."""
    with open(CORNELL_GLTF, encoding="utf-8") as f:
        doc = json.load(f)
    return {m["name"]: m for m in doc["materials"]}


def light_material(luminance):
    """The Cornell light's warm colour at `luminance` cd/m^2 (emissiveFactor x emissiveStrength is
    the radiance per linear-sRGB channel)."""
    light = json.loads(json.dumps(cornell_materials()["light"]))
    strength = light["extensions"]["KHR_materials_emissive_strength"]
    strength["emissiveStrength"] = cb.rounded(strength["emissiveStrength"] * luminance /
                                              CORNELL_LIGHT_LUMINANCE)
    return light


def unit_sphere():
    """Positions (= outward unit normals) and counter-clockwise indices of a UV sphere of radius 1.
    The poles get one vertex per segment and one triangle per segment, so no triangle is
    degenerate."""
    positions = []
    for ring in range(SPHERE_RINGS + 1):
        theta = math.pi * ring / SPHERE_RINGS
        for seg in range(SPHERE_SEGMENTS + 1):
            phi = 2.0 * math.pi * seg / SPHERE_SEGMENTS
            positions.append((math.sin(theta) * math.cos(phi), math.cos(theta),
                              -math.sin(theta) * math.sin(phi)))
    row = SPHERE_SEGMENTS + 1
    indices = []
    for ring in range(SPHERE_RINGS):
        for seg in range(SPHERE_SEGMENTS):
            a, b = ring * row + seg, ring * row + seg + 1
            c, d = a + row, b + row
            if ring > 0:
                indices += [a, c, b]
            if ring < SPHERE_RINGS - 1:
                indices += [b, c, d]
    for t in range(0, len(indices), 3):
        p = [positions[i] for i in indices[t:t + 3]]
        n = cb.triangle_normal(*p)
        assert cb.dot(n, cb.centroid(p)) > 0.0, "sphere triangle wound inward"
    return positions, indices


def build_scene(name, generator, light_size_m, luminance, spheres, extras):
    """The glTF document of a box variant.

    light_size_m: side of the square light, centred under the ceiling like the Cornell light.
    luminance: the light's luminance in cd/m^2.
    spheres: (node name, material dict, centre (m), radius (m)) for each sphere.
    extras: added to asset.extras (say what the scene is for)."""
    paints = cornell_materials()
    materials = [paints["white"], paints["red"], paints["green"], light_material(luminance)]
    index = {"white": 0, "red": 1, "green": 2}

    # The Cornell light's centre, 0.1 mm below the ceiling as in make_cornell_box.py.
    cx = 0.5 * (cb.LIGHT[0][0] + cb.LIGHT[2][0]) / 1000.0
    cz = 0.5 * (cb.LIGHT[0][2] + cb.LIGHT[1][2]) / 1000.0
    y = (cb.LIGHT[0][1] / 1000.0) - cb.LIGHT_OFFSET
    h = 0.5 * light_size_m
    light = [(cx + h, y, cz - h), (cx + h, y, cz + h), (cx - h, y, cz + h), (cx - h, y, cz - h)]
    down = (0.0, -1.0, 0.0)
    surfaces = [(n, m, cb.to_metres(q), i) for (n, m, q, i) in (
        ("floor", "white", cb.FLOOR, (0.0, 1.0, 0.0)),
        ("ceiling", "white", cb.CEILING, down),
        ("back_wall", "white", cb.BACK_WALL, (0.0, 0.0, -1.0)),
        ("red_wall", "red", cb.RED_WALL, (-1.0, 0.0, 0.0)),
        ("green_wall", "green", cb.GREEN_WALL, (1.0, 0.0, 0.0)))]
    surfaces.append(("light", "light", light, down))
    index["light"] = 3

    builder = cb.GltfBuilder()
    meshes, nodes = [], []
    for mesh_name, material, quad, intended in surfaces:
        positions, normals, indices = cb.quad_primitive(cb.orient_quad(quad, intended), intended,
                                                        0.999)
        meshes.append({"name": mesh_name, "primitives": [{
            "attributes": {"POSITION": builder.vec3(positions, True),
                           "NORMAL": builder.vec3(normals, False)},
            "indices": builder.indices(indices), "material": index[material], "mode": 4}]})
        nodes.append({"name": mesh_name, "mesh": len(meshes) - 1})

    # One unit sphere shared by every sphere mesh; nodes place and scale it (uniform scale keeps
    # the normals exact).
    sphere_positions, sphere_indices = unit_sphere()
    sphere_attributes = {"POSITION": builder.vec3(sphere_positions, True),
                         "NORMAL": builder.vec3(sphere_positions, False)}
    sphere_index_accessor = builder.indices(sphere_indices)
    for node_name, material, centre, radius in spheres:
        materials.append(dict(material, name=node_name))
        meshes.append({"name": node_name, "primitives": [{
            "attributes": sphere_attributes, "indices": sphere_index_accessor,
            "material": len(materials) - 1, "mode": 4}]})
        nodes.append({"name": node_name, "mesh": len(meshes) - 1,
                      "translation": [cb.rounded(c) for c in centre], "scale": [radius] * 3})

    yfov = 2.0 * math.atan(0.5 * cb.FILM_MM / cb.FOCAL_LENGTH_MM)
    nodes.append({"name": "cornell_camera", "camera": 0,
                  "translation": [c / 1000.0 for c in cb.CAMERA_POSITION_MM],
                  "rotation": [0.0, 1.0, 0.0, 0.0]})
    used = sorted({k for m in materials for k in m.get("extensions", {})})
    uri = "data:application/octet-stream;base64," + base64.b64encode(bytes(builder.blob)).decode("ascii")
    return {
        "asset": {"version": "2.0", "generator": generator,
                  "extras": dict({"base": "scenes/cornell-box (measured Cornell box, blocks removed)",
                                  "units": "metres", "light_luminance_cd_per_m2": luminance},
                                 **extras)},
        "extensionsUsed": used,
        "scene": 0,
        "scenes": [{"name": name, "nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "cameras": [{"name": "cornell_camera", "type": "perspective",
                     "perspective": {"yfov": yfov, "aspectRatio": 1.0, "znear": 0.01}}],
        "accessors": builder.accessors,
        "bufferViews": builder.buffer_views,
        "buffers": [{"byteLength": len(builder.blob), "uri": uri}],
    }


def write_scene(doc, path):
    """Write the document deterministically (same bytes every run)."""
    text = json.dumps(doc, sort_keys=True, indent=1) + "\n"
    with open(path, "w", encoding="utf-8", newline="\n") as f:
        f.write(text)
    print("wrote %s (%d bytes)" % (os.path.relpath(path), len(text)))
