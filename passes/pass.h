// A pass of the rendering pipeline and the context passes share.
//
// Lifecycle (after Tungsten's integrators and RenderPark's radiosity methods): prepare() once,
// then run() until it reports that the pass is finished (a progressive pass returns after each
// step, so that the pipeline can stop it at its time limit with stopEarly()), then stats(). Passes
// communicate only through read-only products registered in the PassContext (image layers, the
// radiosity solution, the caustic photon map), never through global mutable state.
//
// Every pass declares the light transport its product contains, in Heckbert's notation for light
// paths (Heckbert 1990, "Adaptive Radiosity Textures for Bidirectional Ray Tracing"): L a light,
// D a diffuse or rough glossy vertex, S a specular vertex, E the eye. The pipeline uses the
// declarations to check that every path is counted exactly once.
#pragma once

#include "core/camera.h"
#include "core/deadline.h"
#include "core/image.h"
#include "core/render_settings.h"
#include "core/scene.h"
#include "core/scene_contents.h"
#include "core/stats.h"

#include <any>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace penumbra {

class PassContext {
  public:
    PassContext(const Scene& scene, const SceneContents& contents, const Camera& camera,
                const RenderSettings& settings)
        : scene(scene), contents(contents), camera(camera), settings(settings) {}

    const Scene& scene;
    const SceneContents contents;  // the scene's analysis, done once (core/scene_contents.h)
    const Camera& camera;
    const RenderSettings& settings;

    // When the pipeline's time limit ends (RenderSettings::timeLimit from the start of the first
    // pass), set by Pipeline::run; absent without a limit. Passes that sample until it is spent
    // measure their progress against it; the pipeline stops them (Pass::stopEarly).
    Deadline deadline;

    // Image layers produced so far, by name: each image-forming pass's contribution (under the
    // pass's type, e.g. "path"), "beauty" (their sum, made by the composite) and AOVs such as
    // "albedo".
    std::map<std::string, Image> layers;
    // The names of the contribution layers, in the order the passes made them.
    std::vector<std::string> contributions;

    // Publishes the image a pass contributes to the beauty under `name`.
    void contribute(const std::string& name, Image image) {
        layers[name] = std::move(image);
        contributions.push_back(name);
    }

    // Adds `image` to layer `name` pixel by pixel, or makes it the layer if there is none yet:
    // for layers that several passes share, such as the light-path components
    // (core/path_components.h). The sizes and channels must match (std::logic_error).
    void addToLayer(const std::string& name, const Image& image);

    // Read-only products passes hand to later passes, by name (passes/products.h). The publisher
    // keeps the type; a reader asks for the type it expects and gets null when the product is
    // absent.
    template <typename T>
    void publish(const std::string& name, std::shared_ptr<const T> product) {
        products_[name] = std::move(product);
    }
    template <typename T>
    std::shared_ptr<const T> product(const std::string& name) const {
        const auto it = products_.find(name);
        if (it == products_.end())
            return nullptr;
        const auto* typed = std::any_cast<std::shared_ptr<const T>>(&it->second);
        return typed ? *typed : nullptr;
    }

  private:
    std::map<std::string, std::any> products_;
};

// What a pass's output holds that other passes' light-path declarations depend on: flags, not
// data (the data a pass hands on are its products).
// How a pass that reuses a radiosity solution at path vertices takes the light those vertices
// receive through specular surfaces: it traces it itself, so the solution must not hold it
// (kTraced), or it takes it from a solution that holds it with the caustics (the radiosity
// pass's specular transfer after a caustic pass) and traces it otherwise (kFromSolution).
enum class SpecularAtReuse { kNotReused, kTraced, kFromSolution };

// What a pass that reuses a radiosity solution does when it has none, because the solve was
// abandoned at the time limit (RadiosityPass), from the least it can to the most.
enum class WithoutSolution {
    kCannot,  // nothing replaces the solution: the solve is coarsened to end in time instead
    // It traces the light the solution would have given (a distribution pass path-traces the
    // indirect light; a path pass that takes the solution as it is traces every path on): as
    // right as the path tracer, but a coarse solution serves a preview better while it can be
    // had, so the solve is abandoned only when it would not end within the whole time limit.
    kTraces,
    // It does as well without, only slower (a path pass that corrects the solution: its estimate
    // is the path tracer's in expectation either way), so the solve is abandoned as soon as it
    // would not end within its share of the time.
    kSame,
};

struct TransportFlags {
    // The pass's image counts the caustic paths L S+ D S* E (a caustic pass): a path pass in auto
    // mode leaves them out.
    bool countsCausticPaths = false;
    // The pass's radiosity solution took the photons of a caustic map made before it, so it holds
    // L S+ D+ as well: the passes that reuse it take those caustics through it.
    bool solutionTakesCaustics = false;
    // The pass's radiosity solution carries its own light through specular surfaces too (D S+ D,
    // RadiosityPass's specular transfer), so it holds L S* D (S* D)* (without the caustic
    // photons, L D (S* D)*).
    bool solutionTransfersSpecular = false;
    // How the pass takes the light that the vertices where it reuses a radiosity solution
    // receive through specular surfaces (PathPass): kNotReused when it reuses none there.
    SpecularAtReuse specularAtReuse = SpecularAtReuse::kNotReused;
    // What the pass does without the radiosity solution it reuses (WithoutSolution).
    WithoutSolution withoutSolution = WithoutSolution::kCannot;
    // The pass counts the caustic paths L S+ D S* E itself when no other pass of the pipeline
    // does (a path pass with caustics = "auto").
    bool tracesUncountedCaustics = false;
    // The pass shows a radiosity solution's light at the points the eye sees (distribution ray
    // tracing's ambient term), so the solution's values at points matter, not only its element
    // means (RadiositySettings::indirectAtCorners).
    bool showsSolution = false;
};

// What a pass learns of the rest of its pipeline when the pipeline is planned.
struct PipelineShape {
    std::set<std::string> products;     // made by any pass of the pipeline (passes/products.h)
    std::set<std::string> madeBefore;   // made by a pass before this one
    std::set<std::string> neededLater;  // needed by a pass after this one
    bool causticPathsCounted = false;   // some pass of the pipeline counts L S+ D S* E
    bool causticsInRadiosity = false;   // a solution made before this pass holds L S+ D+
    // A solution made before this pass carries light through specular surfaces (D S+ D).
    bool specularTransferInRadiosity = false;
    // What the passes after this one do with light through specular surfaces at their reuse
    // vertices (TransportFlags::specularAtReuse): whether one traces it whatever the solution
    // holds, and whether one takes it from a solution that holds it.
    bool specularTracedLater = false;
    bool specularFromSolutionLater = false;
    // What the passes after this one that reuse the radiosity solution do without it: the least
    // any of them can (TransportFlags::withoutSolution).
    WithoutSolution withoutSolutionLater = WithoutSolution::kSame;
    // A pass after this one traces the caustic paths L S+ D S* E itself when no other pass counts
    // them (TransportFlags::tracesUncountedCaustics).
    bool causticsTracedLater = false;
    // A pass after this one shows the radiosity solution at the points the eye sees
    // (TransportFlags::showsSolution).
    bool solutionShownLater = false;
};

class Pass {
  public:
    virtual ~Pass() = default;

    // The pass type as written in pass scripts, e.g. "path".
    virtual std::string type() const = 0;
    // The light paths of the image the pass adds to the beauty, as a Heckbert expression
    // (core/light_paths.h), e.g. "L(D|S)*E"; "" when it adds no image (it only makes a product
    // for later passes). Valid after adapt().
    virtual std::string lightPaths() const = 0;
    // Products (PassContext::publish; names in passes/products.h) the pass makes, and those it
    // needs from earlier passes.
    virtual std::set<std::string> products() const { return {}; }
    virtual std::set<std::string> needs() const { return {}; }
    // What its output holds that the other passes' declarations depend on. Valid after adapt()
    // (countsCausticPaths before it as well).
    virtual TransportFlags transportFlags() const { return {}; }
    // Called once by the planner before prepare(): a pass may change its role by what the rest
    // of the pipeline does (a radiosity pass whose solution a later pass reuses shows no image
    // of its own; a path pass leaves caustic paths to a caustic pass).
    virtual void adapt(const PipelineShape&) {}
    // Whether the pass files its image by light group within one render when
    // RenderSettings::lightGroups asks it to (its layers "light.GROUP" sum to its image): then a
    // pipeline whose passes all do renders its light groups at once. Valid after adapt().
    virtual bool splitsLightGroups() const { return false; }
    // Whether what the pass adds (its image or its products) accounts for a participating
    // medium: its attenuation and its in-scattered light. The planner refuses a scene with a
    // medium for a pipeline with a pass that runs and does not. Valid after adapt().
    virtual bool rendersMedia() const { return false; }
    // The pass's parameters as resolved, for the plan and the log.
    virtual PassStats parameters() const { return {}; }
    // Why the pass has nothing to do for a scene with these contents, so that the planner skips
    // it; "" when it runs. Valid after adapt().
    virtual std::string skipReason(const SceneContents&) const { return ""; }

    virtual void prepare(PassContext& context) = 0;
    // Advances the pass by one step; returns true when it has finished (its image and products
    // published).
    virtual bool run(PassContext& context) = 0;
    // Asked between steps when the pipeline's time limit would pass before the next step ends: a
    // pass that refines its image step by step publishes what its steps made so far and returns
    // true (finished); one whose work cannot be cut short, or whose fixed amount the passes after
    // it rely on, returns false and goes on.
    virtual bool stopEarly(PassContext&) { return false; }
    // How long publishing what the steps made so far would take (the hybrid's reconstruction of
    // its correction), which the pipeline leaves for it before the time limit; zero for a pass
    // that publishes at once.
    virtual std::chrono::steady_clock::duration publishingTime() const { return {}; }
    virtual PassStats stats() const = 0;
};

}  // namespace penumbra
