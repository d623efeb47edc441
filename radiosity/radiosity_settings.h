// The settings of the hierarchical radiosity solver (radiosity_solver.h), as the radiosity pass and
// `penumbra bake` read them, with their defaults and their validation.
#pragma once

#include "radiosity/radiosity_mesh.h"

#include <string>

namespace penumbra {

class Scene;

// The parameters of the radiosity pass; their table (key, type, default, meaning) is at the top of
// radiosity_settings.cpp.
struct RadiositySettings {
    enum class Iteration { GaussSeidel, Jacobi };

    // Always "hierarchical" here; the radiosity pass also offers "progressive", whose settings
    // are ProgressiveSettings (progressive_solver.h).
    std::string solver = "hierarchical";
    // Refinement threshold: a link is refined while the error it makes in the receiver's radiance
    // (the refinement oracle, link_refiner.cpp) exceeds epsilon times the scene's mean
    // radiance or, from the first refinement round on, epsilon times what the receiver itself
    // reflects in any channel (exceedsThreshold). Dimensionless; smaller is finer and slower.
    float epsilon = 1e-2f;
    // Longest patch edge, metres; 0 = the scene's bounding radius (coarse patches: HSA91 links
    // every pair of patches, so their number enters squared).
    float patchEdgeLength = 0.0f;
    // Smallest element area, m²; 0 = the scene's total surface area / 16384.
    float minElementArea = 0.0f;
    // Cut the scene's triangles along their contact lines before meshing (MeshingSettings::
    // contactLines): discontinuity meshing of the D0 discontinuities.
    bool contactLines = false;
    // Cut them along the shadow boundaries of the point-like sources too (MeshingSettings::
    // shadowLines): the D1 discontinuities of point lights, luminaires and the sun.
    bool shadowLines = true;
    // Stop when the estimated relative error of the iteration (RadiosityIteration::errorBound) is
    // below this.
    double convergence = 1e-4;
    // Shadow rays per link, between stratified points of the two elements, and direct-light
    // samples per element; a power of 2 stratifies best.
    int visibilitySamples = 16;
    int maxIterations = 5000;  // gather sweeps, over all refinement rounds
    int maxRefinements = 8;    // refinement rounds after the first solve
    // Scenes with more patches than this start from clusters of patches (cluster_tree.h) linked
    // from one self-link of the root instead of from links between every pair of patches; 0 =
    // always.
    int clusterMinPatches = 256;
    // Adaptive subdivision after the solve: a leaf whose reflected radiance differs from a
    // neighbouring leaf's by more than this fraction of the larger (and by more than the oracle's
    // absolute threshold) is split, down to the smallest element area, and its links are refined
    // onto its children; up to 4 passes, each followed by a solve. 0 = off.
    float subdivisionThreshold = 0.0f;
    // Final gather after the solve: rays per leaf side, cosine-distributed from stratified points
    // of it, that gather its indirect light from the solution; each patch side's mean difference
    // from the links' gather corrects the solution (final_gather.cpp). 0 = off; kAutoFinalGather
    // = kClusterFinalGatherRays when the solver starts from clusters, else off.
    static constexpr int kAutoFinalGather = -1;
    static constexpr int kClusterFinalGatherRays = 64;
    static constexpr int kMaxFinalGatherRays = 65536;
    int finalGatherRays = kAutoFinalGather;
    Iteration iteration = Iteration::GaussSeidel;
    // Show the sources' direct light as evaluated at the corners of the leaves, on a mesh refined
    // after the solve until its linear interpolation is right (shown_direct.h), instead of as the
    // Gouraud interpolation of the element means: what radiance() returns, the radiosity view and
    // the bake show (docs/radiosity.md, "The direct light at the corners").
    bool directAtCorners = true;
    // Show the indirect light as gathered at the corners of the leaves with this many rays per
    // corner and side (indirect_at_corners.h), instead of as the Gouraud interpolation of the
    // element means: what radiance() and indirectRadiance() return, the radiosity view, the bake
    // and the distribution pipeline's ambient term show. 0 = off.
    static constexpr int kMaxIndirectAtCornersRays = 65536;
    int indirectAtCorners = 256;

    // The mesh settings these stand for, with the defaults resolved for `scene`.
    MeshingSettings meshing(const Scene& scene) const;

    // The solve for a path tracer that corrects the solution it reuses (the hybrid pipeline:
    // raytrace/path_tracer.h, correctionProbability): there the solution's error costs noise, not
    // bias, so a solve that is cheaper and a little rougher pays: 4 visibility rays per link
    // instead of 16, epsilon 0.04 (fewer, coarser links), one refinement round, no final gather
    // and sweeps only to a relative error of 1e-3 (five on the modern hall instead of ten; the
    // hybrid's error at 256 spp on the hall and the Cornell box unchanged to 0.1 %: far under
    // the solution's own error, which the correction removes). On the modern hall this is 14 s
    // instead of 55 s on one thread.
    static RadiositySettings forCorrectedReuse();
};

// Throws UsageError naming the key ("radiosity.epsilon: expected ...") for a value out of range.
void validateRadiositySettings(const RadiositySettings& settings);

}  // namespace penumbra
