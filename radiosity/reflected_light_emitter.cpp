#include "radiosity/reflected_light_emitter.h"

#include "radiosity/element_sampling.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_solver.h"

namespace penumbra {

ReflectedLightEmitter::ReflectedLightEmitter(const Scene& scene, const RadiosityMesh& mesh,
                                             const RadiositySolver& solver)
    : scene_(scene), mesh_(mesh) {
    std::vector<float> weights;
    for (const int e : mesh.leafElements()) {
        for (const bool front : {true, false}) {
            const Color L = solver.reflectedRadiance(e, front) * solver.exposedFraction(e, front);
            const Color flux = kPi * mesh.area(e) * L;
            const float weight = (flux.r + flux.g + flux.b) / 3.0f;
            if (!(weight > 0.0f))
                continue;
            sides_.push_back(Side{e, front, L});
            weights.push_back(weight);
            power_ += flux;
        }
    }
    if (!weights.empty())
        choice_ = AliasTable(weights);
}

std::optional<ReflectedLightEmitter::Point> ReflectedLightEmitter::sample(float uChoice,
                                                                          Vec2 u) const {
    if (choice_.empty())
        return std::nullopt;
    const uint32_t index = choice_.sample(uChoice);
    const Side& side = sides_[index];
    const ElementSample x = sampleElement(scene_, mesh_, side.element, u);
    return Point{x.p, x.pError, side.front ? x.n : -x.n, side.L,
                 choice_.pmf(index) / mesh_.area(side.element)};
}

}  // namespace penumbra
