#include "passes/distribution_pass.h"

#include "core/stats.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_solution.h"

#include <array>
#include <limits>

namespace penumbra {

namespace {

// Whitted's `ambient` as a script gives it: a grey radiance (cd/m²) >= 0, or this value for the
// word "radiosity" (the solution's mean).
constexpr float kAmbientFromSolution = -1.0f;

// The script keys of the distribution pass and, with the ambient term, of the whitted pass, in
// the order the plan prints them.
template <typename Settings, typename Keys>
void distributionKeys(Settings& s, Keys& keys) {
    keys("max_specular_depth", s.maxSpecularDepth, 0, kMaxDepthLimit);
}
template <typename Settings, typename Ambient, typename Keys>
void whittedKeys(Settings& s, Ambient& ambient, Keys& keys) {
    distributionKeys(s, keys);
    keys.orWord("ambient", ambient, "radiosity", kAmbientFromSolution, 0.0f,
                std::numeric_limits<float>::max());
    keys("medium_steps", s.mediumSteps, 1, 1024);
    keys.choice("medium", s.mediumPreview,
                NamedValues<DistributionSettings::MediumPreview>{
                    {"single-scattering", DistributionSettings::MediumPreview::SingleScattering},
                    {"linear-fog", DistributionSettings::MediumPreview::LinearFog}});
}

}  // namespace

std::unique_ptr<Pass> DistributionPass::fromScript(const ScriptTable& table, const PassOverrides&) {
    ParameterReader keys(table);
    DistributionSettings settings;
    distributionKeys(settings, keys);
    return std::make_unique<DistributionPass>(settings);
}

std::unique_ptr<Pass> DistributionPass::whittedFromScript(const ScriptTable& table,
                                                          const PassOverrides&) {
    ParameterReader keys(table);
    DistributionSettings settings;
    float ambient = 0.0f;
    whittedKeys(settings, ambient, keys);
    if (ambient == kAmbientFromSolution)
        return std::make_unique<DistributionPass>(settings, Ambient::RadiosityMean);
    settings.ambient = Color(ambient);
    return std::make_unique<DistributionPass>(settings, Ambient::Constant);
}

Color meanReflectedRadiance(const Scene& scene, const RadiositySolution& solution) {
    constexpr std::array<Vec3, 3> kEdgeMidpoints = {Vec3(0.5f, 0.5f, 0.0f), Vec3(0.0f, 0.5f, 0.5f),
                                                    Vec3(0.5f, 0.0f, 0.5f)};
    const std::span<const Mesh> meshes = scene.meshes();
    glm::dvec3 sum(0.0);
    double area = 0.0;
    for (uint32_t m = 0; m < meshes.size(); ++m) {
        const Mesh& mesh = meshes[m];
        const Material& material = scene.materials()[mesh.material];
        if (!holdsMaterial(material))
            continue;
        for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
            const glm::uvec3& v = mesh.triangles[t];
            const double triangleArea =
                0.5 *
                glm::length(glm::cross(glm::dvec3(mesh.positions[v.y] - mesh.positions[v.x]),
                                       glm::dvec3(mesh.positions[v.z] - mesh.positions[v.x])));
            for (const bool front : {true, false}) {
                if (!front && !material.doubleSided)
                    continue;
                glm::dvec3 triangleSum(0.0);
                for (const Vec3& b : kEdgeMidpoints)
                    triangleSum += glm::dvec3(solution.radiance(m, t, b, false, front));
                sum += triangleArea * triangleSum / 3.0;
                area += triangleArea;
            }
        }
    }
    return area > 0.0 ? Color(sum / area) : Color(0.0f);
}

PassStats DistributionPass::parameters() const {
    ParameterPrinter print;
    if (ambient_ == Ambient::Radiosity) {
        distributionKeys(settings_, print);
    } else {
        // The mean replaces settings_.ambient once the solution exists: print its source.
        const float ambient =
            ambient_ == Ambient::RadiosityMean ? kAmbientFromSolution : settings_.ambient.r;
        whittedKeys(settings_, ambient, print);
    }
    return print.stats();
}

PassStats DistributionPass::stats() const {
    PassStats stats = SamplingPass::stats();
    // Whether the solve was abandoned and the indirect light path traced (makeEstimator).
    if (ambient_ == Ambient::Radiosity)
        stats.push_back({"indirect_path_traced", pathTracer_ ? "yes" : "no"});
    if (ambient_ == Ambient::RadiosityMean) {
        const Color& a = settings_.ambient;
        stats.push_back(
            {"ambient_radiance", formatStat(a.r) + " " + formatStat(a.g) + " " + formatStat(a.b)});
    }
    return stats;
}

RadianceEstimator DistributionPass::makeEstimator(PassContext& context) {
    radiosity_ = context.product<RadiositySolution>(products::kRadiositySolution);
    if (ambient_ == Ambient::Radiosity && !radiosity_ && context.contents.diffuse) {
        // The scene has diffuse surfaces, so the radiosity pass ran, and gave up its solve at the
        // time limit (WithoutSolution::kTraces): the path tracer's estimate instead, of every path
        // but the caustics another pass counts. It counts the paths of distributionLightPaths()
        // and those it leaves out (light through mirrors onto the surface seen, ...), none twice.
        PathTracerSettings traced;
        traced.excludeCaustics = causticPathsCounted_;
        pathTracer_ = std::make_unique<PathTracer>(context.scene, traced);
        return [tracer = pathTracer_.get()](const Ray& ray, Sampler& sampler, FirstHit* firstHit,
                                            PathCounters& counters) {
            return tracer->Li(ray, sampler, firstHit, counters);
        };
    }
    if (ambient_ == Ambient::RadiosityMean) {
        // Null when the planner skipped the radiosity pass: no diffuse surface to reflect.
        settings_.ambient =
            radiosity_ ? meanReflectedRadiance(context.scene, *radiosity_) : Color(0.0f);
    } else if (radiosity_) {
        reusedSolution_.emplace(*radiosity_);
    }
    tracer_ = std::make_unique<DistributionTracer>(context.scene, settings_,
                                                   reusedSolution_ ? &*reusedSolution_ : nullptr);
    return [tracer = tracer_.get()](const Ray& ray, Sampler& sampler, FirstHit* firstHit,
                                    PathCounters& counters) {
        return tracer->Li(ray, sampler, firstHit, counters);
    };
}

}  // namespace penumbra
