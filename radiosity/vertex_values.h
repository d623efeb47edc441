// The per-vertex values a radiosity solution is shown with: for each side of the surfaces, the
// Gouraud interpolation (RadiosityMesh::setElementValues) of a per-element value, kept for both
// sides at once so that a solver can answer queries for either without re-averaging.
#pragma once

#include "core/math.h"
#include "radiosity/radiosity_mesh.h"

#include <array>
#include <functional>
#include <vector>

namespace penumbra {

class SideVertexValues {
  public:
    // Computes the vertex values of value(element, front), called for every element (only the
    // leaves' values are used), for the back and then the front side, so that the mesh is left
    // with the front's values set (setElementValues). With `atCorners`, each leaf adds its values
    // at its three corners (setElementValues' perCorner).
    // With `weight`, each leaf side weighs that in the averages at its corners instead of its
    // area (setElementValues' weights: 0 for a side nobody sees).
    using CornerValues = std::function<std::array<Color, 3>(int element, bool front)>;
    using Weights = std::function<float(int element, bool front)>;
    void compute(RadiosityMesh& mesh, const std::function<Color(int element, bool front)>& value,
                 const CornerValues& atCorners = nullptr, const Weights& weight = nullptr);
    // No compute() yet.
    bool empty() const { return values_[0].empty(); }
    // The interpolated value at a point located on the mesh (RadiosityMesh::locate): the leaf's
    // corner values weighted by the point's barycentrics; zero before compute() or for a point
    // on no element.
    Color interpolate(const RadiosityMesh& mesh, const ElementPoint& point, bool front) const;
    // Bytes held.
    size_t memoryBytes() const { return (values_[0].size() + values_[1].size()) * sizeof(Color); }

  private:
    std::array<std::vector<Color>, 2> values_;  // [front, back], per mesh vertex
};

}  // namespace penumbra
