// Baking a radiosity solution into vertex colours: the refined element mesh as a glTF model
// (core/gltf_writer.h) whose unlit COLOR_0 is the radiance leaving each vertex, so that any glTF
// viewer shows the lit scene for interactive walkthroughs (`penumbra bake`, docs/cli.md).
#pragma once

#include "core/gltf_writer.h"

#include <cstddef>
#include <optional>

namespace penumbra {

class Progress;
class RadiosityMesh;
class Scene;

// The vertex attribute holding the baked radiance itself, unclamped and without the exposure:
// cd/m² per linear-sRGB channel, FLOAT VEC3.
inline constexpr const char* kRadianceAttribute = "_RADIANCE";

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

// Builds the model of a solved mesh: the mesh must be the one RadiositySolver::solve() refined,
// with the mesh's element values left as solve() leaves them (the front side's reflected
// radiance, RadiosityMesh::setElementValues).
//
// - One glTF mesh per scene mesh that has meshed triangles, named like it; transmissive meshes,
//   which the radiosity mesh does not hold, are left out. Positions are the element vertices,
//   relative to the scene's origin (SceneDescription::origin), which becomes the model's origin,
//   so the model lines up with the file that was read.
// - Every leaf element is written without T-junctions: as its own triangle when no finer
//   neighbour put a vertex on its edges, otherwise as a fan from its centroid over
//   RadiosityMesh::leafBoundary(). The fan is exact: the Gouraud field is linear over a leaf, the
//   T-vertices' values included (they are anchored to the leaf's edge), so the centroid takes the
//   mean of the corner values.
// - Radiance L = the front side's radiance including emission: the vertex's reflected radiance
//   (RadiosityMesh::vertexValue) plus the leaf's own Le. COLOR_0 (linear RGB) is L times
//   2^exposure clamped to [0, 1], the range glTF allows for it and viewers show; the attribute
//   kRadianceAttribute keeps L itself. Where leaves with different Le meet (an emitter's edge
//   inside one mesh, textured emission), the vertex is written once per Le, so the emission stays
//   flat per element as in the solution.
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
                         std::optional<float> exposure, Progress* progress = nullptr);

}  // namespace penumbra
