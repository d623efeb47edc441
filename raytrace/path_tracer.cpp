#include "raytrace/path_tracer.h"

#include "core/sampler.h"
#include "core/sampling.h"
#include "core/surface_crossing.h"
#include "raytrace/direct_light.h"
#include "raytrace/tracing_steps.h"

#include <stdexcept>

namespace penumbra {

namespace {

constexpr EnvironmentPart kEnvironmentParts[] = {EnvironmentPart::Map, EnvironmentPart::Sun};

// Paths always have at least this probability of ending at each roulette test, so that a
// path cannot run forever even in a closed box of perfect mirrors; the survivors are
// reweighted by 1 / (1 - q), which keeps the estimator unbiased. It must stay below 1 - rho^2:
// where the throughput stays near 1 (albedo rho), the weights grow as (rho / (1 - q))^k while
// paths survive with (1 - q)^k, so the variance sum of (rho^2 / (1 - q))^k diverges otherwise
// (0.05 gave a 0.99 furnace infinite variance: 89 +- 22 for 100, tests/cli/stress_test.cpp).
constexpr float kMinTerminationProbability = 1e-3f;
// Roulette starts after this many scattering events (the first bounces carry most variance).
constexpr int kRouletteStartDepth = 3;

}  // namespace

float rouletteTerminationProbability(int depth, const Color& beta) {
    if (depth < kRouletteStartDepth)
        return 0.0f;
    return glm::max(kMinTerminationProbability, 1.0f - maxComponent(beta));
}

std::string pathTracerLightPaths(const PathTracerSettings& settings) {
    // Without reuse: every path, less the caustic ones (paths with no D: L S* E; one D with no S
    // before it: L D S* E; two or more D: L (D|S)* D S* D S* E). With reuse: what the first
    // diffuse vertex's next-event estimation and BSDF samples find, and at the second diffuse
    // vertex, seen through specular chains, the light arriving there: the radiosity solution's
    // L D+, the light of specular chains from the lights (L S+ D: the caustic map's, or found by
    // tracing), and the same again at the diffuse vertex behind each specular chain the reuse
    // vertex sees ((S+ D)*). With no specular surface in the scene the last two are empty. A
    // solution that took the caustic photons holds L S+ D+ as well: L S* D+ arrives.
    // A correction (correctionProbability > 0) traces, in expectation, everything the solution
    // held: the paths are the path tracer's again.
    // Only the tracers that count every path meet a medium (V vertices), the corrected reuse
    // too: the planner refuses media for the others.
    if (!settings.excludeCaustics &&
        (!settings.reuseRadiosity || settings.correctionProbability > 0.0f))
        return "L(D|S|V)*E";
    if (!settings.reuseRadiosity || settings.correctionProbability > 0.0f)
        return "L S* E | L D S* E | L (D|S)* D S* D S* E";
    // A solution that holds the light through specular surfaces as well: every path with two
    // diffuse vertices or more arrives at the second one through it.
    if (settings.causticsInRadiosity && settings.specularInRadiosity)
        return std::string(settings.excludeCaustics ? "L S* E | L D S* E"
                                                    : "L S* E | L S* D S* E") +
               " | L S* D (S* D)+ S* E";
    return std::string(settings.excludeCaustics ? "L S* E | L D S* E | "
                                                : "L S* E | L S* D S* E | ") +
           (settings.causticsInRadiosity ? "L S* D+" : "(L D+ | L S+ D)") + " (S+ D)* S* D S* E";
}

bool tracesMedia(const PathTracerSettings& settings) {
    if (settings.excludeCaustics)
        return false;
    return !settings.reuseRadiosity ||
           (settings.correctionProbability > 0.0f && !settings.causticsAtReuse);
}

PathTracer::PathTracer(const Scene& scene, const PathTracerSettings& settings,
                       const ReusedSolution* radiosity, const ReusedCaustics* causticMap,
                       const LightGroupSplit* groups)
    : scene_(scene),
      settings_(settings),
      radiosity_(radiosity),
      causticMap_(causticMap),
      groups_(groups) {
    if (groups_ && settings_.reuseRadiosity)
        throw std::logic_error("PathTracer: light groups need a tracer without reuse");
    if (scene_.medium() && !tracesMedia(settings_))
        throw std::logic_error("PathTracer: a medium needs a tracer that counts every path");
    const Medium* medium = scene_.medium();
    if (medium && medium->scatters() && settings_.equiangular) {
        for (const auto& light : scene_.lights())
            equiangular_ = equiangular_ || pointLike(*light);
    }
}

namespace {

// The weights of one path, whose sum is the path tracer's throughput (see Li()).
struct PathWeights {
    // The part that takes the solution at each reuse vertex (the uncorrected reuse): over the
    // lobes taken so far (`all`) and the part whose light no solution holds yet (`unheld`). They
    // differ right after a reuse vertex left through a non-delta lobe, where the solution holds
    // what its Lambertian layer gathers from non-specular surfaces: only the glossy lobes' share
    // goes on unheld, and the whole comes back if the next vertex is left through a delta lobe
    // (the solution holds no light that arrives through specular surfaces).
    Color all{1.0f};
    Color unheld{1.0f};
    // The correction's parts. `fresh`: made at the last reuse vertex's Lambertian bounce, (1 / q)
    // of the base there; it stands for what the solution held, light arriving from a
    // non-specular surface, so it ends where the next vertex is left through a delta lobe (that
    // light comes back to the base, as above), unless the solution holds the light through
    // specular surfaces too (specularInRadiosity: then it goes on through delta lobes). `traced`:
    // the correction's parts from earlier vertices, traced as the path tracer does (no reuse vertex
    // for them: their weight grows by 1 / q once, not at every reuse vertex, where (rho^2 / q)^k
    // would make the variance diverge for rho^2 > q, the argument of kMinTerminationProbability).
    // `chain`: fresh, followed through delta lobes to count the light found at a specular chain's
    // end, when the solution holds those caustics (causticsInRadiosity) but the base leaves them to
    // the map.
    Color fresh{0.0f};
    Color traced{0.0f};
    Color chain{0.0f};
    // The base's glossy share left at a reuse vertex whose solution holds the caustics
    // (causticsInRadiosity), followed through delta lobes: light found at the chain's end is
    // reflected by those glossy lobes, which no solution holds (the solution reflects it with its
    // Lambertian layer), so the base counts it with this weight.
    Color glossyChain{0.0f};

    void operator*=(const Color& w) {
        all *= w;
        unheld *= w;
        fresh *= w;
        traced *= w;
        chain *= w;
        glossyChain *= w;
    }
    void operator/=(float d) {
        all /= d;
        unheld /= d;
        fresh /= d;
        traced /= d;
        chain /= d;
        glossyChain /= d;
    }
    // The correction's weight for light that every part counts here.
    Color correction() const { return fresh + traced; }
    bool live() const {
        return maxComponent(all) > 0.0f ||
               maxComponent(fresh + traced + chain + glossyChain) > 0.0f;
    }
};

}  // namespace

PathRadiance PathTracer::Li(Ray ray, Sampler& sampler, FirstHit* firstHit,
                            PathCounters& counters) const {
    PathRadiance L;
    if (groups_)
        L.groups.assign(groups_->groups().size(), Color(0.0f));
    const LightSelection* selection = groups_ ? &groups_->selection() : nullptr;
    // The base part takes the solution S at each reuse vertex as its Lambertian layer's light
    // (biased by the solution's error). With settings_.correctionProbability = q > 0 the path
    // also goes on through that layer with probability q and adds (T - S) / q, T being what the
    // path tracer traces for it (its next-event estimation and its bounce): as
    // E[(T - S) / q | goes on] q = E[T] - S, the sum is unbiased whatever the solution (Russian
    // roulette with the solution as the value of the paths it ends, Arvo and Kirk 1990; the
    // control variate's known part, as in Halton's sequential Monte Carlo and Keller's
    // hierarchical Monte Carlo image synthesis). What the correction adds is returned apart too
    // (PathRadiance::corrections), so that the image can reconstruct it on its own.
    PathWeights w;
    const float q = settings_.reuseRadiosity ? settings_.correctionProbability : 0.0f;
    // The solution holds the light arriving through specular surfaces too: the fresh correction
    // goes on through delta lobes, and only the glossy share of the base goes on past a reuse
    // vertex.
    const bool specularHeld =
        settings_.reuseRadiosity && settings_.causticsInRadiosity && settings_.specularInRadiosity;
    // Product of eta^2 over refractions: the throughput carries the 1/eta^2 radiance scaling of
    // each refraction, which this factor undoes for the roulette decision only (pbrt-v4,
    // 14.1.3).
    float etaScale = 1.0f;
    int depth = 0;
    const Vec3 cameraOrigin = ray.o;
    bool lastDelta = true;  // the camera counts as a delta vertex for emission
    float lastBsdfPdf = 0.0f;
    LightSampleContext lastCtx;
    // Vertices left through a non-delta lobe so far, and whether a specular vertex followed the
    // last of them: the path classes of the header's comment.
    int diffuseVertices = 0;
    bool specularAfterDiffuse = false;
    // Whether the last vertex left through a non-delta lobe was a reuse vertex whose caustics
    // (light through specular surfaces) the map or the solution holds (causticsAtReuse): light
    // found at the end of a specular chain after it is theirs, but for the glossy chain's part.
    bool lastDiffuseHeldCaustics = false;
    bool firstVertexSpecular = false;  // the lobe the first vertex was left through was a delta
    float pathLength = 0.0f;           // from the camera to the current vertex, metres

    // Adds radiance `value` reaching the eye as `component`, weighted by the base and
    // correction weights; returns what it added.
    const auto add = [&](PathComponent component, const Color& baseWeight,
                         const Color& correctionWeight, const Color& value) {
        const Color fromCorrection = correctionWeight * value;
        const Color added = baseWeight * value + fromCorrection;
        L[component] += added;
        L.corrections[static_cast<size_t>(component)] += fromCorrection;
        return added;
    };

    // Emission Le reached by the previous BSDF sample (on a surface, or the environment past a
    // ray that left the scene), with its MIS weight against next-event estimation at the
    // previous vertex (Veach 1997, Eq. 9.13). Returns what it added.
    const auto addEmission = [&](const Color& Le, float misWeight) {
        const bool causticPath = diffuseVertices == 1 && specularAfterDiffuse;
        // Light reaching a reuse vertex through specular vertices is held by the caustic map or
        // the solution there; the correction's traced part counts it all the same.
        const bool causticAtReuse =
            specularAfterDiffuse && lastDiffuseHeldCaustics && !specularHeld;
        // The weights that count it: at a chain's end after such a reuse vertex, the base's
        // glossy chain, the correction's traced part and chain.
        const Color baseWeight = causticAtReuse ? w.glossyChain : w.unheld;
        const Color correctionWeight = causticAtReuse ? w.traced + w.chain : w.correction();
        if (maxComponent(Le) > 0.0f && !(causticPath && settings_.excludeCaustics) &&
            maxComponent(baseWeight + correctionWeight) > 0.0f) {
            return add(pathComponent(depth, firstVertexSpecular), baseWeight, correctionWeight,
                       Le * misWeight);
        }
        return Color(0.0f);
    };

    // Next-event estimation at a vertex: `where` is a surface's hit, BSDF and wo, or a scattering
    // event in the medium (MediumPoint). One light sample; with light groups, one light from each
    // group and a direction from each part of the environment, each filed under its group.
    const auto addDirectLight = [&](PathComponent component, const auto&... where) {
        if (!groups_) {
            add(component, w.unheld, w.correction(),
                sampleDirectLight(scene_, where..., sampler, counters));
            return;
        }
        for (size_t set = 0; set < selection->sets(); ++set) {
            uint32_t light = 0;
            const Color direct = sampleDirectLightFromSet(scene_, *selection, set, where...,
                                                          sampler, counters, light);
            if (maxComponent(direct) > 0.0f)
                groups_->file(light, add(component, w.unheld, w.correction(), direct), L.groups);
        }
        for (const EnvironmentPart part : kEnvironmentParts) {
            const int group = groups_->environmentGroup(part);
            if (group >= 0) {
                L.groups[size_t(group)] +=
                    add(component, w.unheld, w.correction(),
                        sampleEnvironmentPart(scene_, part, where..., sampler, counters));
            }
        }
    };

    // Russian roulette after a scattering event, on the throughput without eta scaling: false
    // when it ends the path, else the survivors are reweighted.
    const auto survivesRoulette = [&] {
        const float rr = rouletteTerminationProbability(
            depth, (w.all + w.fresh + w.traced + w.chain) * etaScale);
        if (rr > 0.0f) {
            if (sampler.get1D() < rr)
                return false;
            w /= 1.0f - rr;
        }
        return true;
    };

    // The direct light of the point-like lights that the medium along `segment` scatters, drawn
    // by equiangular sampling: one light, or one from each group, each filed under its group.
    const auto addEquiangular = [&](PathComponent component, const MediumSegment& segment) {
        uint32_t light = 0;
        if (!groups_) {
            add(component, w.unheld, w.correction(),
                sampleEquiangularInScattering(scene_, scene_.lightSampler(), segment, sampler,
                                              counters, light));
            return;
        }
        for (size_t set = 0; set < selection->sets(); ++set) {
            const Color direct = sampleEquiangularInScattering(scene_, selection->set(set), segment,
                                                               sampler, counters, light);
            if (maxComponent(direct) > 0.0f)
                groups_->file(light, add(component, w.unheld, w.correction(), direct), L.groups);
        }
    };

    const Medium* medium = scene_.medium();
    while (true) {
        ++counters.rays;
        const std::optional<SurfaceHit> hit = scene_.intersect(ray);
        // The participating medium along the segment to the hit (or out of the scene), unless
        // the segment runs inside a solid: a free flight, which may end in a scattering event (a
        // V vertex) before the surface. Its weight holds the transmittance and, at an event,
        // sigma_s (core/medium.h). Before it, equiangular sampling's share of the direct light
        // scattered along the segment.
        const bool inMedium = medium && !(hit && insideSolid(scene_, *hit, ray.d));
        const float tMax = hit ? hit->t : INFINITY;
        const std::optional<Medium::Span> span = inMedium ? medium->span(ray, tMax) : std::nullopt;
        const bool scatterHere = settings_.maxDepth < 0 || depth < settings_.maxDepth;
        const std::optional<MediumSegment> segment =
            span && equiangular_
                ? std::optional<MediumSegment>(MediumSegment{ray, span->t0, span->t1, *medium})
                : std::nullopt;
        if (segment && scatterHere)
            addEquiangular(pathComponent(depth + 1, firstVertexSpecular), *segment);
        // The medium's own emission along the segment, in closed form (Medium::emitted).
        if (span && medium->emits()) {
            const Color added = addEmission(medium->emitted(ray, *span), 1.0f);
            if (groups_)
                groups_->fileMediumEmission(added, L.groups);
        }
        if (span) {
            const float uChannel = sampler.get1D();
            const float uDistance = sampler.get1D();
            const Medium::Flight flight = medium->sampleFlight(ray, *span, uChannel, uDistance);
            w *= flight.weight;
            if (flight.scattered) {
                if (!scatterHere)
                    break;
                // The medium's in-scattered light: next-event estimation with the phase
                // function, then a direction drawn from it, whose weight p / pdf is 1.
                const MediumPoint point{ray.o + flight.t * ray.d, medium->phase(), -ray.d,
                                        segment ? &*segment : nullptr, flight.t};
                addDirectLight(pathComponent(depth + 1, firstVertexSpecular), point);
                const Vec3 wi = medium->phase().sample(point.wo, sampler.get2D());
                // A V vertex is diffuse for the path classes, and no reuse vertex: no solution
                // holds a medium's light. Every part goes on through it as it was (the fresh
                // correction stays fresh: light that a specular chain after it brings is the
                // base's, as after a reuse vertex's Lambertian bounce), and no caustic map or
                // solution holds the light that such a chain brings to it.
                ++diffuseVertices;
                specularAfterDiffuse = false;
                lastDiffuseHeldCaustics = false;
                w.chain = w.glossyChain = Color(0.0f);
                lastDelta = false;
                lastBsdfPdf = medium->phase().p(point.wo, wi);
                lastCtx = LightSampleContext{point.p, Vec3(0.0f), Vec3(0.0f)};
                pathLength += flight.t;
                ray = Ray{point.p, wi};
                ++depth;
                if (!survivesRoulette())
                    break;
                continue;
            }
        }
        if (!hit) {
            if (scene_.environment() && groups_) {
                // The map and the sun apart, each weighed against its own light sample.
                for (const EnvironmentPart part : kEnvironmentParts) {
                    const int group = groups_->environmentGroup(part);
                    if (group < 0)
                        continue;
                    L.groups[size_t(group)] +=
                        addEmission(scene_.environment()->radiance(ray.d, part),
                                    lastDelta ? 1.0f
                                              : environmentPartMisWeight(scene_, part, lastCtx.p,
                                                                         ray.d, lastBsdfPdf));
                }
            } else if (scene_.environment()) {
                addEmission(
                    scene_.escaped(ray.d),
                    lastDelta ? 1.0f : escapedMisWeight(scene_, lastCtx.p, ray.d, lastBsdfPdf));
            }
            break;
        }
        w *= volumeAttenuation(scene_, *hit, ray.d);
        pathLength += glm::distance(ray.o, hit->p);
        const Vec3 wo = -ray.d;
        const bool unheld = maxComponent(w.unheld) > 0.0f || maxComponent(w.correction()) > 0.0f;

        const Color Le = scene_.emitted(*hit, wo);
        if (maxComponent(Le) > 0.0f) {
            const Color added = addEmission(
                Le, lastDelta
                        ? 1.0f
                        : emissionMisWeight(scene_, lastCtx, ray.d, *hit, lastBsdfPdf, selection));
            if (groups_)
                groups_->fileEmission(uint32_t(hit->material), added, L.groups);
        }

        const Bsdf bsdf = scene_.bsdf(*hit);

        // Straight-through transparency: depth and the MIS state stay as they were.
        const StraightThrough straight = chooseStraightThrough(scene_, *hit, bsdf, wo, sampler);
        w *= straight.weight;
        if (straight.passes) {
            ray = Scene::spawnRay(*hit, ray.d);
            continue;
        }
        recordFirstHit(scene_, *hit, bsdf, cameraOrigin, firstHit);

        if (settings_.maxDepth >= 0 && depth >= settings_.maxDepth)
            break;

        // A second diffuse vertex under radiosity reuse. The solution reflects what arrives here
        // from the lights and diffuse surfaces with the whole non-delta reflectance, the rough
        // glossy lobes spread as Lambertian: the Lambertian layer's share of it stands for
        // everything that layer would gather (matteShare), and the glossy lobes go on as at any
        // vertex, with next-event estimation and a bounce weighed by fGlossy alone. Every
        // direction of a non-delta bounce here is drawn from the whole BSDF, so f / pdf splits
        // exactly into the Lambertian part, which only delta lobes carry on (light through
        // specular surfaces), and the glossy part, which goes on in full (unheld). The
        // correction's parts see no reuse vertex: they take every lobe.
        const bool reuseHere =
            settings_.reuseRadiosity && diffuseVertices >= 1 && bsdf.hasNonDeltaLobe();
        // The correction's decision: trace the base's Lambertian layer here too, with weight
        // 1 / q, in place of the solution.
        const bool correctHere = reuseHere && maxComponent(w.unheld) > 0.0f && q > 0.0f &&
                                 (q >= 1.0f || sampler.get1D() < q);
        const Color corrected = correctHere ? w.unheld / q : Color(0.0f);
        // Light reflected here reaches the eye over this vertex and the ones before it.
        const PathComponent reflectedHere = pathComponent(depth + 1, firstVertexSpecular);
        if (unheld && reuseHere && radiosity_) {
            const Color S = matteShare(bsdf, wo, *radiosity_) *
                            radiosity_->reflected(*hit, glm::dot(wo, hit->ng) > 0.0f);
            add(reflectedHere, w.unheld, -corrected, S);
        }
        // The map's caustics when the solution took none. (When it took them, the glossy lobes'
        // share is traced through the glossy chain instead: the map's estimate for a glossy
        // lobe, a k-nearest-neighbour query at every reuse vertex, was a fifth of the hybrid's
        // time on the modern hall and its sharpest fireflies, and it left the map's bias.)
        if (unheld && reuseHere && settings_.causticsAtReuse && !settings_.causticsInRadiosity &&
            causticMap_) {
            add(reflectedHere, w.unheld, Color(0.0f),
                causticMap_->radiance(*hit, bsdf, wo, ReflectingLobes::All));
        }
        if (unheld && bsdf.hasNonDeltaLobe()) {
            const bool glossy = (bsdf.lobes() & kLobeGlossy) != 0;
            const bool correctionLive = maxComponent(w.correction() + corrected) > 0.0f;
            if (!reuseHere) {
                addDirectLight(reflectedHere, *hit, bsdf, wo);
            } else if (correctionLive) {
                // One light sample for all parts: the base's glossy share, the traced
                // correction's whole, the new correction's Lambertian share.
                const DirectLightShares direct =
                    sampleDirectLightShares(scene_, *hit, bsdf, wo, sampler, counters);
                add(reflectedHere, w.unheld, w.correction(), direct.glossy);
                add(reflectedHere, Color(0.0f), w.correction() + corrected,
                    direct.all - direct.glossy);
            } else if (glossy) {
                add(reflectedHere, w.unheld, Color(0.0f),
                    sampleDirectLight(scene_, *hit, bsdf, wo, sampler, counters,
                                      ReflectingLobes::Glossy));
            }
        }

        const float uLobe = sampler.get1D();
        const Vec2 uDirection = sampler.get2D();
        const std::optional<BsdfSample> bs = bsdf.sample(wo, uLobe, uDirection);
        if (!bs || !(bs->pdf > 0.0f))
            break;
        const float cosOverPdf = std::abs(glm::dot(bs->wi, bsdf.shadingNormal())) / bs->pdf;
        if (bs->isDelta()) {
            // What the solution held at the reuse vertex before comes back: it holds no light
            // through specular surfaces. The fresh correction ends (see PathWeights). When it
            // does hold that light (specularHeld), the base past a reuse vertex is its glossy
            // share already (w.all = w.unheld there), and the fresh correction goes on.
            const Color weight = bs->f * cosOverPdf;
            w.unheld = w.all *= weight;
            w.traced *= weight;
            w.chain *= weight;
            w.glossyChain *= weight;
            w.fresh = specularHeld ? w.fresh * weight : Color(0.0f);
        } else {
            w.traced = (w.traced + w.fresh) * bs->f * cosOverPdf;
            w.all = w.unheld * bs->f * cosOverPdf;
            if (reuseHere) {
                // Only the unheld part goes on through a non-delta lobe: the solution here holds
                // the rest, but for the correction's traced Lambertian share.
                const Color fGlossy = bsdf.fGlossy(wo, bs->wi);
                w.unheld = w.unheld * fGlossy * cosOverPdf;
                w.fresh = corrected * (bs->f - fGlossy) * cosOverPdf;
                // The solution holds all the rest, through specular surfaces too.
                if (specularHeld)
                    w.all = w.unheld;
            } else {
                w.unheld = w.all;
                w.fresh = Color(0.0f);
            }
            w.chain = settings_.causticsInRadiosity && !specularHeld ? w.fresh : Color(0.0f);
            w.glossyChain = reuseHere && settings_.causticsInRadiosity ? w.unheld : Color(0.0f);
            if (reuseHere && !settings_.specularAtReuse && !(maxComponent(w.unheld) > 0.0f) &&
                !(maxComponent(w.correction()) > 0.0f))
                break;  // the radiosity term above holds this bounce, and no surface is specular
        }
        if (depth == 0)
            firstVertexSpecular = bs->isDelta();
        if (bs->isDelta()) {
            specularAfterDiffuse = diffuseVertices > 0;
        } else {
            if (diffuseVertices == 0 && firstHit && q > 0.0f)
                recordSurfaceGuide(scene_, *hit, bsdf, pathLength, firstHit->firstDiffuse);
            ++diffuseVertices;
            specularAfterDiffuse = false;
            lastDiffuseHeldCaustics = reuseHere && settings_.causticsAtReuse;
        }
        if (!w.live())
            break;
        if (bs->lobe & kLobeTransmission)
            etaScale *= sqr(bs->eta);
        lastDelta = bs->isDelta();
        lastBsdfPdf = bs->pdf;
        lastCtx = LightSampleContext{hit->p, hit->pError, hit->ng};
        ray = Scene::spawnRay(*hit, bs->wi);
        ++depth;
        if (!survivesRoulette())
            break;
    }
    return L;
}

}  // namespace penumbra
