// Progressive refinement radiosity (Cohen, Chen, Wallace and Greenberg 1988, "A Progressive
// Refinement Approach to Fast Radiosity Image Generation", SIGGRAPH '88; "CCWG88" below) on a
// RadiosityMesh split to a uniform element level: the patch side with the most unshot power
// shoots it to every element, until the unshot power is a small fraction of what entered.
//
// What the solution contains is what RadiositySolver's contains (radiosity_solver.h): for every
// element side, the radiance leaving it (cd/m² per linear-sRGB channel) = Le + the diffusely
// reflected light of the bounces shot so far (rho = Bsdf::diffuseGlossyReflectance), the punctual
// lights' direct light included; both sides reflect with the same rho, the back emits only for a
// two-sided material, thin glass passes shadow rays with its transmittance. It approximates the
// same equation, L_i = Le_i + rho_i (D_i + sum_j F_ij V_ij L_j), from below: every shot adds
// light, and what is missing is the future interreflection of the unshot power U, at most
// U rho_max / (1 - rho_max) of reflected flux. The first reflection of the sources (paths L D E)
// is kept apart for indirectRadiance(): the punctual lights' rho D, and what each patch side's
// first shot carries of its own emission (an emitter shoots its emission once, in its first shot).
// Where two faces lie on each other in the same plane (coincident_faces.h), each side of the
// surface belongs to one of them, as in RadiositySolver: an element side hidden at its centroid by
// a coincident patch neither receives nor shoots, has no emission of its own (the replacing side
// carries it: an emitter wins over a non-emitter), and shows the replacing side's light, its
// emission included (radiance(), indirectRadiance()).
//
// Substructuring (Cohen, Greenberg, Immel and Brock 1986, "An Efficient Radiosity Approach for
// Realistic Image Synthesis"): the shooters are the mesh's patches, each with the unshot radiance
// of its elements (their area mean ranks the shooters; each receiver weighs the elements by their
// share of its form factor); the receivers are the elements, split below every patch to the
// level that makes them no larger than ProgressiveSettings::elementArea.
//
// Receiver form factors (Wallace, Elmquist and Haines 1989, "A Ray Tracing Algorithm for
// Progressive Radiosity", SIGGRAPH '89): the exact point-to-polygon form factor from the
// receiver's centroid to the shooting patch (form_factor.h), times the visible fraction estimated
// by shadow rays between stratified points of the receiver and of the shooter
// (element_sampling.h), as many as the light the shot brings the receiver warrants.
#pragma once

#include "core/math.h"
#include "core/stats.h"
#include "radiosity/coincident_faces.h"
#include "radiosity/element_sampling.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_solution.h"
#include "radiosity/solve_progress.h"
#include "radiosity/vertex_values.h"

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace penumbra {

class Scene;

// The parameters of the progressive solver; their table (key, type, default, meaning) is at the
// top of progressive_solver.cpp.
struct ProgressiveSettings {
    // Longest patch edge (shooter size), metres; 0 = 1/4 of the scene's bounding radius.
    float patchEdgeLength = 0.0f;
    // Largest element (receiver) area, m²; 0 = the meshed area / 4096. Every patch is split to the
    // first level whose elements are no larger, at most six levels below the patch.
    float elementArea = 0.0f;
    // Stop when the unshot power is below this fraction of the initial unshot power (emission
    // plus the first reflection of the punctual lights).
    double threshold = 1e-3;
    int maxShots = 100000;
    // Shadow rays per receiver and shot (the most, with adaptiveVisibility), and direct-light
    // samples per element.
    int visibilitySamples = 16;
    // Spend fewer rays on the shots that bring a receiver less light: in proportion to the
    // unoccluded gain, all visibilitySamples for the largest gain the receiver side has had.
    bool adaptiveVisibility = true;
    // Add CCWG88's ambient term to radiance() (the display; never to the solution itself).
    bool ambient = true;

    // The mesh settings these stand for, with the defaults resolved for `scene`.
    MeshingSettings meshing(const Scene& scene) const;
};

// Throws UsageError naming the key ("radiosity.threshold: expected ...") for a value out of range.
void validateProgressiveSettings(const ProgressiveSettings& settings);

class ProgressiveSolver : public RadiositySolution {
  public:
    // Splits the mesh's patches to the uniform element level and shoots the punctual lights
    // (their direct light into every element, the first step of CCWG88 with point sources).
    // The scene and the mesh, made with settings.meshing(scene), must outlive the solver; the
    // mesh must not be split by anyone else afterwards. Throws UsageError for bad settings.
    // Reports the punctual lights' stage to `progress` if given (solve_progress.h).
    ProgressiveSolver(const Scene& scene, RadiosityMesh& mesh, const ProgressiveSettings& settings,
                      SolveProgress* progress = nullptr);

    // Performs up to `shots` shots; returns finished().
    bool step(int shots = 1);
    // Steps until finished(), then updateVertexValues(). Reports the shooting and the vertex
    // values as stages to `progress` if given.
    void solve(SolveProgress* progress = nullptr);
    // The unshot power is below the threshold (converged()) or maxShots were made.
    bool finished() const { return converged() || shots_ >= settings_.maxShots; }
    bool converged() const { return unshotFraction() < settings_.threshold; }

    // Computes the per-vertex values radiance() interpolates, from the current solution and
    // ambient term: solve() calls it at the end; a caller showing a preview calls it after step().
    // Leaves the mesh's setElementValues() at the front side's displayed reflected radiance.
    void updateVertexValues();
    // RadiositySolution: the values of the last updateVertexValues(), with rho times ambient()
    // added to the reflected part if ProgressiveSettings::ambient. Zero before the first call. A
    // side hidden by a coincident face shows the replacing side's light, emission included.
    Color radiance(uint32_t mesh, uint32_t triangle, Vec3 b, bool includeEmission,
                   bool front = true) const override;
    // RadiositySolution: the values of the last updateVertexValues() of elementIndirect(), with
    // rho times ambient() added if ProgressiveSettings::ambient (the ambient term stands for
    // interreflection still to come, which is indirect once every source has shot).
    Color indirectRadiance(uint32_t mesh, uint32_t triangle, Vec3 b,
                           bool front = true) const override;

    // The element side's own (flat) radiance received so far, emission included, no ambient
    // term; zero for an element above the receiver level, and for a side hidden by a coincident
    // face (its light is the replacing side's), as are the next two.
    Color elementRadiance(int element, bool front = true) const { return L_[node(element, front)]; }
    // Its first reflection of the sources' light so far, rho D plus what each source's first
    // shot of its own emission brought (paths L D E), and the rest of its reflected light,
    // max(0, L - Le - direct) (paths L D D+ E); no ambient term in either.
    Color elementDirect(int element, bool front = true) const {
        return direct_[node(element, front)];
    }
    Color elementIndirect(int element, bool front = true) const;
    // The ambient radiance of CCWG88: the unshot power spread evenly over the scene and
    // interreflected with the mean reflectance, R sum_j A_j dL_j / sum_j A_j, with
    // R = 1 / (1 - rho_avg) and rho_avg the area-weighted mean reflectance, per channel. The scene
    // is taken as CCWG88's enclosure of one-sided surfaces: the sums run over both sides' unshot
    // radiance but count each element's area once, half of it for each side that a coincident
    // face does not hide (a wall modelled twice counts once). An element side shows
    // L + rho ambient; the term tends to 0 with the unshot power.
    Color ambient() const;

    // Luminous flux leaving the element sides, sum of pi A L (lm), the three channels summed.
    double unshotPower() const;
    double initialPower() const { return initialPower_; }
    // unshotPower() / initialPower(); 0 when nothing emits.
    double unshotFraction() const;
    int shots() const { return shots_; }
    // Shadow rays traced so far (punctual lights and shots).
    uint64_t rays() const { return rays_; }
    // The leaves receiving the shots, all at their patch's uniform level.
    const std::vector<int>& receivers() const { return receivers_; }

    // patches, elements (receivers), coincident patches (with a side hidden somewhere by a
    // coincident face) and their area, shots, rays, unshot fraction, converged, seconds per stage
    // (setup: splitting and the punctual lights; shooting) and in all, and the reflected luminous
    // flux (pi sum_i A_i Y(L_i) over receiver sides, lm) of the direct and of the indirect part.
    PassStats stats() const override;

  private:
    // Nodes are element sides, as in RadiositySolver: node 2e is the front of element e, 2e + 1
    // its back.
    static int node(int element, bool front) { return 2 * element + (front ? 0 : 1); }
    // The element side's own emission: Le on the front, and on the back of a two-sided material;
    // none on a hidden side.
    Color emission(int element, bool front) const;
    // Whether a coincident face hides the receiver side at its centroid (hidden_).
    bool hidden(int element, bool front) const { return hidden_[node(element, front)] != 0; }
    // The leaf side whose light a receiver side shows: itself, or where it is hidden, the
    // replacing side's leaf under its centroid (shownLeafSide, coincident_faces.h).
    std::pair<int, bool> shownSide(int element, bool front) const;

    void splitToReceiverLevel();
    void shootPunctualLights(SolveProgress* progress);
    // The patch side with the most unshot power, -1 if none has any.
    int selectShooter() const;
    void shoot(int shooter);
    // What a shot shoots: the patch side, its elements' unshot radiance and the sample points
    // on it for visibility.
    struct ShooterElement {
        Vec3 centroid;
        float area;
        Color dL;
        Color dLe;  // the part of dL that is its own emission, shot for the first time
    };
    // What a receiver point gets from a shot, in all and from the emission in it.
    struct Gain {
        Color all{0.0f}, emitted{0.0f};
    };
    struct Shot {
        int patch = -1;
        bool front = true;
        Color dL{0.0f};   // the area mean of the elements' dL
        Color dLe{0.0f};  // and of their dLe
        std::vector<ShooterElement> elements;
        std::vector<ElementSample> samples;
    };
    // The shooter's unshot radiance as seen from receiver point x (normal nr); ns: the shooting
    // side's normal.
    Gain sourceRadiance(const Vec3& x, const Vec3& nr, const Vec3& ns, const Shot& shot) const;
    // The radiance the side of receiver i (receivers_[i]) gains from the shot, rho F V dL, and
    // the part of it that the shooter's emission brings, rho F V dLe.
    Gain receive(size_t i, bool receiverFront, const Shot& shot, uint64_t& rays);
    // Recomputes the patch side's unshot sum from its elements.
    void sumUnshot(int patch);

    const Scene& scene_;
    RadiosityMesh& mesh_;
    ProgressiveSettings settings_;
    CoincidentFaces coincident_;

    std::vector<int> receivers_;          // leaves, grouped by patch
    std::vector<size_t> patchReceivers_;  // receivers of patch p: [patchReceivers_[p], [p + 1])
    // visibilitySamples stratified points per receiver, fixed for the whole solution.
    std::vector<ElementSample> receiverSamples_;
    std::vector<float> gainMax_;      // per receiver side: the largest unoccluded gain so far
    std::vector<uint8_t> hidden_;     // per node of a receiver: hidden at its centroid (1)
    std::vector<Color> L_;            // per node: radiance leaving, emission included
    std::vector<Color> unshot_;       // per node of a receiver: radiance not yet shot
    std::vector<Color> unshotLe_;     // per node of a receiver: emission not yet shot
    std::vector<Color> direct_;       // per node of a receiver: elementDirect()
    std::vector<Color> patchUnshot_;  // per patch node: sum of A dL over its receivers
    double initialPower_ = 0.0;
    double receiverArea_ = 0.0;         // sum of the receivers' areas, each counted once
    Color ambientFactor_{0.0f};         // R / sum A of the ambient term, per channel
    SideVertexValues vertexDisplayed_;  // the displayed reflected radiance, per side and vertex
    SideVertexValues vertexIndirect_;   // its indirect part, displayed
    int shots_ = 0;
    uint64_t rays_ = 0;
    double secondsSetup_ = 0.0, secondsShooting_ = 0.0;
};

}  // namespace penumbra
