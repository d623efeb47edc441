// Values at the three corners of every leaf element, on each side, interpolated linearly inside
// the leaf by a point's barycentric weights: how a solution shows a light evaluated at points
// (shown_direct.h, indirect_at_corners.h) rather than as element means. Per leaf, not per mesh
// vertex, so that two leaves meeting at a vertex may show different values there (the two sides
// of a discontinuity).
#pragma once

#include "core/math.h"
#include "radiosity/radiosity_mesh.h"

#include <array>
#include <functional>
#include <vector>

namespace penumbra {

class LeafCornerValues {
  public:
    // Zero at every corner of `elements` elements.
    void assign(size_t elements) { values_.assign(elements, {}); }
    // Gives the children of a leaf split after the values were set (firstChild to firstChild + 3,
    // RadiosityMesh's numbering) the leaf's interpolation at their corners, so that they show
    // what it showed.
    void inheritSplit(int parent, int firstChild);
    // Corner k (in the order of RadiosityMesh::vertices()) of the element's side.
    Color& at(int element, bool front, size_t k) {
        return values_[static_cast<size_t>(element)][(front ? 0 : 3) + k];
    }
    // The corners weighted by the point's barycentrics; zero on no element or before assign().
    Color interpolate(const ElementPoint& point, bool front) const {
        if (point.element < 0 || static_cast<size_t>(point.element) >= values_.size())
            return Color(0.0f);
        const std::array<Color, 3> c = corners(point.element, front);
        return point.weights.x * c[0] + point.weights.y * c[1] + point.weights.z * c[2];
    }
    std::array<Color, 3> corners(int element, bool front) const {
        if (element < 0 || static_cast<size_t>(element) >= values_.size())
            return {Color(0.0f), Color(0.0f), Color(0.0f)};
        const std::array<Color, 6>& v = values_[static_cast<size_t>(element)];
        const size_t o = front ? 0 : 3;
        return {v[o], v[o + 1], v[o + 2]};
    }
    size_t memoryBytes() const { return values_.capacity() * sizeof(std::array<Color, 6>); }

    // Where a leaf's corner lies on the edge of a coarser leaf of the same plane (a T-vertex),
    // sets it on both sides to the coarser leaf's interpolation along that edge, coarse leaves
    // first, so that the field is continuous across the edge (Baum, Mann, Smith and Winget 1991's
    // anchoring, as RadiosityMesh::setElementValues does for the vertex values): no crack in the
    // view, and the bake's fan of the coarse leaf shows the same values. A coarse leaf's side
    // that `shows` says nobody sees (covered: a piece of floor under a block, cut off along the
    // block's foot by the contact lines) anchors nothing on that side: its values are stand-ins.
    // Nor does an edge on a cut's line (RadiosityMesh::edgeOnCut): the light may step there, and
    // each side keeps its own values.
    using SideShows = std::function<bool(int leaf, bool front)>;
    void anchorTVertices(const RadiosityMesh& mesh, const SideShows& shows);

  private:
    std::vector<std::array<Color, 6>> values_;  // per element: [front c0, c1, c2, back c0, c1, c2]
};

}  // namespace penumbra
