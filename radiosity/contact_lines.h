// The contact lines of a scene: where one opaque surface meets or passes through another (a
// block standing on a floor, a table leg, a shelf against a wall). The radiance of the surface
// is discontinuous there (Heckbert 1992's D0 discontinuities: the other surface hides half of
// the hemisphere at once), so the radiosity mesh puts element edges on them (triangle_pieces.h)
// rather than elements that straddle them.
#pragma once

#include "radiosity/held_triangles.h"

namespace penumbra {

class Scene;

class ContactLines : public SegmentsByTriangle {
  public:
    // Finds the contact lines on every triangle of a material the radiosity mesh holds
    // (holdsMaterial) whose area is at least minTriangleArea, made by the other such triangles
    // that reach its front side (or either side of a double-sided one) and are not parallel to
    // it, keeping the segments at least minSegmentLength long that do not lie on the triangle's
    // own edges (where it meets its neighbours).
    ContactLines(const Scene& scene, float minTriangleArea, float minSegmentLength);
};

}  // namespace penumbra
