// Hierarchical radiosity (Hanrahan, Salzman and Aupperle 1991, "A Rapid Hierarchical Radiosity
// Algorithm", SIGGRAPH '91; "HSA91" below) on the element quadtrees of a RadiosityMesh.
//
// What the solution contains: for every element and each of its two sides, the radiance leaving
// it (cd/m² per linear-sRGB channel) = its own emission Le + the diffusely reflected light of all
// bounces, i.e. the paths L D* E ending on the element, with the direct light of the emissive
// elements and of the punctual lights (point, spot, directional) included. D vertices are the
// diffuse and the rough glossy ones (Heckbert's notation, docs/light-paths.md), so each material
// takes part with all its non-delta reflection, approximated as Lambertian with the same
// hemispherical reflectance (rho = Bsdf::diffuseGlossyReflectance()): the energy is right, the
// directional distribution of rough glossy reflection is not. Delta (S) reflection and
// transmission are left to the ray-tracing passes, but for what a caller gives back as deposited
// flux: the caustic photons (L S+ D) and the solution's own light carried through specular
// surfaces (D S+ D, transferThroughSpecular). The solution also splits the
// reflected light into the first reflection of the sources (paths L D E: Le of the emissive
// elements and the punctual lights, reflected once) and the rest (L D D+ E), for the two-pass
// pipelines that trace the first themselves (indirectRadiance). Surfaces the mesh does not hold
// (transmissive materials) are neither sources nor receivers, but block nothing either when they
// are thin-walled: shadow rays pass through them as Scene::transmittance() says.
//
// Sides: both sides of every element reflect, with the same rho, as the path tracer's BSDF does
// whatever the material's doubleSided flag (RadiosityMesh::twoSided() says a one-sided back does
// not; the solver follows the path tracer); the back emits only for a two-sided material. Each
// side has its own radiance.
//
// Equation solved, per element side i (the discrete radiosity equation of Goral, Torrance,
// Greenberg and Battaile 1984 and HSA91, B = E + rho sum F B, divided by pi to radiance; Cohen and
// Wallace 1993, "Radiosity and Realistic Image Synthesis", chapter 2):
//     L_i = Le_i + rho_i (D_i + sum_j F_ij V_ij L_j)
// with F_ij the unoccluded form factor from i to j, V_ij in [0, 1] the visible fraction and D_i the
// direct irradiance of the punctual lights divided by pi (cd/m²), averaged over the element, plus
// that of any deposited flux: with the caustic photons' (deposited_flux.h) the solution also holds
// the paths L S+ D+ (light that reached the element through specular surfaces, and its further
// diffuse bounces), and its "first reflection of the sources" (elementDirect) their first
// reflection L S+ D too.
//
// Covered parts: where a surface touches another (the floor under a block standing on it, the
// ceiling over a lamp that hangs just under it), part of an element side sees nothing and is seen
// by nothing (isCovered, element_sampling.h). Each element side's L, D and the sum above are means
// over its exposed part only, F_ij V_ij that part's transfer (visibility() and exposedFormFactor
// in link_transfer.cpp), so that an element straddling the foot of a block shows, and sends,
// the light of its lit part rather than its mean with the dark part under the block; a wholly
// covered side has L = Le and no links. The inner sides of closed solids with no light inside
// (sealed_interiors.h: stair treads, table tops modelled as boxes) are wholly covered whatever
// the probes find. A cluster's points take part in a link's visible fraction only through the
// side of their patch that faces the other end, when that side is exposed (visibility()). Where
// two faces lie on each other in the same plane (coincident_faces.h), each side of the surface
// belongs to one of them: the other's side there is covered and shows its light.
//
// Clustering: above RadiositySettings::clusterMinPatches patches, the patches are grouped in a
// bounding-volume hierarchy of clusters (cluster_tree.h) and links may also join a cluster to a
// cluster or to an element, with the isotropic cluster model of Sillion 1995 (see
// link_transfer.cpp, clusterKernel): a cluster gathers one radiance that it pushes to the
// element sides inside it (weighted to first order by their facing, sweepCluster), and shows the
// others the area-weighted mean radiance of its sides, weighted to first order by how its sides
// face the receiver (clusterRadianceToward). The model is approximate, and the oracle
// weighs its error (flat clusters most): with clusters forced on, the closed furnace box still
// gives Le / (1 - rho) within 1 % (tests/radiosity/radiosity_furnace_test.cpp), at more links than
// without; smaller scenes are solved without clusters.
//
// Final gather (RadiositySettings::finalGatherRays): after the solve, rays from every leaf side
// gather the indirect light the solution sends it, and each patch side's mean difference from what
// its links gathered becomes a correction that the gather sweeps then carry through every bounce
// (final_gather.cpp): the links' transfer error, which clusters make largest, is taken out at the
// cost of a few rays per leaf. By default it runs when the solver starts from clusters: without
// them the links alone are within 2.4 % on the Cornell box, and the gather's per-patch correction
// moved its small short-block face by 3 % (docs/radiosity.md, "The final gather"); with them the
// links' transfer was 10 % off in a closed room.
//
// The solver runs the stages of solve() over parts that each own their state:
//   ElementExposure (element_exposure.h)       the exposed part of every element side;
//   DirectIrradiance (direct_irradiance.h)     D, the punctual lights' and deposited flux's;
//   LinkTransfer (link_transfer.h)             form factors, kernel samples, visibility and the
//                                              cluster kernel of a link;
//   LinkHierarchy (link_hierarchy.h)           the links and their children's shares;
//   RadianceHierarchy (radiance_hierarchy.h)   every node's radiance: gather and push-pull;
//   LinkRefiner (link_refiner.h)               the oracle, which makes the links and splits;
//   GatherIteration (gather_iteration.h)       the sweeps until convergence, and their record;
//   FinalGather (final_gather.h)               the final gather's rays and correction;
//   ShownDirect (shown_direct.h)               the direct light shown at the leaves' corners.
#pragma once

#include "core/deadline.h"
#include "core/math.h"
#include "core/stats.h"
#include "radiosity/crease_refinement.h"
#include "radiosity/deposited_flux.h"
#include "radiosity/link_refiner.h"
#include "radiosity/radiosity_iteration.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_settings.h"
#include "radiosity/radiosity_solution.h"
#include "radiosity/solve_progress.h"
#include "radiosity/vertex_values.h"

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace penumbra {

class ClusterTree;
class DirectIrradiance;
class ElementExposure;
class FinalGather;
class GatherIteration;
class IndirectAtCorners;
class LinkHierarchy;
class LinkTransfer;
class RadianceHierarchy;
class Scene;
class ShownDirect;

class RadiositySolver : public RadiositySolution {
  public:
    // The mesh is refined by solve(); both must outlive the solver. `deposits`: flux that reached
    // the surfaces by paths the solver does not follow (the caustic photons), reflected and
    // carried on like the punctual lights' direct light (D_i below, deposited_flux.h).
    RadiositySolver(const Scene& scene, RadiosityMesh& mesh, const RadiositySettings& settings,
                    const std::vector<FluxDeposit>& deposits = {});
    ~RadiositySolver() override;

    // Direct light, initial linking, then gather sweeps alternating with refinement until nothing
    // is refined and the iteration has converged (or maxIterations); then the direct part
    // (indirectRadiance), the final gather, with directAtCorners the leaves split for the direct
    // light at their corners (unless the deadline has passed), and the vertex values. Leaves the
    // mesh's setElementValues() at the front side's reflected radiance. Reports its stages to
    // `progress` if given (solve_progress.h). `deadline`, if given, is when the caller's time for
    // the solve is up (a time limit): it is looked at as the links are refined and before each
    // refinement round and the final gather. Once it has passed, the refinement stops: the solve
    // ends with the links it has, those still being decided made as they stand
    // (LinkRefiner::OnTimeUp::Coarsen; the last gather and the vertex values are quick). With
    // OnTimeUp::Abandon, an initial linking that has not ended by the deadline abandons the solve
    // instead (abandoned()): the solution is then not usable, for a caller that can do without it
    // (the corrected hybrid traces what it would have held). `abandonAt`, with Coarsen, is a later
    // time past which the solve is abandoned all the same (a preview that traces without the
    // solution; LinkRefiner::setTimeLimit); with Abandon it is the deadline. The stages before
    // the links are made are abandoned as soon as they are projected to leave the solve no time
    // to end by then (the exposure, the direct light: solve()).
    void solve(SolveProgress* progress = nullptr, Deadline deadline = std::nullopt,
               LinkRefiner::OnTimeUp onTimeUp = LinkRefiner::OnTimeUp::Coarsen,
               Deadline abandonAt = std::nullopt);
    bool abandoned() const { return abandoned_; }

    // Extended transfer through specular surfaces (paths D S+ D, which the links do not carry):
    // `deposits` is the flux that the solution's reflected light (reflectedRadiance, shot as
    // photons by the caller: passes/specular_transfer.h) sent through mirrors and glass onto the
    // meshed surfaces. It replaces that of any earlier call as light given on the element sides
    // (D_i), part of the indirect light, not of the sources' first reflection; the gather sweeps
    // then converge again with it, and the direct part and vertex values are made anew. Called
    // after solve(); each call with photons shot from the solution it left carries the light one
    // more specular transfer further (the fixed-point iteration L = S(E + T L)).
    void transferThroughSpecular(const std::vector<FluxDeposit>& deposits,
                                 SolveProgress* progress = nullptr);
    // The reflected radiance of an element side (its own emission left out), cd/m², and the
    // fraction of its area that is exposed (element_exposure.h), for a caller that samples the
    // solution's light as an emitter.
    Color reflectedRadiance(int element, bool front) const;
    float exposedFraction(int element, bool front) const;

    // Gathers the indirect light at the leaves' corners (indirect_at_corners.h) with
    // RadiositySettings::indirectAtCorners rays, for radiance() and indirectRadiance() to show;
    // nothing if that is 0. For the owner to call once the solution is final, after solve() and
    // any specular transfer (a transfer drops the corners: they saw the solution before it).
    // With a deadline, fewer rays per corner if the asked count would end after it, and no
    // corners if too few would (IndirectAtCorners::gather). Reports its stage to `progress` if
    // given.
    void showIndirectAtCorners(SolveProgress* progress = nullptr, Deadline deadline = std::nullopt);

    // Radiance (cd/m²) leaving the surface at barycentric b of scene triangle (mesh, triangle)
    // on its front (or back) side: the Gouraud interpolation of the reflected part
    // (RadiosityMesh::setElementValues) plus, if includeEmission, the element's own flat Le; with
    // RadiositySettings::directAtCorners, the reflected part's first reflection of the lights is
    // rho times ShownDirect's interpolation of its corners instead (shown_direct.h). A
    // side hidden under a coincident face (coincident_faces.h) shows that face's light.
    // Zero on a triangle the mesh does not hold.
    Color radiance(uint32_t mesh, uint32_t triangle, Vec3 b, bool includeEmission,
                   bool front = true) const override;
    // radiance() at corner `corner` (in the order of RadiosityMesh::vertices()) of leaf `leaf`, as
    // that leaf shows it: where the leaves that meet at a vertex show different values (the two
    // sides of a cut along a shadow or contact line), each leaf's own.
    Color cornerRadiance(int leaf, size_t corner, bool includeEmission, bool front = true) const;
    // RadiositySolution: the Gouraud interpolation of elementIndirect().
    Color indirectRadiance(uint32_t mesh, uint32_t triangle, Vec3 b,
                           bool front = true) const override;
    // The element side's own (flat, not interpolated) radiance, emission included.
    Color elementRadiance(int element, bool front = true) const;
    // The first reflection of the sources' light on a leaf side, rho (D + sum_j K_ij Le_j) with
    // the links of the leaf and of its ancestors (RadianceHierarchy::computeDirectPart), and the
    // rest of its reflected light, max(0, L - Le - direct): the paths L D E and L D D+ E ending
    // there (cd/m²). Zero before solve() ends and for elements that are not leaves.
    Color elementDirect(int element, bool front = true) const;
    Color elementIndirect(int element, bool front = true) const;

    // What the dense reference of the tests reads (tests/support/full_matrix_solve.h): the
    // transfer the links take between nodes (solver_nodes.h), and a leaf side's radiance from what
    // it gathers, H (cd/m², its exposed part's mean).
    const LinkTransfer& linkTransfer() const { return *transfer_; }
    Color leafRadiance(int node, const Color& H) const;

    bool converged() const;
    size_t linkCount() const;
    // The final gather's rays per leaf side, RadiositySettings::finalGatherRays with auto resolved.
    int finalGatherRays() const;
    const std::vector<RadiosityIteration>& iterations() const;
    // Patches, elements, leaves, clusters (0 without clustering), links, refinement rounds, sweeps
    // ("iterations"), the last relative change ("residual") and error bound, rays, a memory
    // estimate, and seconds per stage: direct (the punctual lights' first shot), linking (initial
    // links), refine (the rounds), solve (the sweeps); form_factors is the part of linking and
    // refine spent on the form factors and visibility of new links; the process's peak resident
    // memory (getrusage ru_maxrss, MiB) at the end of each stage; and the reflected luminous flux
    // (pi sum_i A_i Y(L_i) over leaf sides, lm) of the direct part and of the indirect part; the
    // specular transfer's rounds, deposits, flux (lm) and seconds (its gathers included).
    PassStats stats() const override;
    bool spreadsSharpGlossy() const override { return mesh_.spreadsSharpGlossy(); }

  private:
    void resizeArrays();
    // Element e was split into first .. first + 3: they start from its radiance and direct light
    // until a sweep and their own sampling replace them.
    void inheritSplit(int e, int first);
    // The final gather's passes (final_gather.h), each a stage of rays, one per leaf, then its
    // gather sweeps; with a deadline, no pass that would end past it (as long as the last).
    void finalGather(Deadline deadline);
    // Leaves refined where surfaces meet, for the indirect light at the corners
    // (crease_refinement.h; only with RadiositySettings::indirectAtCorners), until `stop` says so.
    void refineAtCreases(const std::function<bool()>& stop);
    // The sources' direct light at the leaves' corners, on a mesh refined for it (shown_direct.h;
    // RadiositySettings::directAtCorners), its rounds of splits until `stop` says so.
    void showDirectAtCorners(const std::function<bool()>& stop);
    // What the solution shows of the indirect light (the transferred flux's first reflection
    // included) at a point: the corners' interpolation (indirect_at_corners.h), or without them
    // the vertex values' (Gouraud).
    Color shownIndirect(const ElementPoint& point, bool front) const;
    // radiance() at a point of a leaf.
    Color shownRadiance(const ElementPoint& point, bool includeEmission, bool front) const;
    void computeVertexValues();
    // The progress sink of solve(), if any (these do nothing without one).
    void beginStage(const std::string& name, uint64_t total);
    void endStage(const std::string& summary);

    const Scene& scene_;
    RadiosityMesh& mesh_;
    RadiositySettings settings_;
    std::unique_ptr<ElementExposure> exposure_;
    std::unique_ptr<DirectIrradiance> irradiance_;
    std::unique_ptr<ClusterTree> clusters_;  // null without clustering
    std::unique_ptr<LinkTransfer> transfer_;
    std::unique_ptr<LinkHierarchy> links_;
    std::unique_ptr<RadianceHierarchy> radiance_;
    std::unique_ptr<LinkRefiner> refiner_;
    std::unique_ptr<GatherIteration> iteration_;
    std::unique_ptr<FinalGather> finalGather_;
    std::unique_ptr<ShownDirect> shown_;                  // null unless directAtCorners
    std::unique_ptr<IndirectAtCorners> indirectCorners_;  // null unless indirectAtCorners > 0

    CreaseRefinement creases_;
    int firstCreaseLeaf_ = std::numeric_limits<int>::max();  // the first element it made, if run
    int rounds_ = 0;
    bool stoppedRefining_ = false;      // the deadline ended the refinement
    bool abandoned_ = false;            // ... before the links were all made (abandonAt)
    SideVertexValues vertexReflected_;  // the reflected radiance, per mesh vertex and side
    SideVertexValues vertexIndirect_;   // its indirect part (elementIndirect)
    SideVertexValues vertexRest_;       // with shown_ or indirectCorners_: what their corners leave
    SolveProgress* progress_ = nullptr;  // during solve() only
    uint64_t rays_ = 0;
    int finalGatherPasses_ = 0;
    int transferRounds_ = 0;
    double secondsTransfer_ = 0;
    double secondsDirect_ = 0, secondsLinking_ = 0, secondsSolve_ = 0, secondsRefine_ = 0,
           secondsFinalGather_ = 0, secondsCreases_ = 0, secondsShownDirect_ = 0,
           secondsIndirectAtCorners_ = 0, secondsTotal_ = 0;
    double peakDirect_ = 0, peakLinking_ = 0, peakRefine_ = 0, peakSolve_ = 0;  // MiB
};

}  // namespace penumbra
