#!/usr/bin/python3
"""Equal-time comparison of penumbra's reference path tracer with Blender Cycles on the Cornell box.

Not a test and not part of the build: a benchmark script whose output docs/benchmarks.md quotes.
It needs Blender and the peer harness of /work/shared/peers (see its README; on Debian 12:
`apt-get install -y blender python3-numpy python3-openimageio`), and runs with /usr/bin/python3.

Steps (all images 256 x 256, linear EXR, in --workdir):
  1. reference: penumbra, --ref-spp samples (default 4096), seed 1000 (kept if already there);
  2. converged Cycles image (--cycles-converged-spp, 0 to skip; kept if already there) and its
     per-channel mean ratio to the reference: do the two renderers agree on the image they
     converge to?
  3. Cycles' cost per sample, from one calibration render (--calibration-spp);
  4. for each budget (seconds), --repeats times, alternately: penumbra with --time-limit BUDGET
     --seed 1, then Cycles (seed 1) with the spp that the latest measured Cycles rate says fits
     in BUDGET. Cycles has no time limit of its own, so its spp is chosen beforehand and on a
     shared machine its time drifts; every Cycles render updates the rate (seconds per spp, its
     scene sync included) for the next one, so the repeats home in on the budget;
  5. relMSE of every render against the reference: mean over pixels and channels of
     (test - ref)^2 / (ref^2 + 0.01) (the same formula as the peers' imgdiff.py), and
     relMSE x seconds, the time-normalised error (an unbiased estimator's relMSE falls as
     1 / samples, so this product compares renderers even when their times differ; lower is
     better).

Timings: penumbra's is the path-tracing pass (`path seconds` of its report, without the ~0.1 s
of loading); Cycles' is `render_s` of cycles_render.py (bpy.ops.render.render: scene sync, BVH
build and path tracing, without Blender's start-up and the glTF import).
"""
import argparse
import json
import os
import re
import subprocess
import sys

import numpy as np
import OpenImageIO as oiio

SIZE = 256
REF_SEED = 1000
TEST_SEED = 1
RELMSE_EPS = 0.01


def load(path):
    inp = oiio.ImageInput.open(path)
    if inp is None:
        raise SystemExit("cannot open %s: %s" % (path, oiio.geterror()))
    spec = inp.spec()
    pixels = inp.read_image(0, 0, 0, spec.nchannels, oiio.FLOAT)
    inp.close()
    image = np.asarray(pixels, dtype=np.float64).reshape(spec.height, spec.width, spec.nchannels)
    names = list(spec.channelnames)
    return image[:, :, [names.index(c) for c in "RGB"]]


def relmse(test, ref):
    return float(np.mean((test - ref) ** 2 / (ref * ref + RELMSE_EPS)))


def channel_ratios(test, ref):
    return [float(test[:, :, c].mean() / ref[:, :, c].mean()) for c in range(3)]


def run_penumbra(a, out, seed, spp=None, time_limit=None):
    cmd = [a.penumbra, "render", a.scene, "-o", out, "--width", str(SIZE), "--height", str(SIZE),
           "--seed", str(seed), "--threads", str(a.threads)]
    if time_limit is not None:
        cmd += ["--time-limit", str(time_limit), "--spp", "1000000"]
    else:
        cmd += ["--spp", str(spp)]
    print("$ " + " ".join(cmd), flush=True)
    log = subprocess.run(cmd, check=True, capture_output=True, text=True).stderr
    stats = dict(re.findall(r"^\s+path (\S+): (\S+)$", log, re.MULTILINE))
    return {"spp": int(stats["spp"]), "seconds": float(stats["seconds"]),
            "rays_per_s": float(stats["rays_per_second"])}


def run_cycles(a, out, spp, seed):
    cmd = [a.blender, "-b", "--factory-startup", "-P",
           os.path.join(a.peers, "cycles_render.py"), "--", "--scene", a.scene, "--out", out,
           "--spp", str(spp), "--width", str(SIZE), "--height", str(SIZE),
           "--threads", str(a.threads), "--seed", str(seed)]
    print("$ " + " ".join(cmd), flush=True)
    log = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    materials = re.findall(r"^material .*$", log, re.MULTILINE)
    result = json.loads(re.search(r"^CYCLES_RESULT (.*)$", log, re.MULTILINE).group(1))
    return {"spp": spp, "seconds": result["render_s"], "materials": materials}


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap.add_argument("--penumbra", default=os.path.join(root, "build", "bin", "penumbra"))
    ap.add_argument("--scene", default=os.path.join(root, "scenes", "cornell-box",
                                                   "cornell-box.gltf"))
    ap.add_argument("--peers", default="/work/shared/peers")
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--workdir", default="/tmp/penumbra-cycles")
    ap.add_argument("--threads", type=int, default=os.cpu_count())
    ap.add_argument("--ref-spp", type=int, default=4096)
    ap.add_argument("--cycles-converged-spp", type=int, default=1024)
    ap.add_argument("--budgets", type=float, nargs="+", default=[2.0, 8.0, 30.0])
    ap.add_argument("--calibration-spp", type=int, default=32)
    ap.add_argument("--repeats", type=int, default=1)
    a = ap.parse_args()
    os.makedirs(a.workdir, exist_ok=True)
    w = lambda name: os.path.join(a.workdir, name)  # noqa: E731

    # 1. The reference.
    ref_path = w("penumbra_ref_%dspp.exr" % a.ref_spp)
    if not os.path.exists(ref_path):
        info = run_penumbra(a, ref_path, REF_SEED, spp=a.ref_spp)
        print("reference: %d spp in %.1f s" % (info["spp"], info["seconds"]), flush=True)
    ref = load(ref_path)
    print("reference mean RGB: %s" % np.round([ref[:, :, c].mean() for c in range(3)], 6))

    # 2. Do they converge to the same image?
    if a.cycles_converged_spp > 0:
        path = w("cycles_%dspp.exr" % a.cycles_converged_spp)
        if not os.path.exists(path):
            info = run_cycles(a, path, a.cycles_converged_spp, REF_SEED)
            print("\n".join(info["materials"]))
            print("converged Cycles: %d spp in %.1f s" % (info["spp"], info["seconds"]))
        image = load(path)
        print("converged Cycles (%d spp): mean RGB %s, ratio to reference R G B %s, relMSE %.3g"
              % (a.cycles_converged_spp, np.round([image[:, :, c].mean() for c in range(3)], 6),
                 np.round(channel_ratios(image, ref), 5), relmse(image, ref)), flush=True)

    # 3. Cycles' seconds per sample per pixel.
    n = a.calibration_spp
    per_spp = run_cycles(a, w("cycles_cal_%d.exr" % n), n, TEST_SEED)["seconds"] / n
    print("Cycles calibration: %d spp, %.4f s/spp" % (n, per_spp), flush=True)

    # 4 and 5. Equal time, alternating the renderers.
    rows = []
    for budget in a.budgets:
        for repeat in range(a.repeats):
            for renderer in ("penumbra", "cycles"):
                out = w("%s_%gs_%d.exr" % (renderer, budget, repeat))
                if renderer == "penumbra":
                    info = run_penumbra(a, out, TEST_SEED, time_limit=budget)
                else:
                    info = run_cycles(a, out, max(1, round(budget / per_spp)), TEST_SEED)
                    per_spp = info["seconds"] / info["spp"]
                image = load(out)
                rows.append((budget, renderer, repeat, info["spp"], info["seconds"],
                             relmse(image, ref), channel_ratios(image, ref)))
                print("budget %g s, %s: %d spp, %.2f s, relMSE %.4g"
                      % (rows[-1][:2] + rows[-1][3:6]), flush=True)

    print("\n| budget (s) | renderer | run | spp | seconds | relMSE | relMSE x s | "
          "mean ratio R, G, B |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for budget, renderer, repeat, spp, seconds, err, ratios in rows:
        print("| %g | %s | %d | %d | %.2f | %.4g | %.4g | %s |" % (
            budget, renderer, repeat, spp, seconds, err, err * seconds,
            ", ".join("%.4f" % r for r in ratios)))


if __name__ == "__main__":
    sys.exit(main())
