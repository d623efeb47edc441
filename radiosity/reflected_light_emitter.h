// The light a solved radiosity mesh reflects, as an emitter: points on its leaf element sides
// drawn in proportion to the flux each side sends out, for photons that carry that light on
// through mirrors and glass (the solver's extended transfer, RadiositySolver::
// transferThroughSpecular; the photons are shot by caustics/photon_tracer.h, which this library
// does not use: the radiosity pass joins the two).
//
// A side's flux is pi L A f: L its reflected radiance (emission left out: the lights' own paths
// through specular surfaces are the caustic photons'), A its area and f its exposed fraction
// (element_exposure.h). Its points are drawn uniformly over the whole element with radiance L f,
// which sends the same flux: the element's covered part is small, and the photons from it meet
// the covering surface at once.
#pragma once

#include "core/math.h"
#include "core/sampling.h"

#include <optional>
#include <vector>

namespace penumbra {

class RadiosityMesh;
class RadiositySolver;
class Scene;

class ReflectedLightEmitter {
  public:
    // The solver's current solution; all three must outlive this.
    ReflectedLightEmitter(const Scene& scene, const RadiosityMesh& mesh,
                          const RadiositySolver& solver);

    struct Point {
        Vec3 p, pError;
        Vec3 n;     // unit normal of the emitting side
        Color L;    // radiance into the side's hemisphere, cd/m²
        float pdf;  // per m², the side's choice included
    };
    // A point drawn with density pdf, or nothing when no side reflects any light.
    std::optional<Point> sample(float uChoice, Vec2 u) const;
    // The total flux of the sides, lm per channel.
    const Color& power() const { return power_; }

  private:
    struct Side {
        int element;
        bool front;
        Color L;  // the reflected radiance times the exposed fraction
    };
    const Scene& scene_;
    const RadiosityMesh& mesh_;
    std::vector<Side> sides_;
    AliasTable choice_;  // in proportion to each side's flux (its channels' mean)
    Color power_{0.0f};
};

}  // namespace penumbra
