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
//
// Caustics: when a caustic pass made a photon map before it, the hierarchical solver takes the
// photons' flux as deposited light (radiosity/deposited_flux.h), so that the solution also holds
// L S+ D+ (indirect caustics: light through the glass onto the floor, then to the walls), unless
// the pass is told to leave them out (Caustics::Exclude, the script's caustics = "exclude"). Its
// transport flags then say so (solutionTakesCaustics), by which the passes reusing the solution
// know what it holds. The progressive solver takes no photons.
//
// Specular transfer: the hierarchical solution's links carry light between diffuse surfaces only;
// mirrors and glass send it on too (a floor lit through the glass balustrade by the wall behind
// it: D S+ D). Unless told to leave it out (Transfer::Exclude, specular_transfer = "exclude"), or
// a path pass reuses the solution (its reuse vertex traces that light itself), the pass shoots
// photons from the solved light and solves again until that light settles
// (passes/specular_transfer.h): the solution then holds L S* D (S* D)*, and its transport flags
// say so to the passes reusing it.
#pragma once

#include "passes/pass.h"
#include "passes/pass_parameters.h"
#include "passes/products.h"
#include "passes/sampling_pass.h"
#include "radiosity/progressive_solver.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_solver.h"

#include <memory>
#include <variant>

namespace penumbra {

class RadiosityPass : public SamplingPass {
  public:
    // Whether the solution takes the photons of a caustic map made before the pass: Auto takes
    // them when there is one (hierarchical solver only).
    enum class Caustics { Auto, Exclude };
    // Whether the solution carries its light through specular surfaces: Auto does unless a path
    // pass reuses it (hierarchical solver only; nothing to do without specular surfaces).
    enum class Transfer { Auto, Exclude };
    // transfer_photons = "auto": automaticTransferPhotons() (passes/specular_transfer.h).
    static constexpr int64_t kAutoTransferPhotons = 0;

    // The settings are validated here (UsageError naming the key).
    explicit RadiosityPass(RadiositySettings settings, Caustics caustics = Caustics::Auto,
                           Transfer transfer = Transfer::Auto);
    explicit RadiosityPass(ProgressiveSettings settings);
    ~RadiosityPass() override;
    // The pass of a script's [[pass]] table of type "radiosity": `solver` picks the method and so
    // the keys that are valid (those of the other solver are refused as unknown); each set is
    // checked by its validate function, the same rules as for any other caller.
    static std::unique_ptr<Pass> fromScript(const ScriptTable& table, const PassOverrides&);

    std::string type() const override { return "radiosity"; }
    std::string lightPaths() const override;
    std::set<std::string> products() const override { return {products::kRadiositySolution}; }
    TransportFlags transportFlags() const override { return {false, takesCaustics_, transfers_}; }
    void adapt(const PipelineShape& shape) override;
    // A solution that only later passes reuse: they say whether they render a medium (the
    // corrected path pass does, whatever the solution holds). The view does not. The solution
    // holds part of a medium's effect, the transmittance its shadow rays carry
    // (Scene::transmittance), not the light the medium scatters.
    bool rendersMedia() const override { return !view_; }
    // A solution that only later passes reuse is zero without a diffuse surface: skipped then.
    std::string skipReason(const SceneContents& contents) const override;
    PassStats parameters() const override;
    // Meshes the scene and solves (the long part); the view, if the pass shows one, is formed by
    // run() like any sampling pass's image.
    void prepare(PassContext& context) override;
    // Finished at once when the pass forms no image; else SamplingPass::run().
    bool run(PassContext& context) override;
    // The resolved parameters, the solver's figures (patches, elements, links, iterations,
    // residual, seconds per stage), then those of the view (SamplingPass::samplingFigures(),
    // all but spp and dropped_samples named "view ...", as the solver has its own seconds and
    // rays).
    PassStats stats() const override;

    // Radiance (cd/m²) arriving along -ray.d at the ray's origin from the first opaque surface
    // the mesh holds: thin glass and alpha cut-outs in front of it are passed through with their
    // straight transmittance (Scene::straightTransmittance); zero when the ray leaves the scene.
    PathRadiance Li(Ray ray, FirstHit* firstHit, PathCounters& counters) const;

  protected:
    RadianceEstimator makeEstimator(PassContext& context) override;
    std::string activity() const override { return "radiosity view"; }

  private:
    // Photons per specular-transfer round, transferPhotons_ with auto resolved for the mesh.
    uint64_t transferPhotons(const RadiosityMesh& mesh) const;
    // The hierarchical settings as solved for this pipeline: the direct light at the corners
    // only for a view.
    RadiositySettings solvedSettings(const RadiositySettings& asked) const;

    std::variant<RadiositySettings, ProgressiveSettings> settings_;
    Caustics caustics_ = Caustics::Exclude;
    Transfer transfer_ = Transfer::Auto;
    int64_t transferPhotons_ = kAutoTransferPhotons;
    bool transfers_ = false;  // the solution carries its light through specular surfaces
    bool view_ = true;        // forms the image (no later pass reuses the solution)
    bool shown_ = true;       // the view or a later pass shows its light at points
    // What the passes that reuse the solution do without it; kCannot for a view.
    WithoutSolution withoutSolution_ = WithoutSolution::kCannot;
    bool takesCaustics_ = false;  // the solution takes a caustic map made before the pass
    const Scene* scene_ = nullptr;
    std::shared_ptr<RadiosityMesh> mesh_;
    std::shared_ptr<RadiositySolution> solution_;
};

}  // namespace penumbra
