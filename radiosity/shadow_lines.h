// The shadow boundaries of a scene's point-like sources on its surfaces: where an opaque edge,
// seen from a point light, a luminaire or the sun, hides the source from the surface behind it.
// The direct light of the surface steps there (Heckbert 1992's D1 discontinuities, the
// umbra/penumbra boundaries; for a point source the two are one line), so the radiosity mesh
// puts element edges on them (triangle_pieces.h), as it does on the contact lines
// (contact_lines.h), instead of elements that straddle them.
//
// A boundary lies in the wedge that a silhouette edge of the occluders (an edge whose two faces
// face the source differently, or an edge with one face) sweeps away from the source
// (Lischinski, Tampieri and Greenberg 1992, "Discontinuity Meshing for Accurate Radiosity",
// section 3: the EV wedges of a point source); where the wedge crosses a receiving triangle
// that faces the source, and the edge is seen from there with the source behind it unblocked,
// the crossing is a boundary.
#pragma once

#include "core/math.h"
#include "radiosity/held_triangles.h"

#include <vector>

namespace penumbra {

class Scene;

// A point-like source of shadows: a position, or a direction for a source at infinity.
struct ShadowSource {
    Vec3 position{0.0f};
    Vec3 direction{0.0f};  // unit, the way its light travels; zero for a source at a position
    bool atInfinity() const { return glm::dot(direction, direction) > 0.0f; }
};

// The scene's point-like sources: its point and spot lights and luminaires (positions), its
// directional lights and the sun's disc (directions; the sun's 0.53 degrees make a penumbra a
// few millimetres wide a metre from the edge, taken as one line).
std::vector<ShadowSource> shadowSources(const Scene& scene);

class ShadowLines : public SegmentsByTriangle {
  public:
    // Finds the boundaries of the shadows that the triangles the radiosity mesh holds cast from
    // `sources` on every such triangle of at least minTriangleArea that faces a source (or on
    // either side, double-sided), keeping the segments at least minSegmentLength long that do
    // not lie on the triangle's own edges, at most a few hundred, the longest, per triangle.
    ShadowLines(const Scene& scene, const std::vector<ShadowSource>& sources, float minTriangleArea,
                float minSegmentLength);

    size_t wedges() const { return wedges_; }  // the silhouette edges' wedges, over all sources

  private:
    size_t wedges_ = 0;
};

}  // namespace penumbra
