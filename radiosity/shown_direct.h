// The sources' direct light as a solution shows it: evaluated at the corners of every leaf
// (point_direct.h) and interpolated linearly in between, on a mesh refined until that
// interpolation is right. The element means the solver transports (direct_irradiance.h) average a
// light's pool or ridge away, and Gouraud shading of them misses the peak under a downlight by a
// quarter on a hall-sized floor; values at the corners, exact where nothing casts a shadow, do not.
//
// Refinement (a posteriori, by the interpolation error, as in the adaptive subdivision of Cohen
// and Wallace 1993, "Radiosity and Realistic Image Synthesis", chapter 8, with the error measured
// at points rather than estimated from neighbours): a leaf is split when, at its edge midpoints
// or its centroid, the exact D differs from the linear interpolation of its corners by more than
// kTolerance of the larger of the two (kEnvironmentTolerance for the environment's part, tested
// apart) (or of kFloor times the brightest corner of the scene, so
// that darkness does not refine on the last digits), and its longest edge is longer than
// kMinEdgePerDistance times its distance to the nearest source (a floor half a metre under a
// downlight gets elements of a few centimetres there; a distant wall keeps its elements), and its
// children would be at least kMinElementArea: the settings' smallest element area sizes the solve
// by the scene, not by the light, and does not bound this. The refinement gives up, and says so
// (budgetReached()), at maxLeaves leaves: of a round that would pass it, the leaves whose error
// is the largest part of their tolerance are split first.
//
// Energy: a leaf is also split when the mean of its corners' punctual light differs by more than
// the tolerance from the element's own mean (DirectIrradiance's, exact in energy: it weighs its
// samples by the solid angle the element subtends at the light), which catches a spike between
// the test points (a light a metre over elements ten metres wide). A leaf that the rules above
// leave wrong but may not split (too small, too near a source, over budget) has its corners'
// punctual light scaled to that mean (shifted where they have none), so that it shows its
// element's energy if not its shape.
//
// Corners are per leaf, not per mesh vertex: each is evaluated a thousandth of the leaf's size
// inside it, so that a leaf beside a discontinuity of the light (the foot of an emitter standing
// on the floor, a shadow's edge where an edge of the mesh runs) takes the limit from its own side.
// A corner where the side is covered (under a block standing on the floor: it sees nothing and
// is seen by nothing, element_exposure.h) takes the mean of the leaf's exposed corners, or with
// none the element's own exposed mean, so that the floor around the block is not darkened
// towards its foot; covered test points are not tested.
// Where two leaves meet at a T-vertex the finer one's exact value and the coarser one's
// interpolation there differ by at most the tolerance: the coarser leaf was tested at that point.
#pragma once

#include "core/math.h"
#include "radiosity/leaf_corner_values.h"
#include "radiosity/point_direct.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/solve_progress.h"

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace penumbra {

class Scene;

class ShownDirect {
  public:
    static constexpr float kTolerance = 0.01f;
    // The environment's light is tested apart, against what its estimate at a point resolves:
    // PointDirect::kEnvironmentDirections fixed directions of each strategy see the sky through a
    // roof light in steps (8 % high below its centre, with 64), whose size goes with the whole
    // sky's light, not with the point's. So its error is measured against the larger of its value
    // and kEnvironmentFloor times the brightest corner's environment light: with kTolerance and
    // kFloor the refinement split on the steps of the dim corners of a room lit through a roof
    // light, to the budget (65 535 leaves), and left the floor below it 3 % dark; with these, 2 949
    // leaves and within 1 % (tests/cli/environment_render_test.cpp).
    static constexpr float kEnvironmentTolerance = 0.05f;
    static constexpr float kEnvironmentFloor = 0.25f;
    static constexpr float kFloor = 1e-3f;
    static constexpr float kMinEdgePerDistance = 1.0f / 32.0f;
    // The smallest element it makes, m² (a square millimetre): the size a leaf at a contact line,
    // where the nearest source is at no distance, stops at. Not relative to the patch: a point
    // light a metre over a floor modelled as one 10 km square needs elements of centimetres there.
    static constexpr float kMinElementArea = 1e-6f;

    // Both must outlive it; the mesh is refined by refine(). `exposed`: whether an element side
    // shows any light (a covered side, under a block or inside a wall, is neither evaluated nor
    // tested, and a hidden emitting side does not emit).
    using SideExposed = std::function<bool(int element, bool front)>;
    ShownDirect(const Scene& scene, RadiosityMesh& mesh, const SideExposed& exposed);

    // What refine() needs of the solver: `split` splits one leaf as the solver does (so that its
    // parts indexed by node make room) and returns its first child; `settle`, called after each
    // round of splits, gives the children their own exposure and element means; `punctualMean`
    // is an element side's mean D of the punctual lights, `exposedMean` the element's mean D of
    // every source over its exposed part; `covered` whether the side is covered at a point of
    // the element (adding its probe rays).
    struct Solver {
        std::function<int(int leaf, float minChildArea)> split;
        std::function<void()> settle;
        std::function<Color(int element, bool front)> punctualMean, exposedMean;
        // Makes, once the mesh is refined (it reads the mesh as it is then), the D that a side
        // showing no light of its own (covered, or hidden under a coincident face) is shown
        // with: the exposed mean of what it shows (ElementExposure::shownValues).
        std::function<std::function<Color(int element, bool front)>()> shownMeans;
        std::function<bool(int element, const ElementSample& x, bool front, uint64_t& rays)>
            covered;
        // If given, asked before each round of splits: once it says yes (a time limit has run
        // out), the leaves still to split stay as they are, as at the budget.
        std::function<bool()> stop;
    };
    // Evaluates the corners of every leaf, then splits leaves as the rules above say until none
    // is left to split, the mesh holds maxLeaves leaves or the solver's stop says so. A child's
    // corners are its parent's corners and the points its parent was tested at, so that only its
    // own test points are new. With `progress`, a stage per round of splits.
    void refine(const Solver& solver, size_t maxLeaves, SolveProgress* progress = nullptr);

    // Gives the children of a leaf split after refine() (the refinement at creases,
    // crease_refinement.h) the leaf's interpolation at their corners: they show what it showed.
    void inheritSplit(int parent, int firstChild) { corners_.inheritSplit(parent, firstChild); }

    // D at a point of a leaf (its corners' values weighted by the point's barycentrics), on one
    // side, cd/m²; zero on no element or before refine().
    Color D(const ElementPoint& point, bool front) const;
    // A leaf side's D at its three corners, in the order of RadiosityMesh::vertices().
    std::array<Color, 3> cornerD(int element, bool front) const;

    bool budgetReached() const { return budgetReached_; }
    size_t leavesSplit() const { return leavesSplit_; }
    // Whether the solver's stop ended the splits with leaves still to split.
    bool stopped() const { return stopped_; }
    uint64_t rays() const { return rays_; }
    size_t memoryBytes() const { return corners_.memoryBytes(); }

  private:
    // D at a point, and whether the side is covered there.
    struct Sample {
        PointDirect::Parts D;
        bool covered = false;
    };
    using CornerParts = std::array<Sample, 6>;
    // Per leaf while it is refined: D at its test points (its edge midpoints m01, m12, m20 and its
    // centroid), [front ..., back ...].
    using TestPoints = std::array<Sample, 8>;
    Sample sample(int element, const ElementSample& x, bool front, uint64_t& rays) const;
    // A leaf side's corners, covered ones replaced as above.
    std::array<PointDirect::Parts, 3> shownCorners(int leaf, size_t side) const;

    void evaluateCorners(const std::vector<int>& leaves, SolveProgress* progress);
    void inheritCorners(int parent, int firstChild);
    // Those of `leaves` that the rules above split, the most wrong first; those wrong but not
    // split go to unresolved_.
    std::vector<int> toSplit(const std::vector<int>& leaves, SolveProgress* progress);
    // The leaf's largest error over its tolerance (wrong above 1).
    float wrongness(int leaf, uint64_t& rays);
    bool maySplit(int leaf) const;
    // The element side's punctual mean less its corners' (what a shift of its corners would
    // take to show its energy).
    Color energyShift(int leaf, size_t side) const;
    // Sets the corners of a leaf side that the rules leave wrong so that they show its element's
    // punctual energy.
    void keepEnergy(int leaf, size_t side);

    const Scene& scene_;
    RadiosityMesh& mesh_;
    SideExposed exposed_;
    PointDirect sources_;
    const Solver* solver_ = nullptr;  // during refine()
    std::vector<CornerParts> parts_;  // per element, during refine()
    std::vector<TestPoints> tests_;   // per element, during refine()
    LeafCornerValues corners_;        // the leaves' are set
    std::vector<int> unresolved_;
    float floor_ = 0.0f;
    float environmentFloor_ = 0.0f;
    bool budgetReached_ = false;
    size_t leavesSplit_ = 0;
    bool stopped_ = false;
    uint64_t rays_ = 0;
};

}  // namespace penumbra
