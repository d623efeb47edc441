#!/usr/bin/python3
"""Light groups in one render against a render per group: the time of each, and each group's
noise in both (docs/benchmarks.md, "Light groups in one render").

Not a test and not part of the build: a benchmark. Usage:

    bench/light_groups_benchmark.py SCENE.gltf [--spp N] [--width W] [--height H]
        [--penumbra build/bin/penumbra]

Renders the scene with the path tracer (`reference`) twice without groups and twice with
`--light-groups` (seeds 1 and 2), then, for each group of its emissive materials and punctual
lights, twice a copy of the scene lit by that group alone (the other emissive materials' factor
zero, the other punctual lights' intensity zero: the scene a render per group renders). A group's
noise is half the mean squared difference of its two seeds' luminance, over the square of its
mean luminance: the relative variance of one pixel. Prints a Markdown table.
"""
import argparse
import copy
import json
import os
import re
import subprocess
import tempfile
import time

import numpy
import OpenImageIO as oiio

from gltf_copy import rebase_files, write_document


def group_name(kind, name):
    """penumbra's group name (core/light_groups.cpp)."""
    return re.sub(r"[^A-Za-z0-9_-]", "_", kind + "-" + name)


def groups(document):
    """{group name: (emissive material indices, punctual light indices)}."""
    found = {}
    lights = document.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
    for i, light in enumerate(lights):
        found.setdefault(group_name("light", light.get("name", "")), ([], []))[1].append(i)
    for i, material in enumerate(document.get("materials", [])):
        if any(v > 0 for v in material.get("emissiveFactor", [0, 0, 0])):
            name = material.get("name") or "material_%d" % i
            found.setdefault(group_name("emissive", name), ([], []))[0].append(i)
    return found


def lit_only_by(document, materials, lights):
    alone = copy.deepcopy(document)
    for i, material in enumerate(alone.get("materials", [])):
        if i not in materials and "emissiveFactor" in material:
            material["emissiveFactor"] = [0.0, 0.0, 0.0]
    punctual = alone.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
    for i, light in enumerate(punctual):
        if i not in lights:
            light["intensity"] = 0.0
    return alone


def luminance(path, prefix=""):
    image = oiio.ImageBuf(path)
    names = list(image.spec().channelnames)
    pixels = image.get_pixels(oiio.FLOAT)
    r, g, b = (pixels[:, :, names.index(prefix + c)] for c in "RGB")
    return 0.2126 * r + 0.7152 * g + 0.0722 * b


def noise(a, b):
    """The relative variance of one pixel, from two seeds; and the mean."""
    mean = 0.5 * float((a + b).mean())
    return float(((a - b) ** 2).mean()) / 2.0 / mean ** 2, mean


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("scene")
    parser.add_argument("--spp", default="64")
    parser.add_argument("--width", default="160")
    parser.add_argument("--height", default="90")
    parser.add_argument("--penumbra", default="build/bin/penumbra")
    args = parser.parse_args()
    with open(args.scene) as f:
        document = json.load(f)
    work = tempfile.mkdtemp(prefix="light-groups-")

    def render(scene, out, seed, extra=()):
        start = time.monotonic()
        subprocess.run([args.penumbra, "render", scene, "-o", out, "--seed", str(seed), "--spp",
                        args.spp, "--width", args.width, "--height", args.height,
                        "--threads", "2", "--quiet", *extra], check=True)
        return time.monotonic() - start

    def twice(scene, name, extra=()):
        paths = [os.path.join(work, "%s-%d.exr" % (name, seed)) for seed in (1, 2)]
        seconds = [render(scene, path, seed, extra) for seed, path in zip((1, 2), paths)]
        return paths, seconds

    _, plain = twice(args.scene, "plain")
    split, together = twice(args.scene, "split", ["--light-groups"])
    rows, apart = [], 0.0
    for name, (materials, lights) in groups(document).items():
        alone_scene = os.path.join(work, name + ".gltf")
        alone = lit_only_by(document, materials, lights)
        rebase_files(alone, args.scene, alone_scene)
        write_document(alone, alone_scene)
        paths, seconds = twice(alone_scene, name)
        apart += sum(seconds) / 2.0
        split_noise, split_mean = noise(*(luminance(p, "light.%s." % name) for p in split))
        alone_noise, alone_mean = noise(*(luminance(p) for p in paths))
        rows.append((name, split_mean / alone_mean, split_noise, alone_noise))

    print("| group | mean, one render / alone | noise, one render | noise, alone | ratio |")
    print("| --- | --- | --- | --- | --- |")
    for name, mean, split_noise, alone_noise in rows:
        print("| %s | %.3f | %.4g | %.4g | %.2f |" % (name, mean, split_noise, alone_noise,
                                                   split_noise / alone_noise))
    ratios = [r[2] / r[3] for r in rows]
    print("\nnoise ratio: median %.2f, %.2f-%.2f" % (numpy.median(ratios), min(ratios),
                                                      max(ratios)))
    print("seconds: plain render %s; one render with groups %s; a render per group %.1f (the "
          "sum over groups of the mean of two seeds)"
          % (", ".join("%.1f" % s for s in plain), ", ".join("%.1f" % s for s in together),
             apart))


if __name__ == "__main__":
    main()
