// The contact lines of a scene: where one opaque surface meets or passes through another (a
// block standing on a floor, a table leg, a shelf against a wall). The radiance of the surface
// is discontinuous there (Heckbert 1992's D0 discontinuities: the other surface hides half of
// the hemisphere at once), so the radiosity mesh puts element edges on them (triangle_pieces.h)
// rather than elements that straddle them.
#pragma once

#include "radiosity/triangle_pieces.h"

#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

namespace penumbra {

class Scene;

class ContactLines {
  public:
    // Finds the contact lines on every triangle of a material the radiosity mesh holds
    // (holdsMaterial) whose area is at least minTriangleArea, made by the other such triangles
    // that reach its front side (or either side of a double-sided one) and are not parallel to
    // it, keeping the segments at least minSegmentLength long that do not lie on the triangle's
    // own edges (where it meets its neighbours).
    ContactLines(const Scene& scene, float minTriangleArea, float minSegmentLength);

    // The segments on triangle `triangle` of scene mesh `mesh`, in its barycentric coordinates;
    // empty if none.
    std::span<const TriangleSegment> on(uint32_t mesh, uint32_t triangle) const;
    size_t triangleCount() const { return segments_.size(); }  // triangles with a segment

  private:
    static uint64_t key(uint32_t mesh, uint32_t triangle) {
        return (uint64_t(mesh) << 32) | triangle;
    }
    std::unordered_map<uint64_t, std::vector<TriangleSegment>> segments_;
};

}  // namespace penumbra
