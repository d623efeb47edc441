// What discontinuity meshing is to leave none of: leaves that straddle a line of the light.
#pragma once

#include "core/math.h"
#include "radiosity/radiosity_mesh.h"

#include <cstdint>
#include <functional>

namespace penumbra::test {

// The leaves of scene mesh `sceneMesh` with corners on both sides of an outline (by more than
// 1e-5 m), the outline given as a signed distance.
inline int straddlingLeaves(const RadiosityMesh& mesh, uint32_t sceneMesh,
                            const std::function<float(const Vec3&)>& outline) {
    int straddling = 0;
    for (const int leaf : mesh.leafElements()) {
        if (mesh.sceneMesh(leaf) != sceneMesh)
            continue;
        bool inside = false, outside = false;
        for (const Vec3& corner : mesh.corners(leaf)) {
            const float d = outline(corner);
            inside = inside || d < -1e-5f;
            outside = outside || d > 1e-5f;
        }
        straddling += inside && outside ? 1 : 0;
    }
    return straddling;
}

}  // namespace penumbra::test
