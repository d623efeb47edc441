#!/usr/bin/env python3
"""Generate scenes/glossy/glossy.gltf: the measured Cornell box without its blocks, holding three
rough gold spheres and two blue plastic spheres of several roughnesses (regression scene of
tests/cli/regression_test.cpp; README.md beside this file).

Run from anywhere (Python 3 standard library only; deterministic: same bytes every run):

    python3 scenes/glossy/make_glossy.py
"""

import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "cornell-box"))
import cornell_variants as cv  # noqa: E402  (the folder is put on the path just above)

# Gold's normal-incidence reflectance in linear sRGB, the value the glTF 2.0 specification lists
# for metals (Appendix B, "Metal base colour"): (1.000, 0.766, 0.336).
GOLD = (1.0, 0.766, 0.336)
# A blue plastic: Lambertian base under the glTF dielectric coat (ior 1.5, F0 = 0.04).
BLUE = (0.05, 0.15, 0.5)
# Radius (m) of the spheres; they rest 1 mm above the floor so that no vertex lies in its plane.
RADIUS = 0.075
LIFT = 0.001
# A larger light than the Cornell box's (200 x 200 mm against 130 x 105 mm) with the same
# intensity (luminance x area = 0.68 cd): the highlights of the rough spheres are broad, and the
# light that walls receive by way of the smooth spheres (caustics, rare paths for a path tracer)
# is spread thin, so a 64-spp test render has few fireflies.
LIGHT_SIZE = 0.2
LUMINANCE = 17.0


def material(rgb, metallic, roughness):
    return {"pbrMetallicRoughness": {"baseColorFactor": list(rgb) + [1.0],
                                     "metallicFactor": metallic, "roughnessFactor": roughness},
            "doubleSided": False}


def main():
    y = RADIUS + LIFT
    # x grows towards the camera's left (the red wall): the roughness grows left to right in the
    # image. Gold at the back, plastic in front, staggered so that no sphere hides another.
    spheres = [
        ("gold_roughness_0.1", material(GOLD, 1.0, 0.1), (0.44, y, 0.40), RADIUS),
        ("gold_roughness_0.25", material(GOLD, 1.0, 0.25), (0.278, y, 0.40), RADIUS),
        ("gold_roughness_0.5", material(GOLD, 1.0, 0.5), (0.116, y, 0.40), RADIUS),
        ("plastic_smooth", material(BLUE, 0.0, 0.0), (0.36, y, 0.15), RADIUS),
        ("plastic_roughness_0.3", material(BLUE, 0.0, 0.3), (0.196, y, 0.15), RADIUS),
    ]
    doc = cv.build_scene("glossy", "penumbra scenes/glossy/make_glossy.py", LIGHT_SIZE, LUMINANCE,
                         spheres, {"purpose": "rough and smooth glossy reflection"})
    cv.write_scene(doc, os.path.join(HERE, "glossy.gltf"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
