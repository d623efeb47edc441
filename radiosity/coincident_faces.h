// Patches that lie on top of other patches: coplanar scene triangles whose areas overlap, such as
// a wallpaper modelled exactly on its wall, a panel exported twice, or a wall modelled as two
// back-to-back faces. The path tracer shows one of two coincident surfaces at each point
// (whichever the ray tracer returns); the radiosity mesh holds both, and without care both
// receive and both send the same light. A surface seen twice over a whole room makes the sum of
// rho times the form factors pass 1 and the gather diverge (the modern hall's wallpaper lies on
// 37 m² of its wall; docs/benchmarks.md). The shadow rays cannot tell: a ray towards a point of
// one copy stops where the other copy is, and the probes of isCovered (element_sampling.h) start
// above the surface by the ray offset, beyond a copy in the same plane.
//
// Of two coincident patches one wins: the emitting one if one emits and the other does not (a
// light panel must not vanish into the ceiling it lies on), else the one with the smaller id
// (the earlier scene mesh). Where it overlaps the winner, the loser is hidden on both sides: the
// solver treats such points as covered (neither sending nor receiving), and the winner's two
// sides stand for the surface, with the winner's reflectance.
//
// Coincident: the normals are parallel or opposite (within about 0.25 degrees) and every corner
// of each lies within a small tolerance of the other's plane (relative to the coordinates'
// magnitude, as the ray offset is); the point tests of hidden() take their own tolerance.
#pragma once

#include "core/math.h"

#include <array>
#include <cstddef>
#include <vector>

namespace penumbra {

class RadiosityMesh;

class CoincidentFaces {
  public:
    // Finds the coincident pairs among the mesh's patches (sweep and prune over their bounding
    // boxes along x, then the exact tests), O(n log n + candidate pairs).
    explicit CoincidentFaces(const RadiosityMesh& mesh);

    // Whether the point p of patch `patch` lies on a patch that wins over it: within `tolerance`
    // metres of that patch's plane and inside it.
    bool hidden(int patch, const Vec3& p, float tolerance) const {
        return winnerAt(patch, p, tolerance) >= 0;
    }
    // The patch that wins over patch `patch` at its point p (within `tolerance` metres of its
    // plane, p inside it), or -1.
    int winnerAt(int patch, const Vec3& p, float tolerance) const;
    // The same with the tolerance of the pairs themselves (see above), for points that carry no
    // error bound of their own (an element's centroid).
    int winnerOver(int patch, const Vec3& p) const;
    // Patches that lose to some other patch somewhere, and the sum of their areas (m²), for the
    // log.
    size_t losingPatches() const { return losingPatches_; }
    double losingArea() const { return losingArea_; }

  private:
    struct Winner {
        int patch;
        std::array<Vec3, 3> corners;
        Vec3 normal;
    };
    // Per patch, the patches that win over it; empty for most.
    std::vector<std::vector<Winner>> winners_;
    size_t losingPatches_ = 0;
    double losingArea_ = 0.0;
};

}  // namespace penumbra
