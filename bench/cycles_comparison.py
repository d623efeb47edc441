#!/usr/bin/python3
"""Equal-time comparison of penumbra's pipelines with Blender Cycles on one glTF scene.

Not a test and not part of the build: a benchmark script whose output docs/benchmarks.md quotes.
It needs Blender and the peer harness, by default ../shared/peers from the repository's root
(the shared folder beside the repository; see its README, and --peers for another place).
Blender is a dependency of this benchmark only, never of the build or the tests, so
scripts/setup does not install it; on Debian 12, as root:

    DEBIAN_FRONTEND=noninteractive apt-get install -y blender python3-numpy python3-openimageio

and run this script with /usr/bin/python3 (the Debian numpy and OpenImageIO).

Steps (linear EXR images, in --workdir):
  1. the reference: either --reference, an existing converged image whose size the comparison
     takes (e.g. scenes/cornell-box/reference.exr, 128 x 128), or penumbra's path tracer at
     --ref-spp samples, seed 1000, --size x --size pixels (kept if already there);
  2. a converged Cycles image (--cycles-converged-spp, 0 to skip; kept if already there) and its
     per-channel mean ratio to the reference: do the two renderers converge to the same image?
  3. Cycles' cost per sample, from one calibration render (--calibration-spp);
  4. for each budget (seconds), --repeats times, alternately: every penumbra pipeline of
     --pipelines with --time-limit BUDGET --seed 1, then Cycles (seed 1) with the spp that the
     latest measured Cycles rate says fits in BUDGET. Cycles has no time limit of its own, so
     its spp is chosen beforehand and on a shared machine its time drifts; every Cycles render
     updates the rate (seconds per spp, its scene sync included) for the next one, so the
     repeats home in on the budget;
  5. relMSE of every render against the reference: mean over pixels and channels of
     (test - ref)^2 / (ref^2 + 0.01) (the same formula as the peers' imgdiff.py), and
     relMSE x seconds, the time-normalised error (an unbiased estimator's relMSE falls as
     1 / samples, so this product compares renderers even when their times differ; lower is
     better; a biased pipeline's product grows once its bias dominates). With a converged
     Cycles image, also the relMSE against it: for the Cycles runs, their noise alone, without
     the difference between the two renderers' materials (which the reference comparison
     counts as error once Cycles' noise falls below it). A table of every run, then one of the
     medians over the repeats.

A pass script as --scene (`.toml`) is rendered by penumbra as it stands when it lists [[pass]]
tables (its passes are the one pipeline, named "script"; --pipelines is not used), with each of
--pipelines in place of its own when it names a built-in `pipeline`, and by Cycles as its glTF scene, with the
script's [[medium]] table, if it has one, added by bench/cycles_medium.py as a volume box
(docs/media.md). An environment-lit scene (--environment: the scene's own map, or a file given to both renderers)
is rendered in Cycles by bench/cycles_environment.py, which runs the same harness with the map as
Cycles' world, looked up in penumbra's orientation; with --cycles-portals, Cycles also gets the
openings penumbra finds as portals (Cycles samples the world through portal lights it is given).

Timings: penumbra's is the whole pipeline as its EXR records it (`penumbra:seconds`: every pass,
the radiosity solve and the photon map included, and the ~0.1 s of scene loading); Cycles' is
`render_s` of cycles_render.py (bpy.ops.render.render: scene sync, BVH build and path tracing,
without Blender's start-up and the glTF import).
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tomllib

import numpy as np
import OpenImageIO as oiio

REF_SEED = 1000
TEST_SEED = 1
RELMSE_EPS = 0.01


def load(path):
    """The image's RGB as a (height, width, 3) float64 array, and its metadata."""
    inp = oiio.ImageInput.open(path)
    if inp is None:
        raise SystemExit("cannot open %s: %s" % (path, oiio.geterror()))
    spec = inp.spec()
    pixels = inp.read_image(0, 0, 0, spec.nchannels, oiio.FLOAT)
    inp.close()
    image = np.asarray(pixels, dtype=np.float64).reshape(spec.height, spec.width, spec.nchannels)
    names = list(spec.channelnames)
    metadata = {a.name: a.value for a in spec.extra_attribs}
    return image[:, :, [names.index(c) for c in "RGB"]], metadata


def relmse(test, ref):
    return float(np.mean((test - ref) ** 2 / (ref * ref + RELMSE_EPS)))


def channel_means(image):
    return [float(image[:, :, c].mean()) for c in range(3)]


def channel_ratios(test, ref):
    return [t / r for t, r in zip(channel_means(test), channel_means(ref))]


def size(a):
    """The image size in file names: 128px for a square, 160x90 otherwise."""
    return "%dpx" % a.width if a.width == a.height else "%dx%d" % (a.width, a.height)


def environment_args(a):
    """penumbra's option for a map given as a file (the scene's own map needs none)."""
    return ["--environment", a.environment] if a.environment not in (None, "scene") else []


def run(cmd):
    print("$ " + " ".join(cmd), flush=True)
    return subprocess.run(cmd, check=True, capture_output=True, text=True)


def run_penumbra(a, out, pipeline, seed, spp=None, time_limit=None):
    """Renders with penumbra; spp and seconds are those the EXR records. A pass script with
    [[pass]] tables is its own pipeline; one that names a built-in `pipeline` takes --pipeline."""
    cmd = [a.penumbra, "render", a.scene, "-o", out,
           "--width", str(a.width), "--height", str(a.height), "--seed", str(seed),
           "--threads", str(a.threads)] + environment_args(a)
    if a.takes_pipeline:
        cmd += ["--pipeline", pipeline]
    if time_limit is not None:
        cmd += ["--time-limit", str(time_limit), "--spp", "1000000"]
    else:
        cmd += ["--spp", str(spp)]
    run(cmd)
    metadata = load(out)[1]
    return {"spp": int(metadata["penumbra:spp"]), "seconds": float(metadata["penumbra:seconds"])}


def medium_args(medium):
    """cycles_medium.py's options for a pass script's [[medium]] table (docs/pass-scripts.md)."""
    def channels(key):
        value = medium.get(key, 0.0)
        return ",".join(str(float(x)) for x in (value if isinstance(value, list) else [value] * 3))
    args = ["--sigma-a", channels("sigma_a"), "--sigma-s", channels("sigma_s"),
            "--g", str(float(medium.get("g", 0.0)))]
    if "box" in medium:
        args += ["--box", ",".join(str(float(x)) for x in medium["box"])]
    if "density" in medium:
        args += ["--density", medium["density"]]
        if "density_grid" in medium:
            args += ["--density-grid", medium["density_grid"]]
    return args


def run_cycles(a, out, spp, seed):
    """Renders with Cycles through the peer harness; with --environment, through
    cycles_environment.py, which runs the harness with the map as the world; with a pass
    script's medium, through cycles_medium.py, which adds it as a volume box."""
    here = os.path.dirname(os.path.abspath(__file__))
    if a.medium is not None:
        script = [os.path.join(here, "cycles_medium.py"), "--", "--peers", a.peers]
        script += medium_args(a.medium)
    elif a.environment is None:
        script = [os.path.join(a.peers, "cycles_render.py"), "--"]
    else:
        script = [os.path.join(os.path.dirname(os.path.abspath(__file__)),
                               "cycles_environment.py"), "--", "--peers", a.peers]
        script += environment_args(a)
        for portal in a.portals:
            script += ["--portal", portal]
    cmd = [a.blender, "-b", "--factory-startup", "-P"] + script + [
           "--scene", a.gltf, "--out", out,
           "--spp", str(spp), "--width", str(a.width), "--height", str(a.height),
           "--threads", str(a.threads), "--seed", str(seed)]
    log = run(cmd).stdout
    materials = re.findall(r"^material .*$", log, re.MULTILINE)
    result = json.loads(re.search(r"^CYCLES_RESULT (.*)$", log, re.MULTILINE).group(1))
    return {"spp": spp, "seconds": result["render_s"], "materials": materials}


def found_portals(a):
    """The openings penumbra finds as portals for the scene (`penumbra info`), in the form of
    its --portal option."""
    cmd = [a.penumbra, "info", a.scene] + environment_args(a)
    portals = re.findall(r"^\s+--portal (\S+)", run(cmd).stderr, re.MULTILINE)
    print("portals given to Cycles: %s" % (" ".join(portals) or "none found"), flush=True)
    return portals


def reference_image(a, w):
    """Step 1: the given reference (which sets --size) or a long path-traced render."""
    if a.reference:
        ref, metadata = load(a.reference)
        a.height, a.width = ref.shape[0], ref.shape[1]
        print("reference %s: %d x %d, %s spp" % (a.reference, a.width, a.height,
                                                 metadata.get("penumbra:spp", "?")))
        return ref
    path = w("penumbra_ref_%s_%dspp.exr" % (size(a), a.ref_spp))
    if not os.path.exists(path):
        info = run_penumbra(a, path, "reference", REF_SEED, spp=a.ref_spp)
        print("reference: %d spp in %.1f s" % (info["spp"], info["seconds"]), flush=True)
    return load(path)[0]


def compare_converged(a, w, ref):
    """Step 2: the per-channel mean ratio of a converged Cycles image to the reference; returns
    the image."""
    path = w("cycles_%s_%dspp.exr" % (size(a), a.cycles_converged_spp))
    if not os.path.exists(path):
        info = run_cycles(a, path, a.cycles_converged_spp, REF_SEED)
        print("\n".join(info["materials"]))
        print("converged Cycles: %d spp in %.1f s" % (info["spp"], info["seconds"]))
    image = load(path)[0]
    print("reference mean RGB: %s" % np.round(channel_means(ref), 6))
    print("converged Cycles (%d spp): mean RGB %s, ratio to reference R G B %s, relMSE %.3g"
          % (a.cycles_converged_spp, np.round(channel_means(image), 6),
             np.round(channel_ratios(image, ref), 5), relmse(image, ref)), flush=True)
    return image


def equal_time_runs(a, w, ref, converged):
    """Steps 3 to 5: every renderer at every budget, alternately; one row per render.
    converged: the converged Cycles image, or None."""
    n = a.calibration_spp
    per_spp = run_cycles(a, w("cycles_cal_%s_%d.exr" % (size(a), n)), n, TEST_SEED)["seconds"] / n
    print("Cycles calibration: %d spp, %.4f s/spp" % (n, per_spp), flush=True)
    rows = []
    for budget in a.budgets:
        for repeat in range(a.repeats):
            for renderer in a.pipelines + ["cycles"]:
                out = w("%s_%s_%gs_%d.exr" % (renderer, size(a), budget, repeat))
                if renderer == "cycles":
                    info = run_cycles(a, out, max(1, round(budget / per_spp)), TEST_SEED)
                    per_spp = info["seconds"] / info["spp"]
                else:
                    info = run_penumbra(a, out, renderer, TEST_SEED, time_limit=budget)
                image = load(out)[0]
                rows.append({"budget": budget, "renderer": renderer, "repeat": repeat,
                             "spp": info["spp"], "seconds": info["seconds"],
                             "relmse": relmse(image, ref), "ratios": channel_ratios(image, ref),
                             "relmse_cycles": (relmse(image, converged)
                                               if converged is not None else float("nan"))})
                print("budget %(budget)g s, %(renderer)s: %(spp)d spp, %(seconds).2f s, "
                      "relMSE %(relmse).4g" % rows[-1], flush=True)
    return rows


def print_tables(rows):
    print("\n| budget (s) | renderer | run | spp | seconds | relMSE | relMSE x s | "
          "mean ratio R, G, B | relMSE against converged Cycles |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for r in rows:
        print("| %g | %s | %d | %d | %.2f | %.4g | %.4g | %s | %.4g |" % (
            r["budget"], r["renderer"], r["repeat"], r["spp"], r["seconds"], r["relmse"],
            r["relmse"] * r["seconds"], ", ".join("%.4f" % x for x in r["ratios"]),
            r["relmse_cycles"]))

    print("\nMedians over the repeats:\n")
    print("| budget (s) | renderer | spp (runs) | seconds (runs) | relMSE | relMSE x s | "
          "relMSE against converged Cycles |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    groups = {}
    for r in rows:
        groups.setdefault((r["budget"], r["renderer"]), []).append(r)
    for (budget, renderer), runs in groups.items():
        print("| %g | %s | %s | %s | %.3g | %.3g | %.3g |" % (
            budget, renderer, ", ".join(str(r["spp"]) for r in runs),
            ", ".join("%.2f" % r["seconds"] for r in runs),
            statistics.median(r["relmse"] for r in runs),
            statistics.median(r["relmse"] * r["seconds"] for r in runs),
            statistics.median(r["relmse_cycles"] for r in runs)))


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap.add_argument("--penumbra", default=os.path.join(root, "build", "bin", "penumbra"))
    ap.add_argument("--scene", default=os.path.join(root, "scenes", "cornell-box",
                                                   "cornell-box.gltf"))
    ap.add_argument("--pipelines", default="reference",
                    help="penumbra pipelines to time against Cycles, comma separated")
    ap.add_argument("--reference", default=None,
                    help="an existing converged image to compare with (sets the size)")
    ap.add_argument("--size", type=int, default=256, help="image width and height without "
                    "--reference (which gives them)")
    ap.add_argument("--peers", default=os.path.join(os.path.dirname(root), "shared", "peers"),
                    help="the peer harness (cycles_render.py); default: shared/peers beside the "
                    "repository (../shared/peers from its root), found from this script's place")
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--workdir", default="/tmp/penumbra-cycles")
    ap.add_argument("--threads", type=int, default=os.cpu_count())
    ap.add_argument("--ref-spp", type=int, default=4096)
    ap.add_argument("--cycles-converged-spp", type=int, default=1024)
    ap.add_argument("--budgets", type=float, nargs="+", default=[2.0, 8.0, 30.0])
    ap.add_argument("--calibration-spp", type=int, default=32)
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--environment", nargs="?", const="scene", default=None,
                    help="light Cycles' world with the scene's own environment map (its extras), "
                    "or with FILE, through bench/cycles_environment.py")
    ap.add_argument("--cycles-portals", action="store_true",
                    help="with --environment: give Cycles, as portal lights, the openings "
                    "penumbra finds as portals (penumbra info)")
    a = ap.parse_args()
    a.width = a.height = a.size
    a.pipelines = a.pipelines.split(",")
    a.script = a.scene.endswith(".toml")
    a.gltf, a.medium = a.scene, None
    a.takes_pipeline = not a.script
    if a.script:
        if a.environment is not None:
            raise SystemExit("--environment with a pass script: give it in the script")
        with open(a.scene, "rb") as f:
            script = tomllib.load(f)
        a.gltf = os.path.join(os.path.dirname(os.path.abspath(a.scene)), script["scene"])
        a.medium = script.get("medium", [None])[0]
        if a.medium is not None and "density" in a.medium:
            a.medium["density"] = os.path.join(os.path.dirname(os.path.abspath(a.scene)),
                                               a.medium["density"])
        a.takes_pipeline = "pass" not in script
        if not a.takes_pipeline:
            a.pipelines = ["script"]
    os.makedirs(a.workdir, exist_ok=True)
    w = lambda name: os.path.join(a.workdir, name)  # noqa: E731

    if a.cycles_portals and a.environment is None:
        raise SystemExit("--cycles-portals needs --environment")
    a.portals = found_portals(a) if a.cycles_portals else []
    ref = reference_image(a, w)
    converged = compare_converged(a, w, ref) if a.cycles_converged_spp > 0 else None
    print_tables(equal_time_runs(a, w, ref, converged))


if __name__ == "__main__":
    sys.exit(main())
