// The sides of scene triangles that face a sealed interior, which no light can reach: the inside
// of a closed surface with no light inside it. A solid modelled as a closed box (a stair tread, a
// table top, a wall with thickness) has inner faces that the radiosity mesh would otherwise light
// and link like any other side: whatever a cluster of such solids receives was shared between
// the outer and the inner sides, and the visible fraction of a cluster's points counted the
// rays from its far faces, blocked by the solid itself, as occluded (in the modern hall the
// floating stairs gathered 20-25 % less than rays from them see; docs/radiosity.md, "Clusters").
// Knowing the interior from the topology does not depend on glTF's doubleSided flag, which
// exporters set on everything.
//
// A closed surface is a connected part of one scene mesh that is a consistently wound
// edge-manifold without boundary (each edge shared by exactly two of its triangles, in opposite
// directions, vertices welded by exact position since glTF meshes duplicate them at hard edges),
// enclosing a non-zero volume. Its interior is the side its triangles face when its signed
// volume is negative, else the other. It is sealed when its material is opaque (alphaMode
// OPAQUE, no transmission), emits nothing, and no light lies inside it: no point or spot light,
// no centroid of an emissive triangle (winding number of the point: the sum of the signed solid
// angles of the surface's triangles over 4 pi, as in Jacobson, Kavan and Sorkine-Hornung 2013,
// "Robust Inside-Outside Segmentation using Generalized Winding Numbers", SIGGRAPH '13). A room
// modelled as a closed box with its lamps inside is not sealed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace penumbra {

class Scene;

class SealedInteriors {
  public:
    explicit SealedInteriors(const Scene& scene);

    // Whether the side (front: the side the counter-clockwise winding faces) of triangle
    // `triangle` of scene mesh `mesh` faces a sealed interior.
    bool faces(uint32_t mesh, uint32_t triangle, bool front) const {
        const std::vector<uint8_t>& sides = side_[mesh];
        return !sides.empty() && sides[triangle] == (front ? kFront : kBack);
    }
    // Number of sealed closed surfaces, for the log.
    size_t count() const { return count_; }

  private:
    static constexpr uint8_t kNone = 0, kFront = 1, kBack = 2;
    // Per scene mesh, per triangle, the side facing a sealed interior; empty for a mesh without.
    std::vector<std::vector<uint8_t>> side_;
    size_t count_ = 0;
};

}  // namespace penumbra
