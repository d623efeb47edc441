// The radiosity pass: solves radiosity for the whole scene (radiosity/: hierarchical, the default,
// or progressive refinement, by the settings given), then forms
// the image by showing, at the first opaque surface each camera ray meets, the solution's
// interpolated radiance on the side the ray sees, emission included. No further bounce is traced:
// specular and transmissive light is not in the image.
//
// Product: the solution ("radiosity", a RadiositySolution) for later passes. When no later pass
// reuses it, the pass also contributes the image "radiosity" (light paths L D* E: emission seen
// directly and the reflected light of every bounce, rough glossy reflection spread as
// Lambertian: radiosity_solver.h) and
// the requested AOVs; otherwise it forms no image.
#pragma once

#include "core/pass.h"
#include "core/progress.h"
#include "radiosity/progressive_solver.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_solver.h"
#include "raytrace/image_renderer.h"

#include <chrono>
#include <memory>
#include <variant>

namespace penumbra {

class RadiosityPass : public Pass {
  public:
    // The settings are validated here (UsageError naming the key).
    explicit RadiosityPass(RadiositySettings settings);
    explicit RadiosityPass(ProgressiveSettings settings);
    ~RadiosityPass() override;

    std::string type() const override { return "radiosity"; }
    std::string lightPaths() const override { return view_ ? "LD*E" : ""; }
    std::set<std::string> products() const override { return {"radiosity"}; }
    void adapt(const PipelineShape& shape) override {
        view_ = !shape.neededLater.count("radiosity");
    }
    PassStats parameters() const override;
    // Meshes the scene and solves (the long part); the image is formed by run().
    void prepare(PassContext& context) override;
    // Renders one sample per pixel; finished after RenderSettings::spp of them.
    bool run(PassContext& context) override;
    // The solver's figures (patches, elements, links, iterations, residual, seconds per stage),
    // then those of the image.
    PassStats stats() const override;

    // Radiance (cd/m²) arriving along -ray.d at the ray's origin from the first opaque surface
    // the mesh holds: thin glass and alpha cut-outs in front of it are passed through with their
    // straight transmittance (Scene::straightTransmittance); zero when the ray leaves the scene.
    PathRadiance Li(Ray ray, FirstHit* firstHit, PathCounters& counters) const;

  private:
    std::variant<RadiositySettings, ProgressiveSettings> settings_;
    bool view_ = true;  // forms the image (no later pass reuses the solution)
    const Scene* scene_ = nullptr;
    std::shared_ptr<RadiosityMesh> mesh_;
    std::shared_ptr<RadiositySolution> solution_;
    std::unique_ptr<ImageRenderer> renderer_;
    std::unique_ptr<Progress> progress_;
    std::chrono::steady_clock::time_point renderStart_;
    double renderSeconds_ = 0.0;
};

}  // namespace penumbra
