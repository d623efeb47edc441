// The element mesh of the radiosity pass: every opaque scene triangle split into patches, each
// patch the root of a quadtree of triangular elements (1:4 splits), with vertices shared between
// neighbouring elements so that a per-element solution can be shown Gouraud-interpolated without
// cracks or T-junction jumps. The solver (Hanrahan, Salzman and Aupperle 1991) refines the
// quadtrees through split() and keeps its own per-element arrays, indexed by element id.
//
// Conventions:
//  - Elements are identified by int ids, stable for the life of the mesh. The patches are ids
//    [0, patchCount()); the four children of a split element have consecutive ids, child c
//    (c = 0, 1, 2) at the parent's corner c and child 3 in the middle:
//        child 0: (c0, m01, m20), child 1: (m01, c1, m12), child 2: (m20, m12, c2),
//        child 3: (m12, m20, m01),
//    with mij the midpoint of the edge ci cj. Corners run counter-clockwise seen from the front,
//    the front being the side the scene triangle's counter-clockwise winding faces.
//  - Vertices are identified by uint32_t ids. A vertex is shared by every element that has it as
//    a corner, across patches and, through the scene mesh's own vertex indices, across scene
//    triangles of one mesh. (glTF meshes duplicate vertices at hard edges and UV seams: those
//    stay separate, and so do the corners of a triangle that would make the mesh non-manifold.)
//  - Units: metres, square metres; rho is a reflectance in [0, 1] per channel; Le is a radiance
//    in cd/m² per channel.
//
// Only radiosity_mesh.cpp (and sealed_interiors.cpp) sees OpenMesh (CONTRIBUTING.md,
// "Layering"); it holds the leaf elements as a polygon mesh in which an element next to
// a finer neighbour carries that neighbour's midpoints on its edges (T-vertices, leafBoundary()).
#pragma once

#include "core/material.h"
#include "core/math.h"

#include <array>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace penumbra {

class Scene;

struct MeshingSettings {
    // Longest edge of a patch, metres, > 0: the solvers resolve their script's "auto" to a length
    // (RadiositySettings::meshing, ProgressiveSettings::meshing) before they mesh.
    float patchEdgeLength = 0.0f;
    // Smallest element area split() may create, m²; 0 = the element's patch area / 4^6, i.e. at
    // most six levels of 1:4 splits below each patch.
    float minElementArea = 0.0f;
    // Cut the scene triangles along their contact lines (contact_lines.h) before the patches are
    // made, so that no element straddles one: the triangles of at least 16 times minElementArea,
    // along segments at least sqrt(minElementArea) long (which must then be > 0).
    bool contactLines = false;
    // Cut them along the shadow boundaries of the scene's point-like sources too
    // (shadow_lines.h), with the same bounds.
    bool shadowLines = false;
    // Reflect the sharp glossy lobes (Bsdf::hasSharpGlossyLobe) spread as Lambertian, as the
    // rough ones; false for a solution whose specular transfer carries their reflection by
    // photons (passes/specular_transfer.h), so that rho leaves them out.
    bool spreadSharpGlossy = true;
};

// Sizes for the log (the solver's statistics).
struct RadiosityMeshStats {
    size_t patches = 0;
    size_t elements = 0;  // patches and every element below them
    size_t leaves = 0;
    size_t vertices = 0;
    // Midpoints on an edge whose other side is not split, as of the last setElementValues().
    size_t tVertices = 0;
    size_t cutTriangles = 0;  // scene triangles cut along contact or shadow lines, into...
    size_t pieces = 0;        // ... this many pieces, each patched like a triangle
    size_t memoryBytes = 0;   // estimate of what the mesh holds, OpenMesh's arrays included
};

// A point inside an element: the element and the point's barycentric weights with respect to the
// element's corners (vertices(element)); element -1 when the point lies on no meshed triangle.
struct ElementPoint {
    int element = -1;
    Vec3 weights{0.0f};
};

// Whether the radiosity mesh holds the surfaces of this material: the opaque ones, in the sense
// of having no transmission (transmission factor 0; alpha cut-outs are meshed as if opaque).
// Transmissive surfaces are left to the ray tracer.
inline bool holdsMaterial(const Material& material) {
    return !(material.transmission > 0.0f);
}

class RadiosityMesh {
  public:
    static constexpr int kChildren = 4;

    // Meshes every triangle of every scene mesh whose material it holds (holdsMaterial), cut
    // into pieces along its contact lines first if the settings ask it. Each triangle (or piece)
    // is split uniformly into n^2 patches, n = 2^k the smallest power of two with
    // (longest edge) / n <= patchEdgeLength. A power of two, not ceil(longest edge / length): with
    // it the patch grids of two triangles sharing an edge nest (the coarser one's patch vertices
    // are among the finer one's), so the T-vertex rule of setElementValues() keeps the
    // interpolated field continuous across the scene's own edges too. The mesh keeps a reference
    // to the scene, which must outlive it. Throws std::invalid_argument for a negative or NaN
    // setting, or for settings that would give more than 2^31 - 1 patches.
    RadiosityMesh(const Scene& scene, const MeshingSettings& settings);
    ~RadiosityMesh();
    RadiosityMesh(const RadiosityMesh&) = delete;
    RadiosityMesh& operator=(const RadiosityMesh&) = delete;
    RadiosityMesh(RadiosityMesh&&) noexcept;
    RadiosityMesh& operator=(RadiosityMesh&&) noexcept;

    // The resolved settings (defaults replaced by the values they stand for).
    float patchEdgeLength() const { return patchEdgeLength_; }
    // Smallest area split() may give a child of `element`, m².
    float minElementArea(int element) const {
        return minElementArea_ > 0.0f ? minElementArea_ : area(patch(element)) / 4096.0f;
    }

    size_t patchCount() const { return patchCount_; }
    size_t elementCount() const { return elements_.size(); }
    size_t leafCount() const { return leafCount_; }
    // The current leaves, in element order.
    std::vector<int> leafElements() const;
    size_t vertexCount() const { return positions_.size(); }
    RadiosityMeshStats stats() const;

    // --- The quadtrees ---------------------------------------------------------------------

    // -1 for a patch.
    int parent(int element) const { return at(element).parent; }
    // The first of the four consecutive children, -1 for a leaf.
    int firstChild(int element) const { return at(element).firstChild; }
    // Which of an element's children (0-3, whether it is split yet or not) holds the point of
    // barycentric coordinates w in the element's corners: child c < 3 the corner c's, where
    // w[c] > 1/2, child 3 the middle one.
    // The corners of each child as indices into the parent's corners c0 c1 c2 (0-2) and edge
    // midpoints m01 m12 m20 (3-5), in the order above.
    static constexpr int kChildCorners[kChildren][3] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}, {4, 5, 3}};
    static int childAt(const Vec3& w) {
        return w.x > 0.5f ? 0 : w.y > 0.5f ? 1 : w.z > 0.5f ? 2 : 3;
    }
    bool isLeaf(int element) const { return at(element).firstChild < 0; }
    // The patch (quadtree root) the element belongs to; a patch is its own.
    int patch(int element) const { return at(element).patch; }
    // Number of splits between the patch and the element (0 for a patch).
    int level(int element) const { return at(element).level; }
    // Whether the element's edge from corner k to corner k + 1 lies on a contact or shadow
    // line the triangle was cut along (MeshingSettings): the light may step across it.
    bool edgeOnCut(int element, size_t k) const { return (at(element).cutEdges >> k & 1) != 0; }
    // Whether split(element) is allowed: the element is a leaf and its children would be at least
    // minElementArea(element).
    bool canSplit(int element) const { return canSplit(element, minElementArea(element)); }
    // The same with another smallest child area, for a refinement with its own rule of size
    // (ShownDirect's, which sizes elements by the light rather than by the scene).
    bool canSplit(int element, float minChildArea) const {
        return isLeaf(element) && area(element) * 0.25f >= minChildArea;
    }
    // Whether the element has children or may be given some (canSplit).
    bool subdivisible(int element) const { return !isLeaf(element) || canSplit(element); }
    // Splits a leaf 1:4 at its edge midpoints and returns the id of its first child. A midpoint
    // is shared with the neighbouring element across that edge (it exists already if the
    // neighbour was split first). Children inherit the parent's normal, get exactly a quarter of
    // its area, and their own rho and Le. An element split before is returned unchanged (its
    // first child). Throws std::logic_error if !canSplit(element) for a leaf. Invalidates the
    // values of the last setElementValues(), which must be called again before interpolating.
    int split(int element) { return split(element, minElementArea(element)); }
    // The same, allowed down to children of minChildArea (canSplit(element, minChildArea)).
    int split(int element, float minChildArea);

    // --- Geometry ----------------------------------------------------------------------------

    // Corner vertex ids, counter-clockwise seen from the front.
    const std::array<uint32_t, 3>& vertices(int element) const { return at(element).vertices; }
    // Corner positions in world space, in the order of vertices().
    std::array<Vec3, 3> corners(int element) const {
        const auto& v = at(element).vertices;
        return {positions_[v[0]], positions_[v[1]], positions_[v[2]]};
    }
    const Vec3& position(uint32_t vertex) const {
        assert(vertex < positions_.size());
        return positions_[vertex];
    }
    // m²; a patch has 1/n^2 of its scene triangle's area, a child exactly 1/4 of its parent's.
    float area(int element) const { return at(element).area; }
    // Unit normal on the front side: the scene triangle's geometric normal.
    const Vec3& normal(int element) const { return at(element).normal; }
    Vec3 centroid(int element) const {
        const auto c = corners(element);
        return (c[0] + c[1] + c[2]) / 3.0f;
    }
    // The vertices around a leaf, counter-clockwise from corner 0: its three corners and, between
    // them, the T-vertices that finer neighbours put on its edges. A triangle fan of these without
    // T-junctions (e.g. from the centroid) is what an exporter writes. Throws std::logic_error for
    // an element that is not a leaf.
    std::vector<uint32_t> leafBoundary(int element) const;

    // --- Where it lies in the scene -----------------------------------------------------------

    // Index of the scene mesh (Scene::meshes()) and of the triangle in it.
    uint32_t sceneMesh(int element) const { return at(element).mesh; }
    uint32_t sceneTriangle(int element) const { return at(element).triangle; }
    // Barycentric coordinates of the corners in the scene triangle (weights of its vertices 0,
    // 1, 2), in the order of vertices(). Exact (dyadic fractions) in a triangle not cut into
    // pieces.
    const std::array<Vec3, 3>& barycentrics(int element) const { return at(element).barycentric; }

    // --- Material ----------------------------------------------------------------------------

    // Reflectance: Bsdf::diffuseGlossyReflectance() of Scene::bsdf() at the centroid (the sharp
    // glossy lobes' part left out unless spreadsSharpGlossy()); for a material whose reflectance
    // varies over the surface (a base colour, metallic-roughness, specular or specular colour
    // texture), the mean over four points: the centroid and the midpoints between it and each
    // corner.
    const Color& rho(int element) const { return at(element).rho; }
    // The rough glossy lobes' part of rho (rho less Bsdf::matteReflectance()), averaged as rho:
    // zero on a Lambertian surface.
    const Color& rhoGlossy(int element) const { return at(element).rhoGlossy; }
    // Whether rho holds the sharp glossy lobes (MeshingSettings::spreadSharpGlossy).
    bool spreadsSharpGlossy() const { return spreadSharpGlossy_; }
    // Emitted radiance towards the front (Scene::emitted), averaged like rho when the emission is
    // textured; the back emits nothing unless twoSided().
    const Color& Le(int element) const { return at(element).Le; }
    // The material is double-sided: the back reflects (with the same rho) and emits (the same Le)
    // like the front.
    bool twoSided(int element) const { return at(element).twoSided; }

    // --- Lookups and interpolation -----------------------------------------------------------

    // The leaf containing the point with barycentric coordinates b in scene triangle (mesh,
    // triangle), found in O(1) for the patch and O(level) below it, and the point's weights in
    // it. b is clamped into the triangle first. element -1 if the triangle is not meshed.
    ElementPoint locate(uint32_t mesh, uint32_t triangle, const Vec3& b) const;

    // Takes one value per element (size elementCount(); only the leaves' values are used) and
    // computes the per-vertex values of the Gouraud interpolation: the area-weighted average of
    // the leaves having the vertex as a corner (nodal averaging), except at T-vertices, which
    // take the linear interpolation along the edge they lie on, so the interpolated field is
    // continuous (Cohen and Wallace 1993, "Radiosity and Realistic Image Synthesis", ch. 6;
    // the anchoring of T-vertices of Baum, Mann, Smith and Winget 1991, "Making Radiosity
    // Usable", SIGGRAPH '91). With `perCorner` (size elementCount() too), each leaf adds its own
    // value at each of its corners to its element value there before the averaging (a field
    // known at the leaves' corners, ShownDirect's). With `weights` (size elementCount() too) a
    // leaf weighs weights[leaf] instead of its area: a leaf of weight 0 (one nobody sees, under a
    // block) counts at none of its corners, unless all the leaves at a corner weigh 0 (then
    // their areas do), and anchors no T-vertex on its edges. Throws std::invalid_argument for a
    // wrong size.
    void setElementValues(std::span<const Color> perElement,
                          std::span<const std::array<Color, 3>> perCorner = {},
                          std::span<const float> weights = {});
    // The value computed by setElementValues() at a vertex.
    Color vertexValue(uint32_t vertex) const;
    // The Gouraud interpolation at a point (see locate()): the leaf's corner values weighted by
    // the point's barycentrics. A constant field is returned exactly. Zero on a triangle that is
    // not meshed. Throws std::logic_error if setElementValues() was not called since the last
    // split.
    Color interpolate(uint32_t mesh, uint32_t triangle, const Vec3& b) const;
    // The leaf's own (flat) value at a point; same conventions as interpolate().
    Color elementValue(uint32_t mesh, uint32_t triangle, const Vec3& b) const;

  private:
    struct Element {
        std::array<uint32_t, 3> vertices{};
        std::array<Vec3, 3> barycentric{};
        Vec3 normal{0.0f};
        float area = 0.0f;
        Color rho{0.0f};
        Color rhoGlossy{0.0f};
        Color Le{0.0f};
        uint32_t mesh = 0;
        uint32_t triangle = 0;
        int parent = -1;
        int firstChild = -1;
        int patch = -1;
        int face = -1;  // the leaf's face in the OpenMesh mesh, -1 once split
        uint8_t level = 0;
        bool twoSided = false;
        uint8_t cutEdges = 0;  // bit k: its edge from corner k to k + 1 lies on a cut's line
    };
    // Per scene triangle, or per piece of a triangle cut along contact lines: its first patch
    // and the number of patches along an edge (n = 2^level).
    struct TrianglePatches {
        int firstPatch = -1;  // -1: not meshed
        uint8_t level = 0;
        // A cut triangle: its pieces are pieces_[firstPiece, firstPiece + pieceCount), and
        // firstPatch and level are unused.
        int firstPiece = -1;
        int pieceCount = 0;
    };
    // A piece of a cut triangle: its patches, and its corners' barycentric coordinates in the
    // triangle, with what turns the triangle's (b1, b2) into the piece's (w1, w2):
    // w = toPiece * (b - corners[0]).
    struct Piece {
        TrianglePatches patches;
        std::array<Vec3, 3> corners{};
        glm::mat2 toPiece{1.0f};
    };
    // OpenMesh's mesh and properties, per-material caches (radiosity_mesh.cpp).
    struct Impl;

    const Element& at(int element) const {
        assert(element >= 0 && static_cast<size_t>(element) < elements_.size());
        return elements_[static_cast<size_t>(element)];
    }
    void setMaterial(Element& element);
    void syncPositions();
    void checkValuesCurrent() const;
    // The leaf at lattice point (b1, b2) of a triangle or piece patched as `patches`.
    ElementPoint locateInLattice(const TrianglePatches& patches, float b1, float b2) const;

    const Scene* scene_;
    bool spreadSharpGlossy_ = true;
    float patchEdgeLength_ = 0.0f;
    float minElementArea_ = 0.0f;  // 0: relative to the patch
    std::unique_ptr<Impl> impl_;
    std::vector<Element> elements_;
    std::vector<Vec3> positions_;                          // per vertex
    std::vector<std::vector<TrianglePatches>> triangles_;  // per scene mesh, per triangle
    std::vector<Piece> pieces_;
    size_t patchCount_ = 0;
    size_t leafCount_ = 0;
    // Gouraud interpolation, from setElementValues()
    std::vector<Color> elementValues_;
    std::vector<Color> vertexValues_;
    size_t tVertexCount_ = 0;
};

}  // namespace penumbra
