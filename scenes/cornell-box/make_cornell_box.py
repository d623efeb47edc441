#!/usr/bin/env python3
"""Generate scenes/cornell-box/cornell-box.gltf, the measured Cornell box as a glTF 2.0 scene.

Run from anywhere (Python 3 standard library only):

    python3 scenes/cornell-box/make_cornell_box.py

Sources (see SOURCE.txt and README.md beside this file):
  * Geometry, camera, reflectance and emission spectra: "Cornell Box Data", Cornell University Program
    of Computer Graphics, https://www.graphics.cornell.edu/online/box/data.html (millimetres; the
    spectra as transcribed in the reference-data folder, see --data-dir).
  * CIE 1931 2-degree colour-matching functions: the multi-lobe piecewise-Gaussian fit of
    C. Wyman, P.-P. Sloan, P. Shirley, "Simple Analytic Approximations to the CIE XYZ Color Matching
    Functions", Journal of Computer Graphics Techniques (JCGT) 2(2):1-11, 2013,
    http://jcgt.org/published/0002/02/01/ (the fit used here is their Equation 2, "xFit_1931" etc.).
  * sRGB: IEC 61966-2-1 (ITU-R BT.709 primaries, D65 white); chromatic adaptation: Bradford transform.

The output is deterministic: the same inputs give the same bytes on every run.
"""

import argparse
import base64
import csv
import json
import math
import os
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
# The shared data folder sits beside the repository (../shared from the repository root).
SHARED_SCENES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "shared", "scenes")
DEFAULT_DATA_DIR = os.path.normpath(os.path.join(SHARED_SCENES, "cornell-box-reference-data"))
DEFAULT_GLB = os.path.normpath(os.path.join(SHARED_SCENES, "cornell-box-bevy", "CornellBox.glb"))
OUTPUT = os.path.join(HERE, "cornell-box.gltf")
GENERATOR = "penumbra scenes/cornell-box/make_cornell_box.py"

# --------------------------------------------------------------------------------------------------
# Choices documented in README.md
# --------------------------------------------------------------------------------------------------

# Luminance of the light quad, cd/m^2. The published emission spectrum is relative only; this fixes
# its absolute scale so that the white floor under the light reads about 0.8 cd/m^2 (see
# estimate_floor_luminance()).
LIGHT_LUMINANCE = 50.0
# The light quad sits this far (in metres) below the ceiling plane y = 0.5488 m so that the two
# surfaces never coincide (no z-fighting, no ambiguous ray hits).
LIGHT_OFFSET = 0.0001
# Spectral integration: 1 nm grid over the range the published data cover (400-700 nm).
LAMBDA_MIN, LAMBDA_MAX, LAMBDA_STEP = 400, 700, 1
# Luminous efficacy constant of the CIE photopic observer, lm/W.
K_M = 683.0

# --------------------------------------------------------------------------------------------------
# Published geometry, millimetres, published coordinate system (right-handed, +y up, camera at
# z = -800 looking along +z, so +x is on the camera's left). Quads in the order the page lists them.
# --------------------------------------------------------------------------------------------------

FLOOR = [(552.8, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 559.2), (549.6, 0.0, 559.2)]
CEILING = [(556.0, 548.8, 0.0), (556.0, 548.8, 559.2), (0.0, 548.8, 559.2), (0.0, 548.8, 0.0)]
BACK_WALL = [(549.6, 0.0, 559.2), (0.0, 0.0, 559.2), (0.0, 548.8, 559.2), (556.0, 548.8, 559.2)]
# The page calls the red wall the "left wall" and the green wall the "right wall" (as seen by the camera).
RED_WALL = [(552.8, 0.0, 0.0), (549.6, 0.0, 559.2), (556.0, 548.8, 559.2), (556.0, 548.8, 0.0)]
GREEN_WALL = [(0.0, 0.0, 559.2), (0.0, 0.0, 0.0), (0.0, 548.8, 0.0), (0.0, 548.8, 559.2)]
LIGHT = [(343.0, 548.8, 227.0), (343.0, 548.8, 332.0), (213.0, 548.8, 332.0), (213.0, 548.8, 227.0)]

SHORT_BLOCK = [
    [(130.0, 165.0, 65.0), (82.0, 165.0, 225.0), (240.0, 165.0, 272.0), (290.0, 165.0, 114.0)],
    [(290.0, 0.0, 114.0), (290.0, 165.0, 114.0), (240.0, 165.0, 272.0), (240.0, 0.0, 272.0)],
    [(130.0, 0.0, 65.0), (130.0, 165.0, 65.0), (290.0, 165.0, 114.0), (290.0, 0.0, 114.0)],
    [(82.0, 0.0, 225.0), (82.0, 165.0, 225.0), (130.0, 165.0, 65.0), (130.0, 0.0, 65.0)],
    [(240.0, 0.0, 272.0), (240.0, 165.0, 272.0), (82.0, 165.0, 225.0), (82.0, 0.0, 225.0)],
]
TALL_BLOCK = [
    [(423.0, 330.0, 247.0), (265.0, 330.0, 296.0), (314.0, 330.0, 456.0), (472.0, 330.0, 406.0)],
    [(423.0, 0.0, 247.0), (423.0, 330.0, 247.0), (472.0, 330.0, 406.0), (472.0, 0.0, 406.0)],
    [(472.0, 0.0, 406.0), (472.0, 330.0, 406.0), (314.0, 330.0, 456.0), (314.0, 0.0, 456.0)],
    [(314.0, 0.0, 456.0), (314.0, 330.0, 456.0), (265.0, 330.0, 296.0), (265.0, 0.0, 296.0)],
    [(265.0, 0.0, 296.0), (265.0, 330.0, 296.0), (423.0, 330.0, 247.0), (423.0, 0.0, 247.0)],
]

# Camera (published): position (278, 273, -800) mm, direction +z, up +y, focal length 35 mm,
# film 25 x 25 mm.
CAMERA_POSITION_MM = (278.0, 273.0, -800.0)
FOCAL_LENGTH_MM = 35.0
FILM_MM = 25.0

# --------------------------------------------------------------------------------------------------
# Small vector helpers
# --------------------------------------------------------------------------------------------------


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def scale(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def normalize(a):
    length = math.sqrt(dot(a, a))
    assert length > 0.0, "degenerate vector"
    return scale(a, 1.0 / length)


def centroid(points):
    s = (0.0, 0.0, 0.0)
    for p in points:
        s = add(s, p)
    return scale(s, 1.0 / len(points))


def triangle_normal(a, b, c):
    """Geometric normal of triangle (a, b, c): the side from which a -> b -> c is counter-clockwise."""
    return normalize(cross(sub(b, a), sub(c, a)))


def mat_vec(m, v):
    return tuple(m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2] for i in range(3))


def mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def mat_inv(m):
    (a, b, c), (d, e, f), (g, h, i) = m
    det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
    assert abs(det) > 1e-12
    return [
        [(e * i - f * h) / det, (c * h - b * i) / det, (b * f - c * e) / det],
        [(f * g - d * i) / det, (a * i - c * g) / det, (c * d - a * f) / det],
        [(d * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d) / det],
    ]


def diag(v):
    return [[v[0], 0.0, 0.0], [0.0, v[1], 0.0], [0.0, 0.0, v[2]]]


# --------------------------------------------------------------------------------------------------
# Colour science
# --------------------------------------------------------------------------------------------------

# CIE 1931 2-degree colour-matching functions, multi-lobe piecewise-Gaussian fit of Wyman, Sloan and
# Shirley, JCGT 2(2), 2013, Equation 2 (coefficients as in the paper's listing). Wavelength in nm.


def _g(wave, mu, sigma_lo_inv, sigma_hi_inv):
    t = (wave - mu) * (sigma_lo_inv if wave < mu else sigma_hi_inv)
    return math.exp(-0.5 * t * t)


def x_bar(wave):
    return (0.362 * _g(wave, 442.0, 0.0624, 0.0374) + 1.056 * _g(wave, 599.8, 0.0264, 0.0323)
            - 0.065 * _g(wave, 501.1, 0.0490, 0.0382))


def y_bar(wave):
    return 0.821 * _g(wave, 568.8, 0.0213, 0.0247) + 0.286 * _g(wave, 530.9, 0.0613, 0.0322)


def z_bar(wave):
    return 1.217 * _g(wave, 437.0, 0.0845, 0.0278) + 0.681 * _g(wave, 459.0, 0.0385, 0.0725)


def wavelength_grid():
    """(wavelength, trapezoid weight) pairs of the integration grid."""
    n = (LAMBDA_MAX - LAMBDA_MIN) // LAMBDA_STEP
    grid = []
    for k in range(n + 1):
        w = LAMBDA_STEP * (0.5 if k in (0, n) else 1.0)
        grid.append((float(LAMBDA_MIN + k * LAMBDA_STEP), w))
    return grid


def interpolate(table, wave):
    """Linear interpolation of a tabulated spectrum [(wavelength, value), ...] sorted by wavelength."""
    if wave < table[0][0] or wave > table[-1][0]:
        raise ValueError("wavelength %g nm outside the tabulated range %g-%g nm"
                         % (wave, table[0][0], table[-1][0]))
    for (w0, v0), (w1, v1) in zip(table, table[1:]):
        if w0 <= wave <= w1:
            t = (wave - w0) / (w1 - w0)
            return v0 + t * (v1 - v0)
    raise AssertionError("unreachable")


def integrate_xyz(spectrum):
    """(X, Y, Z) = integral over 400-700 nm of spectrum(lambda) * (x_bar, y_bar, z_bar) d lambda."""
    x = y = z = 0.0
    for wave, w in wavelength_grid():
        s = spectrum(wave)
        x += w * s * x_bar(wave)
        y += w * s * y_bar(wave)
        z += w * s * z_bar(wave)
    return (x, y, z)


def chromaticity_to_xyz(x, y):
    return (x / y, 1.0, (1.0 - x - y) / y)


def srgb_matrices():
    """RGB -> XYZ and XYZ -> RGB matrices of linear sRGB, derived from the IEC 61966-2-1 primaries
    (ITU-R BT.709: R 0.64/0.33, G 0.30/0.60, B 0.15/0.06) and white point (D65: 0.3127/0.3290)."""
    primaries = [chromaticity_to_xyz(0.64, 0.33), chromaticity_to_xyz(0.30, 0.60),
                 chromaticity_to_xyz(0.15, 0.06)]
    white = chromaticity_to_xyz(0.3127, 0.3290)
    p = [[primaries[j][i] for j in range(3)] for i in range(3)]  # columns = primaries
    s = mat_vec(mat_inv(p), white)
    rgb_to_xyz = mat_mul(p, diag(s))
    xyz_to_rgb = mat_inv(rgb_to_xyz)
    # Sanity check against the 4-decimal matrix printed in IEC 61966-2-1.
    published = [[3.2406, -1.5372, -0.4986], [-0.9689, 1.8758, 0.0415], [0.0557, -0.2040, 1.0570]]
    for i in range(3):
        for j in range(3):
            assert abs(xyz_to_rgb[i][j] - published[i][j]) < 6e-4, (i, j, xyz_to_rgb[i][j])
    return rgb_to_xyz, xyz_to_rgb, white


# Bradford cone-response matrix (Lam 1985; as used by ICC and in Lindbloom's tables).
BRADFORD = [[0.8951, 0.2664, -0.1614], [-0.7502, 1.7135, 0.0367], [0.0389, -0.0685, 1.0296]]


def bradford_adaptation(src_white, dst_white):
    """XYZ -> XYZ von Kries adaptation in Bradford space from src_white to dst_white."""
    s = mat_vec(BRADFORD, src_white)
    d = mat_vec(BRADFORD, dst_white)
    return mat_mul(mat_inv(BRADFORD), mat_mul(diag([d[i] / s[i] for i in range(3)]), BRADFORD))


def read_csv(path):
    with open(path, newline="") as f:
        rows = [row for row in csv.reader(line for line in f if not line.startswith("#"))]
    header, body = rows[0], [r for r in rows[1:] if r]
    return header, [[float(v) for v in r] for r in body]


def compute_colours(data_dir):
    header, rows = read_csv(os.path.join(data_dir, "cornell_box_reflectance.csv"))
    assert header == ["wavelength_nm", "white", "green", "red"], header
    reflectance = {}
    for col, name in enumerate(header[1:], start=1):
        reflectance[name] = [(r[0], r[col]) for r in rows]
    header, rows = read_csv(os.path.join(data_dir, "cornell_box_light_emission.csv"))
    assert header == ["wavelength_nm", "emission"], header
    emission = [(r[0], r[1]) for r in rows]
    for table in list(reflectance.values()) + [emission]:
        assert table[0][0] == LAMBDA_MIN and table[-1][0] == LAMBDA_MAX, "data must cover 400-700 nm"

    rgb_to_xyz, xyz_to_rgb, d65 = srgb_matrices()

    # Reflectances: XYZ under the equal-energy illuminant E, normalised so that a perfect reflector
    # has Y = 1. The "white" of this computation is the perfect reflector's own XYZ on the same grid
    # (close to, but because of the 400-700 nm range and the fit, not exactly, (1, 1, 1)).
    perfect = integrate_xyz(lambda wave: 1.0)
    norm = 1.0 / perfect[1]
    src_white = scale(perfect, norm)
    adapt = bradford_adaptation(src_white, d65)
    to_srgb = mat_mul(xyz_to_rgb, adapt)
    albedo, albedo_xyz = {}, {}
    for name in ("white", "red", "green"):
        table = reflectance[name]
        xyz = scale(integrate_xyz(lambda wave, t=table: interpolate(t, wave)), norm)
        albedo_xyz[name] = xyz
        albedo[name] = mat_vec(to_srgb, xyz)
    white_check = mat_vec(to_srgb, src_white)
    assert all(abs(c - 1.0) < 1e-9 for c in white_check), white_check

    # Light: absolute luminance Y = 683 lm/W * k * integral(L_rel * y_bar); k fixed by LIGHT_LUMINANCE.
    rel = integrate_xyz(lambda wave: interpolate(emission, wave))
    k = LIGHT_LUMINANCE / (K_M * rel[1])  # W / (sr m^2 nm) per unit of the relative table
    light_xyz = scale(rel, K_M * k)
    light_rgb = mat_vec(xyz_to_rgb, light_xyz)  # no chromatic adaptation: an emitter, not a surface
    return {
        "albedo": albedo,
        "albedo_xyz": albedo_xyz,
        "perfect_reflector_xyz": src_white,
        "light_xyz": light_xyz,
        "light_rgb": light_rgb,
        "light_scale": k,
        "rgb_to_xyz": rgb_to_xyz,
    }


def estimate_floor_luminance(white_y):
    """Rough luminance of the white floor under the light (the basis of LIGHT_LUMINANCE)."""
    area = ((LIGHT[0][0] - LIGHT[2][0]) * (LIGHT[1][2] - LIGHT[0][2])) * 1e-6  # m^2
    d = LIGHT[0][1] * 1e-3 - LIGHT_OFFSET  # light height above the floor, m
    irradiance = LIGHT_LUMINANCE * area / (d * d)  # lux, small-source approximation
    return white_y / math.pi * irradiance * 1.5  # x1.5 for interreflection


# --------------------------------------------------------------------------------------------------
# Geometry
# --------------------------------------------------------------------------------------------------


def to_metres(points):
    return [(x / 1000.0, y / 1000.0, z / 1000.0) for (x, y, z) in points]


def orient_quad(quad, intended):
    """Return the quad with its vertex order reversed if needed so that it is counter-clockwise as
    seen from the side `intended` points to."""
    n = (0.0, 0.0, 0.0)  # Newell normal of the polygon
    for i in range(len(quad)):
        a, b = quad[i], quad[(i + 1) % len(quad)]
        n = add(n, ((a[1] - b[1]) * (a[2] + b[2]), (a[2] - b[2]) * (a[0] + b[0]),
                    (a[0] - b[0]) * (a[1] + b[1])))
    return list(quad) if dot(n, intended) > 0.0 else list(reversed(quad))


def quad_primitive(quad, intended, min_cos):
    """Triangulate an oriented quad (v0 v1 v2, v0 v2 v3) into positions, normals and indices.

    A planar quad shares its 4 vertices; a non-planar one (the published red wall is slightly
    twisted) gets 3 vertices per triangle so that each triangle carries its own flat normal."""
    tris = [(quad[0], quad[1], quad[2]), (quad[0], quad[2], quad[3])]
    normals = [triangle_normal(*t) for t in tris]
    for n in normals:
        # The winding check: the geometric normal must point where the surface is meant to face.
        assert dot(n, intended) >= min_cos, ("wrong winding or orientation", n, intended)
    if dot(normals[0], normals[1]) > 1.0 - 1e-12:
        n = normalize(add(normals[0], normals[1]))
        return list(quad), [n] * 4, [0, 1, 2, 0, 2, 3]
    positions, vnormals = [], []
    for t, n in zip(tris, normals):
        positions.extend(t)
        vnormals.extend([n] * 3)
    return positions, vnormals, [0, 1, 2, 3, 4, 5]


def block_faces(name, quads_mm):
    """Faces of a block, oriented outward and named by the direction they face.

    front = -z (towards the camera), back = +z, left = +x (the camera's left, towards the red wall),
    right = -x (towards the green wall)."""
    quads = [to_metres(q) for q in quads_mm]
    all_points = [p for q in quads for p in q]
    c = centroid(all_points)
    faces = []
    seen = set()
    for q in quads:
        outward = normalize(sub(centroid(q), c))
        if abs(outward[1]) > 0.9:
            assert outward[1] > 0.0, "blocks have no bottom face in the published data"
            label, intended = "top", (0.0, 1.0, 0.0)
        else:
            horizontal = normalize((outward[0], 0.0, outward[2]))
            # the exact outward direction of a vertical face: horizontal, perpendicular to its edge
            edge = sub(q[1], q[0]) if abs(q[1][1] - q[0][1]) < 1e-12 else sub(q[2], q[1])
            perp = normalize((edge[2], 0.0, -edge[0]))
            intended = perp if dot(perp, horizontal) > 0.0 else scale(perp, -1.0)
            if abs(intended[0]) > abs(intended[2]):
                label = "left" if intended[0] > 0.0 else "right"
            else:
                label = "back" if intended[2] > 0.0 else "front"
        assert label not in seen, (name, label)
        seen.add(label)
        faces.append(("%s_%s" % (name, label), orient_quad(q, intended), intended))
    order = ["top", "front", "left", "right", "back"]
    faces.sort(key=lambda f: order.index(f[0][len(name) + 1:]))
    return faces


def build_surfaces():
    """List of (mesh/node name, material name, [(primitive name, quad, intended normal), ...])."""
    light = [(x, y - LIGHT_OFFSET * 1e3, z) for (x, y, z) in LIGHT]
    walls = [
        ("floor", "white", FLOOR, (0.0, 1.0, 0.0)),
        ("ceiling", "white", CEILING, (0.0, -1.0, 0.0)),
        ("back_wall", "white", BACK_WALL, (0.0, 0.0, -1.0)),
        ("red_wall", "red", RED_WALL, (-1.0, 0.0, 0.0)),
        ("green_wall", "green", GREEN_WALL, (1.0, 0.0, 0.0)),
    ]
    surfaces = []
    for name, material, quad, intended in walls:
        q = to_metres(quad)
        surfaces.append((name, material, [(name, orient_quad(q, intended), intended)]))
    surfaces.append(("short_block", "white", block_faces("short_block", SHORT_BLOCK)))
    surfaces.append(("tall_block", "white", block_faces("tall_block", TALL_BLOCK)))
    q = to_metres(light)
    surfaces.append(("light", "light", [("light", orient_quad(q, (0.0, -1.0, 0.0)), (0.0, -1.0, 0.0))]))
    return surfaces


# --------------------------------------------------------------------------------------------------
# Cross-check against the Bevy GLB (optional; prints a report, never changes the output)
# --------------------------------------------------------------------------------------------------


def read_glb_positions(path):
    """World-space POSITION data of every primitive of a GLB whose nodes carry only translations,
    with the 180-degree rotation about +Y undone (x -> -x, z -> -z), in millimetres."""
    with open(path, "rb") as f:
        data = f.read()
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    assert magic == b"glTF" and version == 2 and length == len(data)
    offset, chunks = 12, {}
    while offset < len(data):
        chunk_len, chunk_type = struct.unpack_from("<I4s", data, offset)
        chunks[chunk_type] = data[offset + 8:offset + 8 + chunk_len]
        offset += 8 + chunk_len
    doc = json.loads(chunks[b"JSON"].decode("utf-8"))
    binary = chunks[b"BIN\x00"]
    result = {}
    for node in doc["nodes"]:
        assert set(node) <= {"mesh", "name", "translation"}, node
        t = node.get("translation", [0.0, 0.0, 0.0])
        mesh = doc["meshes"][node["mesh"]]
        for pi, prim in enumerate(mesh["primitives"]):
            acc = doc["accessors"][prim["attributes"]["POSITION"]]
            view = doc["bufferViews"][acc["bufferView"]]
            assert acc["componentType"] == 5126 and acc["type"] == "VEC3"
            stride = view.get("byteStride", 12)
            base = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
            points = []
            for i in range(acc["count"]):
                x, y, z = struct.unpack_from("<3f", binary, base + i * stride)
                points.append((-(x + t[0]), y + t[1], -(z + t[2])))
            result[(mesh["name"], pi)] = points
    return result


def cross_check_glb(path):
    if not os.path.exists(path):
        print("cross-check: %s not found, skipped" % path)
        return
    glb = read_glb_positions(path)
    box = [p for (mesh, _), pts in glb.items() if mesh == "cornell_box" for p in pts]

    def max_nearest(points, candidates):
        return max(min(math.sqrt(dot(sub(p, c), sub(p, c))) for c in candidates) for p in points)

    shell = FLOOR + CEILING + BACK_WALL + RED_WALL + GREEN_WALL
    d_shell = max_nearest(shell, box)
    d_shell_rev = max_nearest(box, shell)
    print("cross-check vs %s (rotation undone):" % os.path.basename(path))
    print("  walls/floor/ceiling: max vertex distance %.3f mm (published -> GLB), %.3f mm (GLB -> published)"
          % (d_shell, d_shell_rev))
    assert d_shell < 0.05 and d_shell_rev < 0.05
    light_glb = glb[("Light", 0)]
    xs = sorted(p[0] for p in light_glb)
    zs = sorted(p[2] for p in light_glb)
    print("  light: GLB x %.2f..%.2f z %.2f..%.2f y %.3f mm; published x 213..343 z 227..332 y 548.8 mm"
          % (xs[0], xs[-1], zs[0], zs[-1], light_glb[0][1]))
    assert abs(xs[0] - 213) < 0.05 and abs(xs[-1] - 343) < 0.05
    assert abs(zs[0] - 227) < 0.05 and abs(zs[-1] - 332) < 0.05
    for label, quads, mesh in (("short block", SHORT_BLOCK, "small_box"), ("tall block", TALL_BLOCK, "large_box")):
        pub = [p for q in quads for p in q]
        d = max_nearest(pub, glb[(mesh, 0)])
        print("  %s: max vertex distance %.2f mm (the GLB's block is an exact rectangular box fitted to"
              " the published, slightly irregular one)" % (label, d))
        assert d < 5.0


# --------------------------------------------------------------------------------------------------
# glTF writer
# --------------------------------------------------------------------------------------------------

ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER = 34962, 34963
FLOAT, UNSIGNED_SHORT = 5126, 5123


def f32(v):
    return struct.unpack("<f", struct.pack("<f", v))[0]


def rounded(v, digits=6):
    r = round(v, digits)
    return 0.0 if r == 0.0 else r  # no "-0.0" in the output


class GltfBuilder:
    def __init__(self):
        self.blob = bytearray()
        self.buffer_views = []
        self.accessors = []

    def _view(self, payload, target):
        while len(self.blob) % 4:
            self.blob.append(0)
        self.buffer_views.append({"buffer": 0, "byteOffset": len(self.blob), "byteLength": len(payload),
                                  "target": target})
        self.blob.extend(payload)
        return len(self.buffer_views) - 1

    def vec3(self, values, with_bounds):
        payload = b"".join(struct.pack("<3f", *v) for v in values)
        acc = {"bufferView": self._view(payload, ARRAY_BUFFER), "componentType": FLOAT,
               "count": len(values), "type": "VEC3"}
        if with_bounds:
            stored = [tuple(f32(c) for c in v) for v in values]
            acc["min"] = [min(v[i] for v in stored) for i in range(3)]
            acc["max"] = [max(v[i] for v in stored) for i in range(3)]
        self.accessors.append(acc)
        return len(self.accessors) - 1

    def indices(self, values):
        assert max(values) < 65535
        payload = struct.pack("<%dH" % len(values), *values)
        self.accessors.append({"bufferView": self._view(payload, ELEMENT_ARRAY_BUFFER),
                               "componentType": UNSIGNED_SHORT, "count": len(values), "type": "SCALAR"})
        return len(self.accessors) - 1


def lambertian(name, rgb):
    return {
        "name": name,
        "pbrMetallicRoughness": {"baseColorFactor": [rounded(c) for c in rgb] + [1.0],
                                 "metallicFactor": 0.0, "roughnessFactor": 1.0},
        "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}},
        "doubleSided": False,
    }


def build_gltf(colours):
    light_rgb = colours["light_rgb"]
    strength = max(light_rgb)
    factor = [rounded(c / strength) for c in light_rgb]
    materials = [
        lambertian("white", colours["albedo"]["white"]),
        lambertian("red", colours["albedo"]["red"]),
        lambertian("green", colours["albedo"]["green"]),
        {
            "name": "light",
            "pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0,
                                     "roughnessFactor": 1.0},
            "emissiveFactor": factor,
            "extensions": {
                "KHR_materials_emissive_strength": {"emissiveStrength": rounded(strength)},
                "KHR_materials_specular": {"specularFactor": 0.0},
            },
            "doubleSided": False,
        },
    ]
    material_index = {m["name"]: i for i, m in enumerate(materials)}

    builder = GltfBuilder()
    meshes, nodes = [], []
    for name, material, faces in build_surfaces():
        primitives = []
        for prim_name, quad, intended in faces:
            min_cos = 0.999 if prim_name in ("floor", "ceiling", "back_wall", "red_wall", "green_wall",
                                              "light") else 0.999999
            positions, normals, indices = quad_primitive(quad, intended, min_cos)
            primitives.append({
                "attributes": {"POSITION": builder.vec3(positions, True),
                               "NORMAL": builder.vec3(normals, False)},
                "indices": builder.indices(indices),
                "material": material_index[material],
                "mode": 4,
                "extras": {"name": prim_name},
            })
        meshes.append({"name": name, "primitives": primitives})
        nodes.append({"name": name, "mesh": len(meshes) - 1})

    yfov = 2.0 * math.atan(0.5 * FILM_MM / FOCAL_LENGTH_MM)
    cameras = [{"name": "cornell_camera", "type": "perspective",
                "perspective": {"yfov": yfov, "aspectRatio": 1.0, "znear": 0.01}}]
    nodes.append({"name": "cornell_camera", "camera": 0,
                  "translation": [c / 1000.0 for c in CAMERA_POSITION_MM],
                  # 180 degrees about +Y: the camera's -Z (its view direction) becomes world +z.
                  "rotation": [0.0, 1.0, 0.0, 0.0]})

    uri = "data:application/octet-stream;base64," + base64.b64encode(bytes(builder.blob)).decode("ascii")
    return {
        "asset": {"version": "2.0", "generator": GENERATOR,
                  "extras": {"source": "https://www.graphics.cornell.edu/online/box/data.html",
                             "units": "metres",
                             "light_luminance_cd_per_m2": LIGHT_LUMINANCE}},
        "extensionsUsed": ["KHR_materials_emissive_strength", "KHR_materials_specular"],
        "scene": 0,
        "scenes": [{"name": "cornell-box", "nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "cameras": cameras,
        "accessors": builder.accessors,
        "bufferViews": builder.buffer_views,
        "buffers": [{"byteLength": len(builder.blob), "uri": uri}],
    }


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data-dir", default=os.environ.get("CORNELL_BOX_DATA_DIR", DEFAULT_DATA_DIR),
                        help="folder with cornell_box_reflectance.csv and cornell_box_light_emission.csv")
    parser.add_argument("--glb", default=DEFAULT_GLB,
                        help="Bevy's CornellBox.glb, used only to cross-check the geometry (optional)")
    parser.add_argument("--output", default=OUTPUT)
    args = parser.parse_args(argv)

    colours = compute_colours(args.data_dir)
    print("integration: trapezoid rule, %d-%d nm, %d nm step (the data cover only 400-700 nm)"
          % (LAMBDA_MIN, LAMBDA_MAX, LAMBDA_STEP))
    print("perfect reflector XYZ under E (Y = 1): %.5f %.5f %.5f" % colours["perfect_reflector_xyz"])
    for name in ("white", "red", "green"):
        print("albedo %-5s XYZ(E) %.5f %.5f %.5f -> linear sRGB (D65, Bradford) %.5f %.5f %.5f"
              % ((name,) + colours["albedo_xyz"][name] + colours["albedo"][name]))
        assert all(0.0 <= c <= 1.0 for c in colours["albedo"][name]), name
    lr = colours["light_rgb"]
    print("light: relative spectrum scaled by k = %.6g W/(sr m^2 nm) per table unit" % colours["light_scale"])
    print("light: XYZ %.4f %.4f %.4f cd/m^2; linear sRGB radiance %.4f %.4f %.4f cd/m^2; luminance %.4f cd/m^2"
          % (colours["light_xyz"] + lr + (dot(colours["rgb_to_xyz"][1], lr),)))
    assert all(c >= 0.0 for c in lr), "light colour outside the sRGB gamut"
    print("light: emissiveFactor %s, emissiveStrength %.4f"
          % ([round(c / max(lr), 6) for c in lr], max(lr)))
    print("estimated white-floor luminance under the light: %.2f cd/m^2"
          % estimate_floor_luminance(colours["albedo_xyz"]["white"][1]))
    cross_check_glb(args.glb)

    doc = build_gltf(colours)
    text = json.dumps(doc, sort_keys=True, indent=1) + "\n"
    with open(args.output, "w", encoding="utf-8", newline="\n") as f:
        f.write(text)
    print("wrote %s (%d bytes)" % (os.path.relpath(args.output), len(text)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
