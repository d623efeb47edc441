// The hierarchical solver's settings: their defaults, what they resolve to for a scene, their
// validation.
//
// Parameters of the radiosity pass (RadiositySettings):
//   key                 type    default         meaning
//   solver              string  "hierarchical"  solution method ("progressive": see
//                                               progressive_solver.cpp for its own keys)
//   epsilon             float   0.01            refinement threshold: largest error a link may
//                                               make, relative to the scene's mean radiance and,
//                                               once solved, to its receiver's (exceedsThreshold)
//   patch_edge_length   float   0               longest patch edge in m (0 = bounding radius)
//   min_element_area    float   0               smallest element in m² (0 = total area / 16384)
//   contact_lines       bool    false           cut the triangles along the lines where other
//                                               surfaces meet them (a block on a floor) before
//                                               meshing, so that no element straddles one
//   shadow_lines        bool    true            cut them along the shadow boundaries of point
//                                               lights, luminaires and the sun as well
//   convergence         float   1e-4            stop when the estimated relative error of the
//                                               gather iteration is below this
//   visibility_samples  int     16              shadow rays per link and direct-light samples per
//                                               element; a power of 2 stratifies best
//   max_iterations      int     5000            gather sweeps, all rounds together
//   max_refinements     int     8               refinement rounds after the first solve
//   iteration           string  "gauss-seidel"  gather order: gauss-seidel (patch by patch,
//                                               pushing and pulling each tree at once) or jacobi
//   cluster_min_patches int     256             above this many patches, link clusters of
//                                               patches (Sillion 1995) instead of every pair of
//                                               patches; 0 = always
//   subdivision_threshold float 0               after the solve, split leaves whose reflected
//                                               radiance differs from a neighbour's by more than
//                                               this fraction (relative), and solve again; 0 = off
//   final_gather        int     auto (-1)       rays per leaf side that gather its indirect light
//                                               from the solution to correct the links' transfer
//                                               (finalGather); 0 = off; auto = 64 when the solver
//                                               starts from clusters, else off
//   direct_at_corners   bool    true            show the sources' direct light evaluated at the
//                                               leaves' corners, the mesh refined after the solve
//                                               until its interpolation is within 1 %
//                                               (shown_direct.h); false = the element means
//   indirect_at_corners int     256             rays per leaf corner and side that gather the
//                                               indirect light shown there (indirect_at_corners.h);
//                                               0 = the element means
#include "radiosity/radiosity_settings.h"

#include "core/errors.h"
#include "core/scene.h"

#include <cmath>
#include <sstream>

namespace penumbra {

MeshingSettings RadiositySettings::meshing(const Scene& scene) const {
    MeshingSettings m;
    m.patchEdgeLength =
        patchEdgeLength > 0.0f ? patchEdgeLength : glm::max(scene.bounds().boundingRadius(), 1e-6f);
    if (minElementArea > 0.0f) {
        m.minElementArea = minElementArea;
    } else {
        double total = 0.0;
        for (const Mesh& mesh : scene.meshes()) {
            for (const glm::uvec3& t : mesh.triangles) {
                const Vec3 &p0 = mesh.positions[t[0]], &p1 = mesh.positions[t[1]],
                           &p2 = mesh.positions[t[2]];
                total += 0.5 * glm::length(glm::cross(p1 - p0, p2 - p0));
            }
        }
        m.minElementArea = static_cast<float>(glm::max(total / 16384.0, 1e-12));
    }
    m.contactLines = contactLines;
    m.shadowLines = shadowLines;
    return m;
}

void validateRadiositySettings(const RadiositySettings& s) {
    const auto fail = [](const std::string& key, const std::string& expected, double got) {
        std::ostringstream out;
        out << "radiosity." << key << ": expected " << expected << ", got " << got;
        throw UsageError(out.str());
    };
    if (s.solver != "hierarchical") {
        throw UsageError("radiosity.solver: unknown solver '" + s.solver +
                         "'; valid: hierarchical");
    }
    if (!(s.epsilon > 0.0f && s.epsilon < 1.0f))
        fail("epsilon", "a number in (0, 1)", s.epsilon);
    if (!(s.patchEdgeLength >= 0.0f) || !std::isfinite(s.patchEdgeLength))
        fail("patch_edge_length", "a length >= 0", s.patchEdgeLength);
    if (!(s.minElementArea >= 0.0f) || !std::isfinite(s.minElementArea))
        fail("min_element_area", "an area >= 0", s.minElementArea);
    if (!(s.convergence > 0.0 && s.convergence < 1.0))
        fail("convergence", "a number in (0, 1)", s.convergence);
    if (s.visibilitySamples < 1 || s.visibilitySamples > 4096)
        fail("visibility_samples", "an integer in [1, 4096]", s.visibilitySamples);
    if (s.maxIterations < 1)
        fail("max_iterations", "an integer >= 1", s.maxIterations);
    if (s.maxRefinements < 0)
        fail("max_refinements", "an integer >= 0", s.maxRefinements);
    if (s.clusterMinPatches < 0)
        fail("cluster_min_patches", "an integer >= 0", s.clusterMinPatches);
    if (!(s.subdivisionThreshold >= 0.0f) || !std::isfinite(s.subdivisionThreshold))
        fail("subdivision_threshold", "a number >= 0", s.subdivisionThreshold);
    if (s.finalGatherRays != RadiositySettings::kAutoFinalGather &&
        (s.finalGatherRays < 0 || s.finalGatherRays > RadiositySettings::kMaxFinalGatherRays))
        fail("final_gather", "an integer in [0, 65536] or auto (-1)", s.finalGatherRays);
    if (s.indirectAtCorners < 0 ||
        s.indirectAtCorners > RadiositySettings::kMaxIndirectAtCornersRays)
        fail("indirect_at_corners", "an integer in [0, 65536]", s.indirectAtCorners);
}

RadiositySettings RadiositySettings::forCorrectedReuse() {
    RadiositySettings settings;
    settings.epsilon = 0.04f;
    settings.visibilitySamples = 4;
    settings.maxRefinements = 1;
    settings.finalGatherRays = 0;
    settings.indirectAtCorners = 0;
    settings.convergence = 1e-3;
    return settings;
}

}  // namespace penumbra
