// A pass of the rendering pipeline and the context passes share.
//
// Lifecycle (after Tungsten's integrators and RenderPark's radiosity methods): prepare() once,
// then run() until it reports that the pass is finished (a progressive pass returns after each
// step, so a pipeline can stop it at a time limit), then stats(). Passes communicate only through
// read-only products registered in the PassContext (image layers now; the radiosity solution and
// the caustic photon map later), never through global mutable state.
//
// Every pass declares the light transport its product contains, in Heckbert's notation for light
// paths (Heckbert 1990, "Adaptive Radiosity Textures for Bidirectional Ray Tracing"): L a light,
// D a diffuse or rough glossy vertex, S a specular vertex, E the eye. The pipeline uses the
// declarations to check that every path is counted exactly once.
#pragma once

#include "core/camera.h"
#include "core/image.h"
#include "core/render_settings.h"
#include "core/scene.h"

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace penumbra {

// Named figures a pass reports (counters, timings), in the order they were added.
using PassStats = std::vector<std::pair<std::string, std::string>>;

class PassContext {
  public:
    PassContext(const Scene& scene, const Camera& camera, const RenderSettings& settings)
        : scene(scene), camera(camera), settings(settings) {}

    const Scene& scene;
    const Camera& camera;
    const RenderSettings& settings;

    // Image layers produced so far, by name: "beauty" and AOVs such as "albedo".
    std::map<std::string, Image> layers;
};

class Pass {
  public:
    virtual ~Pass() = default;

    // The pass type as written in pass scripts, e.g. "path".
    virtual std::string type() const = 0;
    // The light paths the pass's product contains, as a Heckbert expression, e.g. "L(D|S)*E".
    virtual std::string lightPaths() const = 0;

    virtual void prepare(PassContext& context) = 0;
    // Advances the pass; returns true when it has finished.
    virtual bool run(PassContext& context) = 0;
    virtual PassStats stats() const = 0;
};

}  // namespace penumbra
