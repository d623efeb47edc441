// Baking a radiosity solution into vertex colours: the refined element mesh as a glTF model
// (core/gltf_writer.h) whose unlit COLOR_0 is the radiance leaving each vertex, so that any glTF
// viewer shows the lit scene for interactive walkthroughs (`penumbra bake`, docs/cli.md).
#pragma once

#include "core/gltf_writer.h"

#include <cstddef>
#include <functional>
#include <optional>

namespace penumbra {

class Progress;
class RadiosityMesh;
class Scene;

// The vertex attribute holding the baked radiance itself, unclamped and without the exposure:
// cd/m² per linear-sRGB channel, FLOAT VEC3.
inline constexpr const char* kRadianceAttribute = "_RADIANCE";

// Leaves that meet at a vertex show values there that differ by a few thousandths where the light
// is smooth (each evaluates its corners a little inside itself, and a coarse leaf interpolates
// over a finer one's corner), and by up to all of it across a cut. Values within this fraction of
// the larger are written as one vertex, the first leaf's: a tenth of a per cent is far below
// what a viewer shows and below the solution's own error, and it keeps a vertex per value from
// multiplying the model's vertices (2.5 times on the Cornell box).
inline constexpr float kSameBakedRadiance = 1e-3f;

// Area-weighted quantile of the radiance that automatic exposure maps to 1 (see bakeRadiosity).
inline constexpr double kAutoExposureQuantile = 0.99;

struct BakeResult {
    GltfModelData model;
    float exposure = 0.0f;  // EV applied: colours are radiance (cd/m²) times 2^exposure
    bool automaticExposure = false;
    // Automatic exposure: the radiance (cd/m², largest channel) mapped to 1; 0 otherwise.
    float exposureRadiance = 0.0f;
    size_t leaves = 0, vertices = 0, triangles = 0;
};

// The radiance (cd/m², emission included) a solution shows on the front of a leaf at one of its
// corners (RadiositySolver::cornerRadiance).
using LeafCornerRadiance = std::function<Color(int leaf, size_t corner)>;

// Builds the model of a solved mesh: the mesh must be the one RadiositySolver::solve() refined,
// and `cornerRadiance` the solution's values at its leaves' corners.
//
// - One glTF mesh per scene mesh that has meshed triangles, named like it; transmissive meshes,
//   which the radiosity mesh does not hold, are left out. Positions are the element vertices,
//   relative to the scene's origin (SceneDescription::origin), which becomes the model's origin,
//   so the model lines up with the file that was read.
// - Every leaf element is written without T-junctions: as its own triangle when no other vertex
//   lies on its edges, otherwise as a fan from its centroid over its boundary: the vertices of
//   finer neighbours on its edges (RadiosityMesh::leafBoundary()) and, on the edges of its scene
//   triangle, those of the leaves of the triangles beside, which cuts along shadow and contact
//   lines and their own refinement place elsewhere. The fan is exact: the field is linear over a
//   leaf, so each vertex on an edge takes the mix of the edge's corners and the centroid their
//   mean.
// - Radiance L = the front side's radiance including emission, as the leaf shows it at its
//   corners (cornerRadiance), so that where the light steps (the two sides of a shadow line's
//   cut) each side's vertices hold its own value. COLOR_0 (linear RGB) is L times 2^exposure
//   clamped to [0, 1], the range glTF allows for it and viewers show; the attribute
//   kRadianceAttribute keeps L itself. A mesh vertex is written once per value the leaves
//   around it show there (and per normal).
// - Normals: the scene mesh's vertex normals interpolated at the vertex when it has them, else
//   the leaf's geometric normal (vertices are then split at creases: glTF's flat shading).
// - Sides: the material is doubleSided exactly when the source material was, and only the front
//   side's radiance is baked. A one-sided source is culled from behind by glTF viewers, as the
//   input model is, so the bake looks like the input in the same viewer. For a two-sided source
//   the back shows the front's radiance: exact for surfaces lit alike on both sides, an
//   approximation otherwise (baking the back would need a second, reverse-wound copy of every
//   triangle, and z-fights in viewers that do not cull).
//
// exposure: in EV; without one, the automatic exposure maps the area-weighted
// kAutoExposureQuantile quantile of the largest channel over the non-emissive surfaces (all
// surfaces if every one emits) to 1, so that 1 % of the lit area saturates; emitters, usually
// brighter, saturate too. A black scene gets exposure 0.
// progress, if given, is advanced once per leaf.
BakeResult bakeRadiosity(const Scene& scene, const RadiosityMesh& mesh,
                         const LeafCornerRadiance& cornerRadiance, std::optional<float> exposure,
                         Progress* progress = nullptr);

}  // namespace penumbra
