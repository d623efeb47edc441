#!/usr/bin/env python3
"""Generate scenes/caustic-spheres/caustic-spheres.gltf: the caustic scene of issue 4, a solid
glass sphere and a mirror sphere in the measured Cornell box (blocks removed) under a small
square ceiling light (README.md beside this file).

Run from anywhere (Python 3 standard library only; deterministic: same bytes every run):

    python3 scenes/caustic-spheres/make_caustic_spheres.py

With --caustic-free it writes the variant that scripts/update-references renders to find the
caustic region (caustic-mask.png): the glass sphere replaced by a black Lambertian one, which
casts the same shadow but focuses no light.
"""

import argparse
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "cornell-box"))
import cornell_variants as cv  # noqa: E402  (the folder is put on the path just above)

RADIUS = 0.1  # m, both spheres; they rest 1 mm above the floor (no vertex in its plane)
LIFT = 0.001
# A small light (80 x 80 mm, 0.0064 m^2 against the Cornell light's 0.01365 m^2) makes a sharp
# caustic; 100 cd/m^2 keeps its intensity (luminance x area: 0.64 cd) near the Cornell light's
# (0.68 cd).
LIGHT_SIZE = 0.08
LUMINANCE = 100.0

# Glass: clear, smooth, ior 1.5, and a solid (KHR_materials_volume thicknessFactor > 0: the
# surface bounds a volume, it is not thin-walled). No attenuation: the volume is clear.
GLASS = {
    "pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0,
                             "roughnessFactor": 0.0},
    "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                   "KHR_materials_ior": {"ior": 1.5},
                   "KHR_materials_volume": {"thicknessFactor": 2.0 * RADIUS}},
    "doubleSided": False,
}
# Mirror: a smooth metal whose reflectance is 0.95 at every angle and wavelength (the base colour
# of a metal is its F0, and Schlick's Fresnel rises from it to 1 at grazing angles).
MIRROR = {
    "pbrMetallicRoughness": {"baseColorFactor": [0.95, 0.95, 0.95, 1.0], "metallicFactor": 1.0,
                             "roughnessFactor": 0.0},
    "doubleSided": False,
}


# The caustic-free variant's glass: absorbs all light, reflects none.
BLACK = {
    "pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0,
                             "roughnessFactor": 1.0},
    "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}},
    "doubleSided": False,
}


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--caustic-free", action="store_true",
                        help="replace the glass sphere by a black one (for the caustic mask)")
    parser.add_argument("--output", default=os.path.join(HERE, "caustic-spheres.gltf"))
    args = parser.parse_args(argv)
    y = RADIUS + LIFT
    # Glass in front on the camera's right (green wall), mirror at the back on its left, as in
    # Jensen's photon-mapping scenes; the glass sphere's caustic falls on the floor in front of
    # and beside its contact point, in view of the camera.
    spheres = [
        ("glass_sphere", BLACK if args.caustic_free else GLASS, (0.16, y, 0.15), RADIUS),
        ("mirror_sphere", MIRROR, (0.39, y, 0.36), RADIUS),
    ]
    doc = cv.build_scene("caustic-spheres", "penumbra scenes/caustic-spheres/make_caustic_spheres.py",
                         LIGHT_SIZE, LUMINANCE, spheres,
                         {"purpose": "caustics: L S+ D E paths through a glass and a mirror sphere"})
    cv.write_scene(doc, args.output)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
