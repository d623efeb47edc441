// Leaves refined where surfaces meet or nearly meet (a floor along a wall, a block's foot, a leg
// by a wall), so that the indirect light shown at the leaves' corners (indirect_at_corners.h)
// holds the dip it has there. At a crease the indirect light changes within a centimetre: a point
// there sees the other surface at grazing angles near its own dim foot, and less of the room (the
// path tracer's indirect light at the Cornell box's short block's foot is half what it is a few
// centimetres out). A corner gathered at the crease sees that, but its value holds only as far as
// its rays' harmonic mean length, micrometres there, and a leaf of the solve's size shows its
// element mean, bright, up to the crease: the Cornell box's creases 8-17 % too bright in the
// distribution pipeline.
//
// So, as the validity radius of a sample decides where irradiance caching needs denser samples
// (Ward, Rubinstein and Clear 1988), a leaf side whose corner's rays (kProbeRays of them, cast as
// the corner gather casts its own, corner_rays.h) have a harmonic mean length under
// kReachPerSize times the leaf's size is split, the leaves of one round's splits probed in the
// next, down to leaves of kCreaseSize. The refinement stops at maxLeaves leaves, and says so; in
// a round that would pass it, the leaves whose reach is the smallest part of their size are split
// first. Only the sides that are shown are probed: those that reflect, have an exposed part (a
// side wholly under a block shows nothing) and are meant to be seen (the front, and the back of a
// double-sided material only: glTF's doubleSided false says the back is not). Without the last,
// the Cornell box's blocks, whose open bottoms stand on the floor, were refined along the
// creases inside them, and their outer faces with them.
// The new leaves keep their parent's radiance and what the direct light's corners showed on it
// (ShownDirect::inheritSplit): the solve does not resolve them, the corner gather shows them.
//
// Size of a leaf: the legs of a right isosceles triangle of its area, sqrt(2 A) (the patches of
// an axis-aligned quad's two triangles are such triangles).
#pragma once

#include "radiosity/radiosity_mesh.h"
#include "radiosity/solve_progress.h"

#include <cstddef>
#include <cstdint>
#include <functional>

namespace penumbra {

class Scene;

// m. The smallest leaf the refinement makes (it splits a leaf only into children this large),
// and the least reach of a gathered corner (indirect_at_corners.h). Absolute, not relative to the
// scene: the dip's width is set by the surfaces at the crease, not by the room. On the modern hall
// (docs/radiosity.md, "Refinement at creases") 1 cm took the distribution preview's relMSE from
// 0.0070 to 0.0064 (0.0059 to 0.0053 with contact lines), 2 cm gained half as much, and leaves
// of 13 cm (a quarter of the scene-relative smallest element's side) lost: 0.0075.
inline constexpr float kCreaseSize = 0.01f;

struct CreaseRefinement {
    static constexpr uint32_t kProbeRays = 32;
    static constexpr float kReachPerSize = 0.25f;

    // What it needs of the solver: whether an element side is shown (see above), how
    // to split a leaf as the solver does (its per-node parts making room, the children
    // inheriting) and to settle the children of a round (their exposure), and whether to stop
    // before the next round (a deadline), if given.
    struct Solver {
        std::function<bool(int element, bool front)> shown;
        std::function<int(int leaf, float minChildArea)> split;
        std::function<void()> settle;
        std::function<bool()> stop;
    };

    size_t leavesSplit = 0;
    bool budgetReached = false;
    uint64_t rays = 0;

    // Refines `mesh` (through solver.split) as above; a stage per round on `progress`, if any.
    static CreaseRefinement run(const Scene& scene, const RadiosityMesh& mesh, const Solver& solver,
                                size_t maxLeaves, SolveProgress* progress = nullptr);
};

}  // namespace penumbra
