#include "radiosity/vertex_values.h"

namespace penumbra {

void SideVertexValues::compute(RadiosityMesh& mesh,
                               const std::function<Color(int element, bool front)>& value,
                               const CornerValues& atCorners, const Weights& weight) {
    std::vector<Color> perElement(mesh.elementCount());
    std::vector<std::array<Color, 3>> perCorner(atCorners ? mesh.elementCount() : 0);
    std::vector<float> weights(weight ? mesh.elementCount() : 0);
    // The back first, so that the mesh is left with the front's values.
    for (const bool front : {false, true}) {
        for (size_t e = 0; e < perElement.size(); ++e)
            perElement[e] = value(static_cast<int>(e), front);
        for (size_t e = 0; e < perCorner.size(); ++e)
            perCorner[e] = atCorners(static_cast<int>(e), front);
        for (size_t e = 0; e < weights.size(); ++e)
            weights[e] = weight(static_cast<int>(e), front);
        mesh.setElementValues(perElement, perCorner, weights);
        std::vector<Color>& out = values_[front ? 0 : 1];
        out.resize(mesh.vertexCount());
        for (size_t v = 0; v < out.size(); ++v)
            out[v] = mesh.vertexValue(static_cast<uint32_t>(v));
    }
}

Color SideVertexValues::interpolate(const RadiosityMesh& mesh, const ElementPoint& point,
                                    bool front) const {
    if (point.element < 0 || empty())
        return Color(0.0f);
    const auto& v = mesh.vertices(point.element);
    const std::vector<Color>& values = values_[front ? 0 : 1];
    return point.weights.x * values[v[0]] + point.weights.y * values[v[1]] +
           point.weights.z * values[v[2]];
}

}  // namespace penumbra
