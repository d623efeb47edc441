// Light that reached the meshed surfaces by paths a radiosity solver does not follow itself, given
// as flux deposited at points: the caustic photons (caustics/photon_tracer.h, light paths L S+ D),
// whose power the solver then reflects and carries on like the punctual lights' direct light
// (radiosity_solver.h: D_i), so that its solution also holds L S+ D+ (the first option of issue
// 4's item 6 for indirect caustics; the photon map's own estimate is kept for what is seen).
//
// Binning, not density estimation: an element side's deposited flux is the sum of the powers of
// the deposits inside it, so its mean irradiance, flux / area, is unbiased whatever the element's
// size (the estimator of the illumination-map methods; Arvo 1986, "Backward Ray Tracing";
// Heckbert 1990, "Adaptive Radiosity Textures"). Its noise is that of the photon count in the
// element: a small element lit by few photons is noisy, which the solution's later bounces
// average out. When the solver splits a leaf, the deposits in it follow the point down to the new
// leaves (update()), and every element keeps the sum over its leaves.
#pragma once

#include "core/math.h"
#include "radiosity/radiosity_mesh.h"

#include <cstdint>
#include <vector>

namespace penumbra {

struct FluxDeposit {
    uint32_t mesh = 0, triangle = 0;  // scene triangle (Scene::meshes())
    Vec3 barycentric{0.0f};           // weights of its vertices 0, 1, 2
    // Geometric normal on the side it arrived from (the side whose D it adds to: the front if
    // this points along the element's normal, RadiosityMesh::normal).
    Vec3 normal{0.0f};
    Color power{0.0f};  // lm per linear-sRGB channel
};

class DepositedFlux {
  public:
    // Locates every deposit in the mesh's current leaves; deposits on triangles the mesh does not
    // hold (transmissive ones) are dropped. The mesh must outlive this.
    DepositedFlux(const RadiosityMesh& mesh, const std::vector<FluxDeposit>& deposits);

    // Moves the deposits of leaves split since the last call down to the new leaves, adding their
    // power to the sums of the elements between.
    void update();

    // Flux (lm per channel) deposited on the element's side: the sum over its leaves. Call
    // update() after splits first.
    Color flux(int element, bool front) const;

    size_t count() const { return deposits_.size(); }
    size_t dropped() const { return dropped_; }
    // The flux of the deposits kept (both sides of every patch).
    Color totalPower() const;

  private:
    struct Located {
        FluxDeposit deposit;
        int leaf = -1;
        bool front = true;  // the side it adds to
    };
    size_t slot(int element, bool front) const {
        return 2 * static_cast<size_t>(element) + (front ? 0 : 1);
    }
    void add(int element, const Located& located);

    const RadiosityMesh& mesh_;
    std::vector<Located> deposits_;
    std::vector<Color> flux_;  // per element side, 2 * element + (front ? 0 : 1)
    size_t dropped_ = 0;
};

}  // namespace penumbra
