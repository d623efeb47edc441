// The products of the view-independent passes as the image-forming tracers reuse them
// (raytrace/reused_light.h): the radiosity solution and the caustic photon map behind the
// tracers' interfaces. Each adapter refers to its product, which must outlive it.
#pragma once

#include "caustics/caustic_map.h"
#include "radiosity/radiosity_solution.h"
#include "raytrace/reused_light.h"

namespace penumbra {

class SolutionForTracers final : public ReusedSolution {
  public:
    explicit SolutionForTracers(const RadiositySolution& solution) : solution_(solution) {}
    Color reflected(const SurfaceHit& hit, bool front) const override {
        return solution_.radiance(hit.mesh, hit.triangle, hit.barycentric, false, front);
    }
    Color indirect(const SurfaceHit& hit, bool front) const override {
        return solution_.indirectRadiance(hit.mesh, hit.triangle, hit.barycentric, front);
    }
    bool spreadsSharpGlossy() const override { return solution_.spreadsSharpGlossy(); }

  private:
    const RadiositySolution& solution_;
};

class CausticsForTracers final : public ReusedCaustics {
  public:
    explicit CausticsForTracers(const CausticMap& map) : map_(map) {}
    Color radiance(const SurfaceHit& hit, const Bsdf& bsdf, const Vec3& wo,
                   ReflectingLobes lobes) const override {
        return map_.radiance(hit, bsdf, wo, lobes);
    }

  private:
    const CausticMap& map_;
};

}  // namespace penumbra
