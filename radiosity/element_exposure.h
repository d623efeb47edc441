// The exposed part of every element side of the hierarchical solver (radiosity_solver.h,
// "Covered parts"): where a surface touches another, or two faces lie on each other in one plane
// (coincident_faces.h), or a side faces a closed solid's interior (sealed_interiors.h), part of
// the side sees nothing and is seen by nothing. Its fraction of the side's area (coverSamples,
// element_sampling.h) makes the side's radiance the mean over its exposed part, and the points of
// a partly covered element, with where they are covered, are kept for the shadow rays of its
// links.
#pragma once

#include "core/math.h"
#include "radiosity/coincident_faces.h"
#include "radiosity/element_sampling.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/sealed_interiors.h"

#include <array>
#include <cstdint>
#include <functional>
#include <unordered_map>
#include <utility>
#include <vector>

namespace penumbra {

class Scene;
class SolveProgress;

// Indexed by the solver's nodes (solver_nodes.h); a cluster is always exposed.
class ElementExposure {
  public:
    // The seed of the element points it samples, which the direct light of the punctual lights
    // samples too (punctualDirect, element_sampling.h), so that the covered points are the same.
    static constexpr uint32_t kPointSeed = 0x85ebca6bu;

    // Both must outlive it; the mesh may be refined meanwhile (resize()).
    ElementExposure(const Scene& scene, const RadiosityMesh& mesh);

    // Makes room for the mesh's new elements, wholly exposed until compute() says otherwise.
    void resize();
    // Exposed fractions of both sides of `elements`, then of their ancestors. Returns the rays it
    // cast. Advances `progress`, if given, by the elements done. `stop`, when given, is asked
    // between chunks of elements with the number done: once it says yes, the rest is not
    // computed and *stopped is set: the fractions are incomplete, for a solve that is abandoned.
    uint64_t compute(const std::vector<int>& elements, SolveProgress* progress = nullptr,
                     const std::function<bool(size_t done)>& stop = nullptr,
                     bool* stopped = nullptr);

    // The fraction of the element side's area that is not covered (coverSamples,
    // element_sampling.h): a leaf's L, H and D are the means over that part, the only one that
    // sends or receives light; a parent's is the mean of its children's.
    float fraction(int node) const { return fractions_[static_cast<size_t>(node)]; }
    // Whether the node is a cluster or an element side not wholly covered.
    bool exposed(int node) const;
    // Whether the node is an element side with an exposed fraction strictly between 0 and 1.
    bool partlyCovered(int node) const;
    // The cover samples of a partly covered node's element, nullptr for any other node.
    const CoverSamples* coverSamplesOf(int node) const;
    // Whether the point x of the element is covered on the side of normal n: hidden by a
    // coincident patch (coincident_faces.h) or covered by a surface within the gap (isCovered,
    // element_sampling.h). Adds the rays it casts to `rays`.
    bool covered(int element, const ElementSample& x, const Vec3& n, uint64_t& rays) const;
    // The mean over the exposed part of element side n of one value per child (values[c] of
    // child c), weighted by the children's exposed fractions; their plain mean if none is exposed.
    Color exposedMean(int n, const std::array<Color, 4>& values) const;
    // The leaf side whose light a leaf side shows: itself, or where it is wholly hidden by a
    // coincident patch, the replacing patch's leaf side under its centroid (shownLeafSide,
    // coincident_faces.h; for shownValues and the solution's radiance()).
    std::pair<int, bool> shownSide(int element, bool front) const;
    // The per-element value function for SideVertexValues::compute that shows `value` at the
    // exposed leaf sides and the exposed mean of an ancestor's leaves at covered ones. It holds
    // the values of the mesh as it is now: make it anew after the mesh is refined.
    std::function<Color(int, bool)> shownValues(const std::function<Color(int, bool)>& value) const;

    const SealedInteriors& sealed() const { return sealed_; }
    const CoincidentFaces& coincident() const { return coincident_; }
    // The fractions' memory, for the solver's estimate.
    size_t memoryBytes() const { return fractions_.size() * sizeof(float); }

  private:
    // The gap (m) under which a surface covers the element (isCovered, element_sampling.h).
    float coveringGap(int element) const;

    const Scene& scene_;
    const RadiosityMesh& mesh_;
    SealedInteriors sealed_;
    CoincidentFaces coincident_;
    std::vector<float> fractions_;  // per node
    // The points of every element with a partly covered side, with where they are covered, so
    // that the shadow rays of its links need not probe for covers at their own points.
    std::unordered_map<int, CoverSamples> coverSamples_;
};

}  // namespace penumbra
