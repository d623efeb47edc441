// Patches that lie on top of other patches: coplanar scene triangles whose areas overlap, such as
// a wallpaper modelled exactly on its wall, a panel exported twice, or a two-sided panel modelled
// as two back-to-back faces. The path tracer shows one of two coincident surfaces at each point
// (whichever the ray tracer returns); the radiosity mesh holds both, and without care both
// receive and both send the same light. A surface seen twice over a whole room makes the sum of
// rho times the form factors pass 1 and the gather diverge (the modern hall's wallpaper lies on
// 37 m² of its wall; docs/radiosity.md, "What the mesh leaves out"). The shadow rays cannot tell: a
// ray towards a point of one copy stops where the other copy is, and the probes of isCovered
// (element_sampling.h) start above the surface by the ray offset, beyond a copy in the same plane.
//
// So each side of the surface is given to one face, and the other face's side there is hidden:
//  - two faces facing the same way: one wins both sides, the emitting one if one emits and the
//    other does not (a light panel must not vanish into the ceiling it lies on), else the one
//    with the smaller id (the earlier scene mesh);
//  - two faces facing opposite ways (back to back): each keeps its front, and its back, which
//    lies on the other's front, is hidden (a two-sided lamp made of two one-sided emitters
//    emits both ways, as in the path tracer).
// The solvers treat a hidden side's points as covered (neither sending nor receiving), and show
// the light of the side that replaces it (shownLeafSide below).
//
// Coincident: the normals are parallel or opposite (within about 0.25 degrees) and every corner
// of each lies within a small tolerance of the other's plane (relative to the coordinates'
// magnitude, as the ray offset is); the point tests take their own tolerance.
#pragma once

#include "core/math.h"

#include <array>
#include <cstddef>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

namespace penumbra {

class RadiosityMesh;
class Scene;

class CoincidentFaces {
  public:
    // The side of a patch: front = the side its counter-clockwise winding faces.
    struct Side {
        int patch;
        bool front;
    };

    // Finds the coincident pairs among the mesh's patches (the pairs whose bounding boxes
    // overlap, overlappingPairs in box_grid.h, then the exact tests), O(n log n + candidate
    // pairs).
    explicit CoincidentFaces(const RadiosityMesh& mesh);

    // The side that replaces side `front` of patch `patch` at its point p: p lies within
    // `tolerance` metres of that side's patch's plane and inside it. Nothing where the side is
    // not hidden.
    std::optional<Side> replacement(int patch, bool front, const Vec3& p, float tolerance) const;
    bool hidden(int patch, bool front, const Vec3& p, float tolerance) const {
        return replacement(patch, front, p, tolerance).has_value();
    }
    // The same with the tolerance of the pairs themselves (see above), for points that carry no
    // error bound of their own (an element's centroid, a probe's hit).
    std::optional<Side> replacementAt(int patch, bool front, const Vec3& p) const;
    // Patches with a side hidden somewhere, and the sum of their areas (m²), for the log.
    size_t hiddenPatches() const { return hiddenPatches_; }
    double hiddenArea() const { return hiddenArea_; }

  private:
    // What hides a side of a patch where the two overlap.
    struct Cover {
        int patch;                    // the patch whose side replaces it
        bool front, back;             // which of the covered patch's sides it hides
        bool sameFacing;              // side s is replaced by the coverer's side s, else !s
        std::array<Vec3, 3> corners;  // the coverer's
        Vec3 normal;                  // the coverer's
    };
    // Per patch, what covers its sides; empty for most.
    std::vector<std::vector<Cover>> covers_;
    size_t hiddenPatches_ = 0;
    double hiddenArea_ = 0.0;
};

// The leaf side whose light the leaf side (element, front) shows: itself where `exposed` says so;
// else, where a coincident patch hides it at its centroid (replacementAt), the replacing patch's
// leaf under that centroid (by the centroid's barycentric coordinates in that patch's scene
// triangle, RadiosityMesh::locate) on the replacing side, and so on along a chain of stacked
// copies, at most four hops (three copies of a face take two). The walk stops at a side that is
// not hidden at its centroid, or where the replacing patch has no leaf.
std::pair<int, bool> shownLeafSide(const Scene& scene, const RadiosityMesh& mesh,
                                   const CoincidentFaces& coincident, int element, bool front,
                                   const std::function<bool(int element, bool front)>& exposed);

// The leaf side that a ray meeting side `front` of the leaf `element` at its point p sees: itself,
// or where a coincident patch hides it at p, the replacing patch's leaf under p on the replacing
// side (and so on, as shownLeafSide). For rays that read the solution where they land (the final
// gather): a partly hidden leaf side's own value is its exposed part's.
std::pair<int, bool> leafSideSeenAt(const Scene& scene, const RadiosityMesh& mesh,
                                    const CoincidentFaces& coincident, int element, bool front,
                                    const Vec3& p);

}  // namespace penumbra
