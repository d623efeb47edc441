// Progressive refinement radiosity by shooting (Cohen, Chen, Wallace and Greenberg 1988) with
// ray-traced receiver form factors (Wallace, Elmquist and Haines 1989).
//
// Parameters of the progressive solver (ProgressiveSettings; solver = "progressive"):
//   key                 type    default  meaning
//   patch_edge_length   float   0        longest patch (shooter) edge in m (0 = bounding radius
//                                        / 4)
//   element_area        float   0        largest element (receiver) area in m² (0 = meshed area
//                                        / 4096); at most six levels of 1:4 splits per patch
//   threshold           float   1e-3     stop when the unshot power is below this fraction of
//                                        the initial unshot power
//   max_shots           int     100000   stop after this many shots in any case
//   visibility_samples  int     16       shadow rays per receiver and shot, direct-light samples
//                                        per element; a power of 2 stratifies best
//   adaptive_visibility bool    true     shadow rays in proportion to the unoccluded gain,
//                                        visibility_samples for the largest a receiver has had
//   ambient             bool    true     show CCWG88's ambient term in the preview
#include "radiosity/progressive_solver.h"
#include "core/stats.h"

#include "core/errors.h"
#include "core/scene.h"
#include "radiosity/element_sampling.h"
#include "radiosity/form_factor.h"

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <sstream>
#include <tuple>

namespace penumbra {

namespace {

// Sum of the three channels: the norm that ranks shooters and measures unshot power.
double channelSum(const Color& c) {
    return static_cast<double>(c.r) + c.g + c.b;
}

// Seeds of the samplers, so that visibility and direct-light samples never share a sequence.
constexpr uint32_t kReceiverSeed = 0x27d4eb2fu;
constexpr uint32_t kShooterSeed = 0x9e3779b1u;
constexpr uint32_t kDirectSeed = 0x165667b1u;

// Elements in the scene at the default element area (the meshed area / 4096), before each patch
// rounds it to a whole number of 1:4 splits.
constexpr double kDefaultElementsPerScene = 4096.0;

// The largest mean reflectance the ambient term takes: 1 / (1 - rho_avg) is infinite at 1.
constexpr float kMaxAmbientReflectance = 0.999f;

// A well-mixed hash of a receiver side and a shot (the 64-bit finaliser of MurmurHash3).
size_t hashIndex(size_t receiver, int shot, bool front) {
    uint64_t h = (static_cast<uint64_t>(receiver) << 33) ^ (static_cast<uint64_t>(shot) << 1) ^
                 (front ? 1u : 0u);
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ull;
    h ^= h >> 33;
    return static_cast<size_t>(h);
}

float longestEdge(const std::array<Vec3, 3>& c) {
    return glm::max(glm::distance(c[0], c[1]),
                    glm::max(glm::distance(c[1], c[2]), glm::distance(c[2], c[0])));
}

}  // namespace

MeshingSettings ProgressiveSettings::meshing(const Scene& scene) const {
    MeshingSettings m;
    m.patchEdgeLength = patchEdgeLength > 0.0f
                            ? patchEdgeLength
                            : glm::max(0.25f * scene.bounds().boundingRadius(), 1e-6f);
    // Splits stop at elementArea; a quarter of it lets the last split below it happen. 0 keeps
    // the mesh's own limit, six levels below each patch.
    m.minElementArea = 0.25f * elementArea;
    return m;
}

void validateProgressiveSettings(const ProgressiveSettings& s) {
    const auto fail = [](const std::string& key, const std::string& expected, double got) {
        std::ostringstream out;
        out << "radiosity." << key << ": expected " << expected << ", got " << got;
        throw UsageError(out.str());
    };
    if (!(s.patchEdgeLength >= 0.0f) || !std::isfinite(s.patchEdgeLength))
        fail("patch_edge_length", "a length >= 0", s.patchEdgeLength);
    if (!(s.elementArea >= 0.0f) || !std::isfinite(s.elementArea))
        fail("element_area", "an area >= 0", s.elementArea);
    if (!(s.threshold > 0.0 && s.threshold < 1.0))
        fail("threshold", "a number in (0, 1)", s.threshold);
    if (s.maxShots < 1)
        fail("max_shots", "an integer >= 1", s.maxShots);
    if (s.visibilitySamples < 1 || s.visibilitySamples > 4096)
        fail("visibility_samples", "an integer in [1, 4096]", s.visibilitySamples);
}

ProgressiveSolver::ProgressiveSolver(const Scene& scene, RadiosityMesh& mesh,
                                     const ProgressiveSettings& settings, SolveProgress* progress)
    : scene_(scene), mesh_(mesh), settings_(settings), coincident_(mesh) {
    validateProgressiveSettings(settings_);
    const auto start = std::chrono::steady_clock::now();
    splitToReceiverLevel();
    shootPunctualLights(progress);
    initialPower_ = unshotPower();
    secondsSetup_ = secondsSince(start);
}

Color ProgressiveSolver::emission(int element, bool front) const {
    if (hidden(element, front))
        return Color(0.0f);
    return front || mesh_.twoSided(element) ? mesh_.Le(element) : Color(0.0f);
}

std::pair<int, bool> ProgressiveSolver::shownSide(int element, bool front) const {
    return shownLeafSide(scene_, mesh_, coincident_, element, front,
                         [this](int leaf, bool side) { return !hidden(leaf, side); });
}

// Substructuring: every patch split uniformly to the first level whose elements are no larger
// than the target area (or as far as the mesh allows); the leaves, grouped by patch, receive.
void ProgressiveSolver::splitToReceiverLevel() {
    double meshedArea = 0.0;
    for (size_t p = 0; p < mesh_.patchCount(); ++p)
        meshedArea += mesh_.area(static_cast<int>(p));
    const double target = settings_.elementArea > 0.0f ? settings_.elementArea
                                                       : meshedArea / kDefaultElementsPerScene;
    patchReceivers_.assign(1, 0);
    std::vector<int> stack;
    for (size_t p = 0; p < mesh_.patchCount(); ++p) {
        stack.assign(1, static_cast<int>(p));
        while (!stack.empty()) {
            const int e = stack.back();
            stack.pop_back();
            if (mesh_.isLeaf(e) && mesh_.area(e) > target && mesh_.canSplit(e))
                mesh_.split(e);
            if (mesh_.isLeaf(e)) {
                receivers_.push_back(e);
                continue;
            }
            const int first = mesh_.firstChild(e);
            for (int c = first + RadiosityMesh::kChildren - 1; c >= first; --c)
                stack.push_back(c);
        }
        patchReceivers_.push_back(receivers_.size());
    }
    const auto n = static_cast<size_t>(settings_.visibilitySamples);
    receiverSamples_.resize(receivers_.size() * n);
    gainMax_.assign(2 * receivers_.size(), 0.0f);
    tbb::parallel_for(size_t(0), receivers_.size(), [&](size_t i) {
        stratifiedElementSamples(scene_, mesh_, receivers_[i], kReceiverSeed,
                                 IVec2(receivers_[i], 0),
                                 std::span<ElementSample>(receiverSamples_).subspan(i * n, n));
    });

    const size_t nodes = 2 * mesh_.elementCount();
    L_.assign(nodes, Color(0.0f));
    unshot_.assign(nodes, Color(0.0f));
    unshotLe_.assign(nodes, Color(0.0f));
    direct_.assign(nodes, Color(0.0f));
    patchUnshot_.assign(2 * mesh_.patchCount(), Color(0.0f));

    // The receiver sides that a coincident face hides at their centroid (coincident_faces.h): the
    // side that replaces them there receives, emits and shoots for them.
    hidden_.assign(nodes, 0);
    for (const int r : receivers_) {
        for (const bool front : {true, false}) {
            hidden_[node(r, front)] =
                coincident_.replacementAt(mesh_.patch(r), front, mesh_.centroid(r)) ? 1 : 0;
        }
    }

    // The ambient term's constants: R / sum A with R = 1 / (1 - rho_avg) per channel, each
    // element's area counted once, half of it per side that is not hidden (a doubled wall once).
    Color rhoArea(0.0f);
    for (const int r : receivers_) {
        const int sides = (hidden(r, true) ? 0 : 1) + (hidden(r, false) ? 0 : 1);
        const float area = 0.5f * static_cast<float>(sides) * mesh_.area(r);
        receiverArea_ += area;
        rhoArea += area * mesh_.rho(r);
    }
    if (receiverArea_ > 0.0) {
        const Color rhoAvg =
            glm::min(rhoArea / static_cast<float>(receiverArea_), Color(kMaxAmbientReflectance));
        ambientFactor_ = 1.0f / ((Color(1.0f) - rhoAvg) * static_cast<float>(receiverArea_));
    }
}

// The initial unshot radiance of every receiver side: its emission, plus the punctual lights' and
// the environment's direct light after one reflection, rho D: the point sources are the first
// shooters of CCWG88, all shot at once, with their irradiance sampled over each element as
// RadiositySolver::computeDirect() does (element_sampling.h). rho D is the first part of the
// direct light (elementDirect); the emission's own first shot adds the rest (shoot). A hidden
// side gets nothing; the points of a side hidden elsewhere than at its centroid get nothing
// either (punctualDirect), as the replacing side gets their light.
void ProgressiveSolver::shootPunctualLights(SolveProgress* progress) {
    const std::vector<const Light*> lights = punctualLights(scene_);
    const bool sources = !lights.empty() || scene_.environment();
    const int n = settings_.visibilitySamples;
    if (sources && progress)
        progress->beginStage("direct light of the punctual lights", receivers_.size());
    std::atomic<uint64_t> rays{0};
    parallelForWithProgress(receivers_.size(), sources ? progress : nullptr, [&](size_t i) {
        const int r = receivers_[i];
        const PunctualDirect direct =
            punctualDirect(scene_, mesh_, r, lights, n, kDirectSeed, &coincident_);
        rays += direct.rays;
        for (const bool front : {true, false}) {
            if (hidden(r, front))
                continue;
            const int nd = node(r, front);
            direct_[nd] = mesh_.rho(r) * direct.D[front ? 0 : 1];
            unshotLe_[nd] = emission(r, front);
            L_[nd] = unshotLe_[nd] + direct_[nd];
            unshot_[nd] = L_[nd];
        }
    });
    if (sources && progress)
        progress->endStage(std::to_string(receivers_.size()) + " elements");
    rays_ += rays;
    for (size_t p = 0; p < mesh_.patchCount(); ++p)
        sumUnshot(static_cast<int>(p));
}

void ProgressiveSolver::sumUnshot(int patch) {
    for (const bool front : {true, false}) {
        double sum[3] = {0.0, 0.0, 0.0};
        for (size_t i = patchReceivers_[patch]; i < patchReceivers_[patch + 1]; ++i) {
            const int r = receivers_[i];
            const Color& dL = unshot_[node(r, front)];
            for (int c = 0; c < 3; ++c)
                sum[c] += static_cast<double>(mesh_.area(r)) * dL[c];
        }
        patchUnshot_[node(patch, front)] = Color(sum[0], sum[1], sum[2]);
    }
}

double ProgressiveSolver::unshotPower() const {
    double power = 0.0;
    for (const Color& u : patchUnshot_)
        power += kPi * channelSum(u);
    return power;
}

double ProgressiveSolver::unshotFraction() const {
    return initialPower_ > 0.0 ? unshotPower() / initialPower_ : 0.0;
}

Color ProgressiveSolver::ambient() const {
    Color sum(0.0f);
    for (const Color& u : patchUnshot_)
        sum += u;
    return ambientFactor_ * sum;
}

// CCWG88: the shooter is the source with the largest unshot power, pi A dL (the largest
// contribution to the solution comes first).
int ProgressiveSolver::selectShooter() const {
    int best = -1;
    double most = 0.0;
    for (size_t n = 0; n < patchUnshot_.size(); ++n) {
        const double power = channelSum(patchUnshot_[n]);
        if (power > most) {
            most = power;
            best = static_cast<int>(n);
        }
    }
    return best;
}

// What a receiver side gains from a shooter side with unshot radiance dL, by the reciprocity of
// form factors: dL_r = rho_r F(r -> s) V dL_s (CCWG88's shooting step, "dRad = rho_j dB_i
// F_ji A_i / A_j = rho_j dB_i F_ij", in radiance). F(r -> s) is the exact point-to-polygon form
// factor from the receiver's centroid (Wallace et al. 1989 evaluate it at the receiving points;
// exact here instead of their disc approximation), V the visible fraction between the two.
ProgressiveSolver::Gain ProgressiveSolver::receive(size_t i, bool receiverFront, const Shot& shot,
                                                   uint64_t& rays) {
    const int r = receivers_[i];
    if (hidden(r, receiverFront))
        return {};  // the side that replaces it receives for it
    const int shooter = shot.patch;
    const std::array<Vec3, 3> cs = mesh_.corners(shooter);
    const Vec3 ns = shot.front ? mesh_.normal(shooter) : -mesh_.normal(shooter);
    const Vec3 nr = receiverFront ? mesh_.normal(r) : -mesh_.normal(r);
    const Vec3 x = mesh_.centroid(r);
    // The shooter is one-sided: the receiver must lie in front of it (a tolerance of 1e-5 of its
    // size absorbs the rounding of coplanar neighbours). pointToPolygonFormFactor() clips the
    // shooter to the receiver's side itself; the corner test only saves its cost.
    if (!(glm::dot(ns, x - cs[0]) > 1e-5f * longestEdge(cs)))
        return {};
    if (std::none_of(cs.begin(), cs.end(),
                     [&](const Vec3& c) { return glm::dot(nr, c - x) > 0.0f; })) {
        return {};
    }
    const auto F = static_cast<float>(pointToPolygonFormFactor(x, nr, cs));
    if (!(F > 0.0f))
        return {};
    // The unoccluded gain G, and the number of shadow rays m: all of them for the largest gain
    // this receiver side has had, in proportion to G for smaller ones, rounded up to a power of 2
    // so that the first m points of both sets stay stratified. m proportional to G is the
    // allocation of rays over the shots that minimises the variance of the sum, sum_k G_k^2 /
    // (4 m_k), for a given number of rays; it bounds that variance by G_max L / (4 n) (L the
    // reflected radiance, the sum of the G_k), against at least G_max^2 / (4 n) for the first shot
    // alone: it spends the rays where the light is.
    const Gain source = sourceRadiance(x, nr, ns, shot);
    const Color gain = mesh_.rho(r) * F * source.all;
    const size_t n = shot.samples.size();
    size_t m = n;
    if (settings_.adaptiveVisibility) {
        float& gainMax = gainMax_[2 * i + (receiverFront ? 0 : 1)];
        const float G = maxComponent(gain);
        gainMax = glm::max(gainMax, G);
        const auto wanted = static_cast<size_t>(std::ceil(static_cast<float>(n) * G / gainMax));
        m = std::min(n, std::bit_ceil(std::max<size_t>(wanted, 1)));
    }
    // Which block of m points: the points [b m, (b + 1) m) of a (0,2)-sequence are stratified
    // like its first m (a (0,2)-sequence is a (0,m,2)-net in every such block), and a block that
    // varies with the receiver keeps the receivers of one shot from sharing their few shooter
    // points, whose error would then not average out over the scene.
    const size_t b = hashIndex(i, shots_, receiverFront) % (n / m);
    const Color V = meanTransmittance(
        scene_, std::span<const ElementSample>(receiverSamples_).subspan(i * n + b * m, m),
        std::span<const ElementSample>(shot.samples).subspan(b * m, m));
    rays += m;
    return {gain * V, mesh_.rho(r) * F * source.emitted * V};
}

// The unshot radiance the receiver point x (normal nr) gets from the shot: not the patch's mean
// but its elements' dL, each weighted by its share of the form factor, estimated by the disc
// approximation (form_factor.h; Wallace et al. 1989) at x, w_e = F_disc(x -> e) / sum F_disc.
// The exact F multiplies it, so the weights only spread F over the patch: where the shooter's
// unshot light varies (a shadow across it), a receiver close to its dark part gets less than the
// mean. RadiositySolver weighs a link's source children in the same way (setSourceWeights).
// Measured against the dense solve of tests/radiosity/progressive_radiosity_test.cpp (16 elements
// per patch): the mean difference of an element side drops from 0.78 % to 0.67 % of the mean
// radiance. The patch mean is the fallback when no element is seen.
//
// The emission in the shot (dLe) is weighed in the same way: the shot is linear in dL, so that the
// emitted part of a gain is the gain of the emitted part.
ProgressiveSolver::Gain ProgressiveSolver::sourceRadiance(const Vec3& x, const Vec3& nr,
                                                          const Vec3& ns, const Shot& shot) const {
    if (shot.elements.size() < 2)
        return {shot.dL, shot.dLe};
    Gain sum;
    double weight = 0.0;
    for (const ShooterElement& e : shot.elements) {
        const double w = diskApproximationFormFactor(x, nr, e.centroid, ns, e.area);
        sum.all += static_cast<float>(w) * e.dL;
        sum.emitted += static_cast<float>(w) * e.dLe;
        weight += w;
    }
    if (!(weight > 0.0))
        return {shot.dL, shot.dLe};
    return {sum.all / static_cast<float>(weight), sum.emitted / static_cast<float>(weight)};
}

void ProgressiveSolver::shoot(int shooterNode) {
    Shot shot;
    shot.patch = shooterNode / 2;
    shot.front = shooterNode % 2 == 0;
    shot.dL = patchUnshot_[shooterNode] / mesh_.area(shot.patch);
    // The emission goes out with the first shot of its side, and only then: that shot's gains
    // from it are the direct light (paths L D), everything shot later is reflected light.
    for (size_t i = patchReceivers_[shot.patch]; i < patchReceivers_[shot.patch + 1]; ++i) {
        const int e = receivers_[i];
        Color& dL = unshot_[node(e, shot.front)];
        Color& dLe = unshotLe_[node(e, shot.front)];
        shot.elements.push_back({mesh_.centroid(e), mesh_.area(e), dL, dLe});
        shot.dLe += mesh_.area(e) * dLe;
        dL = Color(0.0f);
        dLe = Color(0.0f);
    }
    shot.dLe /= mesh_.area(shot.patch);
    patchUnshot_[shooterNode] = Color(0.0f);

    // One set of stratified points on the shooter per shot, which every receiver pairs with its
    // own (Wallace et al. 1989 sample the source once per shot); a new set for each shot of the
    // patch, so that its successive shots average their visibility errors out.
    shot.samples.resize(static_cast<size_t>(settings_.visibilitySamples));
    stratifiedElementSamples(scene_, mesh_, shot.patch, kShooterSeed, IVec2(shot.patch, shots_),
                             shot.samples);

    // Patch by patch, so that each task owns its receivers and their patch's sums.
    tbb::combinable<uint64_t> rays([] { return uint64_t(0); });
    tbb::parallel_for(size_t(0), mesh_.patchCount(), [&](size_t p) {
        const int patch = static_cast<int>(p);
        if (patch == shot.patch)
            return;  // a patch is planar: it sees nothing of itself
        bool received = false;
        for (size_t i = patchReceivers_[p]; i < patchReceivers_[p + 1]; ++i) {
            const int r = receivers_[i];
            for (const bool front : {true, false}) {
                const Gain gain = receive(i, front, shot, rays.local());
                if (maxComponent(gain.all) > 0.0f) {
                    L_[node(r, front)] += gain.all;
                    unshot_[node(r, front)] += gain.all;
                    direct_[node(r, front)] += gain.emitted;
                    received = true;
                }
            }
        }
        if (received)
            sumUnshot(patch);
    });
    rays_ += rays.combine([](uint64_t a, uint64_t b) { return a + b; });
    ++shots_;
}

bool ProgressiveSolver::step(int shots) {
    const auto start = std::chrono::steady_clock::now();
    for (int k = 0; k < shots && !finished(); ++k) {
        const int shooter = selectShooter();
        if (shooter < 0)
            break;
        shoot(shooter);
    }
    secondsShooting_ += secondsSince(start);
    return finished();
}

// The shooting stage's progress: the unshot power's way down on a log scale, from 1 to the
// threshold (it falls roughly geometrically, so the bar moves at a steady rate), or the share of
// max_shots made, whichever is further.
void ProgressiveSolver::solve(SolveProgress* progress) {
    constexpr uint64_t kUnits = 1000;
    if (progress)
        progress->beginStage("shooting", kUnits);
    uint64_t reported = 0;
    bool done = finished();
    while (!done) {
        done = step(1);
        if (!progress)
            continue;
        const double unshot = unshotFraction();
        double f = unshot > 0.0 ? std::log(unshot) / std::log(settings_.threshold) : 1.0;
        f = std::clamp(std::max(f, static_cast<double>(shots_) / settings_.maxShots), 0.0, 1.0);
        const auto units = done ? kUnits : static_cast<uint64_t>(f * kUnits);
        if (units > reported) {
            progress->advance(units - reported);
            reported = units;
        }
    }
    if (progress) {
        std::ostringstream summary;
        summary.precision(3);
        summary << shots_ << " shots, unshot fraction " << unshotFraction()
                << (converged() ? "" : ", not converged");
        progress->endStage(summary.str());
        progress->beginStage("vertex values", 0);
    }
    updateVertexValues();
    if (progress)
        progress->endStage(std::to_string(mesh_.vertexCount()) + " vertices");
}

Color ProgressiveSolver::elementIndirect(int e, bool front) const {
    const int n = node(e, front);
    return glm::max(L_[n] - emission(e, front) - direct_[n], Color(0.0f));
}

void ProgressiveSolver::updateVertexValues() {
    const Color ambientL = settings_.ambient ? ambient() : Color(0.0f);
    // A hidden side shows the light of the side that replaces it.
    vertexIndirect_.compute(mesh_, [&](int e, bool front) {
        std::tie(e, front) = shownSide(e, front);
        return elementIndirect(e, front) + mesh_.rho(e) * ambientL;
    });
    // The whole reflected radiance last, so that the mesh is left with its front's values.
    vertexDisplayed_.compute(mesh_, [&](int e, bool front) {
        std::tie(e, front) = shownSide(e, front);
        return glm::max(L_[node(e, front)] - emission(e, front), Color(0.0f)) +
               mesh_.rho(e) * ambientL;
    });
}

Color ProgressiveSolver::radiance(uint32_t mesh, uint32_t triangle, Vec3 b, bool includeEmission,
                                  bool front) const {
    const ElementPoint point = mesh_.locate(mesh, triangle, b);
    if (point.element < 0 || vertexDisplayed_.empty())
        return Color(0.0f);
    Color L = vertexDisplayed_.interpolate(mesh_, point, front);
    if (!includeEmission)
        return L;
    // A hidden side shows the replacing side's emission too.
    const auto [e, side] = shownSide(point.element, front);
    return L + emission(e, side);
}

Color ProgressiveSolver::indirectRadiance(uint32_t mesh, uint32_t triangle, Vec3 b,
                                          bool front) const {
    return vertexIndirect_.interpolate(mesh_, mesh_.locate(mesh, triangle, b), front);
}

PassStats ProgressiveSolver::stats() const {
    // The reflected luminous flux of each part, pi sum A Y(L) over the receiver sides (lm).
    double directFlux = 0.0, indirectFlux = 0.0;
    for (const int r : receivers_) {
        for (const bool front : {true, false}) {
            directFlux += kPi * mesh_.area(r) * luminance(elementDirect(r, front));
            indirectFlux += kPi * mesh_.area(r) * luminance(elementIndirect(r, front));
        }
    }
    return {{"patches", std::to_string(mesh_.patchCount())},
            {"elements", std::to_string(receivers_.size())},
            {"coincident_patches", std::to_string(coincident_.hiddenPatches())},
            {"coincident_area_m2", formatStat(coincident_.hiddenArea())},
            {"shots", std::to_string(shots_)},
            {"rays", std::to_string(rays_)},
            {"unshot_fraction", formatStat(unshotFraction())},
            {"converged", converged() ? "yes" : "no"},
            {"direct_flux_lm", formatStat(directFlux)},
            {"indirect_flux_lm", formatStat(indirectFlux)},
            {"seconds_setup", formatStat(secondsSetup_)},
            {"seconds_shooting", formatStat(secondsShooting_)},
            {"seconds", formatStat(secondsSetup_ + secondsShooting_)}};
}

}  // namespace penumbra
