// Hierarchical radiosity: HSA91's Refine / Link / GatherRad / PushPullRad, with an error-based
// refinement oracle, a linear push and links carrying form factor times visibility.
//
// Parameters of the radiosity pass (RadiositySettings):
//   key                 type    default         meaning
//   solver              string  "hierarchical"  solution method (only "hierarchical" so far)
//   epsilon             float   0.01            refinement threshold: largest error a link may
//                                               make, relative to the scene's mean radiance
//   patch_edge_length   float   0               longest patch edge in m (0 = bounding radius)
//   min_element_area    float   0               smallest element in m² (0 = total area / 16384)
//   convergence         float   1e-4            stop when the estimated relative error of the
//                                               gather iteration is below this
//   visibility_samples  int     16              shadow rays per link and direct-light samples per
//                                               element; a power of 2 stratifies best
//   max_iterations      int     5000            gather sweeps, all rounds together
//   max_refinements     int     8               refinement rounds after the first solve
//   iteration           string  "gauss-seidel"  gather order: gauss-seidel (patch by patch,
//                                               pushing and pulling each tree at once) or jacobi
#include "radiosity/radiosity_solver.h"

#include "core/errors.h"
#include "core/sampler.h"
#include "core/sampling.h"
#include "core/scene.h"
#include "radiosity/form_factor.h"

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

namespace penumbra {

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Sum of the three channels, the norm the convergence test uses per element.
double channelSum(const Color& c) {
    return static_cast<double>(c.r) + c.g + c.b;
}

std::string format(double value) {
    std::ostringstream out;
    out.precision(4);
    out << value;
    return out.str();
}

// Seeds of the samplers, so that visibility and direct-light samples never share a sequence.
constexpr uint32_t kVisibilitySeed = 0x9e3779b9u;
constexpr uint32_t kDirectSeed = 0x85ebca6bu;

// Threshold of the intermediate solves between refinement rounds: the oracle only needs the
// radiance to a few percent.
constexpr double kRoundConvergence = 2e-2;

}  // namespace

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
}

RadiositySolver::RadiositySolver(const Scene& scene, RadiosityMesh& mesh,
                                 const RadiositySettings& settings)
    : scene_(scene), mesh_(mesh), settings_(settings) {
    validateRadiositySettings(settings_);
    resizeArrays();
}

void RadiositySolver::resizeArrays() {
    const size_t nodes = 2 * mesh_.elementCount();
    L_.resize(nodes, Color(0.0f));
    Lmin_.resize(nodes, 0.0f);
    Lmax_.resize(nodes, 0.0f);
    H_.resize(nodes, Color(0.0f));
    G_.resize(nodes, Mat3(0.0f));
    D_.resize(nodes, Color(0.0f));
    Dspread_.resize(nodes, 0.0f);
    links_.resize(nodes);
}

size_t RadiositySolver::linkCount() const {
    size_t count = 0;
    for (const auto& links : links_)
        count += links.size();
    return count;
}

// --- Geometry of element sides -------------------------------------------------------------

namespace {

// The element's corners ordered counter-clockwise seen from the given side, so that the
// one-sided form factors of form_factor.h see that side as the front.
std::array<Vec3, 3> sideCorners(const RadiosityMesh& mesh, int element, bool front) {
    std::array<Vec3, 3> c = mesh.corners(element);
    if (!front)
        std::swap(c[1], c[2]);
    return c;
}

float longestEdge(const std::array<Vec3, 3>& c) {
    return glm::max(glm::distance(c[0], c[1]),
                    glm::max(glm::distance(c[1], c[2]), glm::distance(c[2], c[0])));
}

// A point on an element, with what a shadow ray needs to leave it robustly.
struct ElementSample {
    Vec3 p, pError, n;
};

// The point with uniform-map coordinates u on the element, placed as a ray hit there would be
// (Scene::surfaceAt), with its error bound for robust shadow rays.
ElementSample sampleElement(const Scene& scene, const RadiosityMesh& mesh, int element, Vec2 u) {
    const Vec3 w = sampleUniformTriangle(u);
    const auto& corners = mesh.barycentrics(element);
    const SurfaceHit hit = scene.surfaceAt(mesh.sceneMesh(element), mesh.sceneTriangle(element),
                                           w.x * corners[0] + w.y * corners[1] + w.z * corners[2]);
    return {hit.p, hit.pError, mesh.normal(element)};
}

}  // namespace

bool RadiositySolver::mayInteract(int receiver, int source) const {
    const int er = element(receiver), es = element(source);
    // Elements of one patch lie in one plane and see nothing of each other.
    if (mesh_.patch(er) == mesh_.patch(es))
        return false;
    const auto cr = mesh_.corners(er), cs = mesh_.corners(es);
    const Vec3 nr = front(receiver) ? mesh_.normal(er) : -mesh_.normal(er);
    const Vec3 ns = front(source) ? mesh_.normal(es) : -mesh_.normal(es);
    // Some corner of each must lie strictly in front of the other's side (a tolerance of 1e-5
    // of the elements' size absorbs the rounding of coplanar neighbours).
    const float tolerance = 1e-5f * glm::max(longestEdge(cr), longestEdge(cs));
    const auto anyInFront = [tolerance](const std::array<Vec3, 3>& corners, const Vec3& origin,
                                        const Vec3& n) {
        for (const Vec3& c : corners) {
            if (glm::dot(n, c - origin) > tolerance)
                return true;
        }
        return false;
    };
    return anyInFront(cs, cr[0], nr) && anyInFront(cr, cs[0], ns);
}

// The accurate unoccluded form factor of a link: the area average over the receiver of the exact
// point-to-polygon value (form_factor.h). The quadrature order follows the distance between the
// elements relative to their size; measured against order 24 on random triangle pairs, order 4
// is within 2e-5 from a centroid distance of twice the longer edge, order 6 within 2e-7 from one
// edge; closer (adjacent) pairs take order 10, within 2e-4 for triangles sharing an edge at any
// angle, where the integrand is only Lipschitz.
float RadiositySolver::formFactor(int receiver, int source) const {
    const auto cr = sideCorners(mesh_, element(receiver), front(receiver));
    const auto cs = sideCorners(mesh_, element(source), front(source));
    const float size = glm::max(longestEdge(cr), longestEdge(cs));
    const float distance =
        glm::distance((cr[0] + cr[1] + cr[2]) / 3.0f, (cs[0] + cs[1] + cs[2]) / 3.0f);
    const int order = distance >= 2.0f * size ? 4 : distance >= size ? 6 : 10;
    return static_cast<float>(areaToAreaFormFactor(cr, cs, order));
}

// Point values of the unoccluded form factor F(x -> source) at the receiver's corners and
// centroid, for the oracle and the linear push.
RadiositySolver::KernelSamples RadiositySolver::kernelSamples(int receiver, int source) const {
    const int er = element(receiver), es = element(source);
    const Vec3 nr = front(receiver) ? mesh_.normal(er) : -mesh_.normal(er);
    const Vec3 ns = front(source) ? mesh_.normal(es) : -mesh_.normal(es);
    const auto cr = mesh_.corners(er);
    const auto cs = mesh_.corners(es);
    // pointToPolygonFormFactor() is two-sided in the polygon: a point behind the source side sees
    // nothing of it.
    const auto F = [&](const Vec3& x) {
        return glm::dot(ns, x - cs[0]) > 0.0f
                   ? static_cast<float>(pointToPolygonFormFactor(x, nr, cs))
                   : 0.0f;
    };
    return {{F(cr[0]), F(cr[1]), F(cr[2])},
            {F(0.5f * (cr[0] + cr[1])), F(0.5f * (cr[1] + cr[2])), F(0.5f * (cr[2] + cr[0]))},
            F((cr[0] + cr[1] + cr[2]) / 3.0f)};
}

// The linear model of a link's form factor over its receiver (see Link::g): the plane through
// the corner values, moved to have the link's exact mean F, its slope scaled down by the largest
// t in [0, 1] that keeps it non-negative at the corners (and so everywhere on the receiver).
// Returns the relative gradient and sets `limiter` to t.
Vec3 RadiositySolver::linearModel(int receiver, const KernelSamples& k, float F,
                                  float& limiter) const {
    limiter = 1.0f;
    const float mean = k.cornerMean();
    for (const float f : k.corner) {
        if (f < mean)
            limiter = glm::min(limiter, F / (mean - f));
    }
    // Gradient of the linear interpolant of values f_i at corners p_i: with e1 = p1 - p0,
    // e2 = p2 - p0 and m = e1 x e2, grad = ((f1 - f0) e2 x m + (f2 - f0) m x e1) / |m|^2.
    const auto c = mesh_.corners(element(receiver));
    const Vec3 e1 = c[1] - c[0], e2 = c[2] - c[0];
    const Vec3 m = glm::cross(e1, e2);
    const Vec3 gradient = ((k.corner[1] - k.corner[0]) * glm::cross(e2, m) +
                           (k.corner[2] - k.corner[0]) * glm::cross(m, e1)) /
                          glm::dot(m, m);
    return gradient * (limiter / F);
}

// Visible fraction between two element sides: the mean transmittance of n shadow rays between
// paired points of the two elements. The points are stratified: sample k on each element is point
// k of an Owen-scrambled (0,2)-sequence (core/sampler.h) mapped to the triangle by Heitz's
// area-preserving map, and the two elements use independently scrambled dimensions, so the pairs
// are decorrelated (HSA91 estimate visibility in the same way, by rays between jittered points of
// the two elements; Cohen and Wallace 1993, chapter 4). Thin glass transmits, as everywhere in
// penumbra.
Color RadiositySolver::visibility(int receiver, int source) const {
    const int n = settings_.visibilitySamples;
    Sampler sampler(kVisibilitySeed);
    const int er = element(receiver), es = element(source);
    Color sum(0.0f);
    for (int k = 0; k < n; ++k) {
        sampler.startPixelSample(IVec2(receiver, source), static_cast<uint32_t>(k));
        const ElementSample x = sampleElement(scene_, mesh_, er, sampler.get2D());
        const ElementSample y = sampleElement(scene_, mesh_, es, sampler.get2D());
        sum += scene_.transmittance(x.p, x.pError, x.n, y.p, y.pError, y.n);
    }
    return sum / static_cast<float>(n);
}

// --- Direct light of the punctual lights ---------------------------------------------------

// For each element: the irradiance of every delta light (point, spot, directional) at n
// stratified points with one shadow ray each, E = L_i |cos theta| T (pbrt-v4's direct lighting
// for delta lights), divided by pi, on the side facing the light; its mean is the element's D and
// its spread (max - min over the points) what refineDirect() weighs. rho D is the reflected
// radiance of the Lambertian element: the punctual lights "shoot" into the elements before the
// gather starts (as the sources of the first step of progressive radiosity, Cohen, Chen, Wallace
// and Greenberg 1988).
void RadiositySolver::computeDirect(const std::vector<int>& elements) {
    std::vector<const Light*> lights;
    for (const auto& light : scene_.lights()) {
        if (light->isDelta())
            lights.push_back(light.get());
    }
    if (lights.empty() || elements.empty())
        return;
    const int n = settings_.visibilitySamples;
    tbb::parallel_for(size_t(0), elements.size(), [&](size_t i) {
        const int e = elements[i];
        Sampler sampler(kDirectSeed);
        // Per side: sum, smallest and largest max-channel value over the points.
        std::array<Color, 2> sum{Color(0.0f), Color(0.0f)};
        std::array<float, 2> lo{INFINITY, INFINITY}, hi{0.0f, 0.0f};
        for (int k = 0; k < n; ++k) {
            sampler.startPixelSample(IVec2(e, 0), static_cast<uint32_t>(k));
            const ElementSample x = sampleElement(scene_, mesh_, e, sampler.get2D());
            std::array<Color, 2> E{Color(0.0f), Color(0.0f)};
            for (const Light* light : lights) {
                const LightSampleContext ctx{x.p, x.pError, x.n};
                const std::optional<LightLiSample> ls = light->sampleLi(ctx, Vec2(0.5f));
                if (!ls)
                    continue;
                const float cosTheta = glm::dot(ls->wi, x.n);
                if (cosTheta == 0.0f)
                    continue;
                const Color T = scene_.transmittance(x.p, x.pError, x.n, ls->pLight,
                                                     ls->pLightError, ls->nLight);
                E[cosTheta > 0.0f ? 0 : 1] += ls->L * std::abs(cosTheta) * T;
            }
            for (int side = 0; side < 2; ++side) {
                sum[side] += E[side];
                lo[side] = glm::min(lo[side], maxComponent(E[side]));
                hi[side] = glm::max(hi[side], maxComponent(E[side]));
            }
        }
        for (int side = 0; side < 2; ++side) {
            const int nd = node(e, side == 0);
            D_[nd] = sum[side] * (kInvPi / static_cast<float>(n));
            Dspread_[nd] = (hi[side] - lo[side]) * kInvPi;
        }
    });
    rays_ += static_cast<uint64_t>(elements.size()) * n * lights.size();
}

// --- Refinement --------------------------------------------------------------------------------

// The oracle's absolute threshold: epsilon times the scene's mean radiance, sum_i A_i max(L_i) /
// sum_i A_i over the patches (both sides counted in the sum, the area once), so that epsilon is a
// fraction of a typical radiance whatever the scene's units and brightness.
double RadiositySolver::refinementThreshold() const {
    double total = 0.0, area = 0.0;
    for (size_t p = 0; p < mesh_.patchCount(); ++p) {
        const int e = static_cast<int>(p);
        area += mesh_.area(e);
        total += mesh_.area(e) * static_cast<double>(maxComponent(L_[node(e, true)]) +
                                                     maxComponent(L_[node(e, false)]));
    }
    return area > 0.0 ? settings_.epsilon * total / area : 0.0;
}

bool RadiositySolver::subdivisible(int e) const {
    return !mesh_.isLeaf(e) || mesh_.canSplit(e);
}

// The first of e's four children, splitting e first if it is a leaf. New children start from the
// parent's radiance and direct light until the next sweep and finishSplits() replace them.
int RadiositySolver::children(int e) {
    if (!mesh_.isLeaf(e))
        return mesh_.firstChild(e);
    const int first = mesh_.split(e);
    resizeArrays();
    for (int c = first; c < first + RadiosityMesh::kChildren; ++c) {
        for (const bool side : {true, false}) {
            L_[node(c, side)] = L_[node(e, side)];
            Lmin_[node(c, side)] = Lmax_[node(c, side)] = maxComponent(L_[node(e, side)]);
            D_[node(c, side)] = D_[node(e, side)];
            Dspread_[node(c, side)] = Dspread_[node(e, side)];
        }
        created_.push_back(c);
    }
    return first;
}

void RadiositySolver::finishSplits() {
    computeDirect(created_);
    created_.clear();
}

// The two errors a link (receiver <- source) makes, in radiance at the receiver. HSA91's BF oracle
// weighs the transfer itself, B_q F_pq (times A_p for power); these weigh what the link gets
// wrong instead, in the way of Lischinski, Smits and Greenberg 1994, "Bounds and Error Estimates
// for Radiosity", SIGGRAPH '94, which refines links by the spread of their transfer (estimated
// here from samples, not bounded):
//  - receiver side: what the linear push cannot follow of the form factor's variation over the
//    receiver, `spread` (Link::spread) times max(L_source);
//  - source side: the link carries the source's mean radiance while the radiance spreads by
//    (L_max - L_min) over the source's leaves: F_max (L_max - L_min).
// Weighing F alone misses the first: with HSA91's constant push, in the closed box a corner
// element gathers 1.9 times what it should from links that each carry under 1 %.
RadiositySolver::LinkErrors RadiositySolver::linkErrors(int source, float spread,
                                                        float Fmax) const {
    return {static_cast<double>(spread) * maxComponent(L_[source]),
            static_cast<double>(Fmax) * (Lmax_[source] - Lmin_[source])};
}

// The receiver-side spread of an unoccluded link from its samples: the centroid's departure from
// the plane through the corners (zero for a linear F), plus the part of the corners' spread that
// the positivity limiter takes out of the model.
float RadiositySolver::KernelSamples::spread(float limiter) const {
    const float lo = glm::min(corner[0], glm::min(corner[1], corner[2]));
    const float hi = glm::max(corner[0], glm::max(corner[1], corner[2]));
    float curvature = std::abs(centroid - cornerMean());
    for (int i = 0; i < 3; ++i)
        curvature =
            glm::max(curvature, std::abs(mid[i] - 0.5f * (corner[i] + corner[(i + 1) % 3])));
    return curvature + (1.0f - limiter) * (hi - lo);
}

// HSA91 "Refine": while the larger of a link's errors exceeds the threshold and one of the two
// elements can still be subdivided, the side at fault is subdivided (the other if it cannot) and
// its children are refined against the other element; otherwise the pair is linked ("Link").
// HSA91 subdivides the element with the larger form factor estimate, i.e. the larger one; here
// the error says which side needs it. `spread` is the receiver-side spread of the pair, from the
// samples for a new pair, from the link for a link being refined.
void RadiositySolver::refine(int receiver, int source, const KernelSamples& samples, float spread,
                             std::vector<PendingLink>& pending) {
    const int er = element(receiver), es = element(source);
    const bool canR = subdivisible(er), canS = subdivisible(es);
    const LinkErrors errors = linkErrors(source, spread, samples.max());
    if (!(std::max(errors.receiver, errors.source) > threshold_) || !(canR || canS)) {
        pending.push_back({receiver, source, samples});
        return;
    }
    const bool splitSource = canS && (!canR || errors.source > errors.receiver);
    const int first = children(splitSource ? es : er);
    for (int c = first; c < first + RadiosityMesh::kChildren; ++c) {
        const int r = splitSource ? receiver : node(c, front(receiver));
        const int s = splitSource ? node(c, front(source)) : source;
        if (mayInteract(r, s)) {
            const KernelSamples k = kernelSamples(r, s);
            refine(r, s, k, k.spread(1.0f), pending);
        }
    }
}

// Form factor, visibility and linear model of new links, in parallel (the refinement that decided
// them is sequential because it splits elements). Links that carry nothing (F = 0, or fully
// occluded) are dropped: no oracle would refine them. A partly occluded link gets no slope (the
// visibility's variation is unknown) and a spread of its whole F_max, as a shadow boundary may
// cross the receiver anywhere.
void RadiositySolver::evaluateLinks(const std::vector<PendingLink>& pending) {
    const auto start = std::chrono::steady_clock::now();
    std::vector<Link> evaluated(pending.size());
    tbb::parallel_for(size_t(0), pending.size(), [&](size_t i) {
        const PendingLink& p = pending[i];
        Link& link = evaluated[i];
        link.source = p.source;
        link.F = formFactor(p.receiver, p.source);
        if (!(link.F > 0.0f))
            return;
        const Color V = visibility(p.receiver, p.source);
        link.K = link.F * V;
        link.Fmax = glm::max(p.samples.max(), link.F);
        if (glm::min(V.r, glm::min(V.g, V.b)) < 1.0f) {
            link.spread = link.Fmax;
            setSourceWeights(p.receiver, link);
            return;
        }
        float limiter = 1.0f;
        link.g = linearModel(p.receiver, p.samples, link.F, limiter);
        link.spread = p.samples.spread(limiter);
        setSourceWeights(p.receiver, link);
    });
    for (size_t i = 0; i < pending.size(); ++i) {
        if (evaluated[i].F > 0.0f) {
            rays_ += static_cast<uint64_t>(settings_.visibilitySamples);
            if (maxComponent(evaluated[i].K) > 0.0f)
                links_[pending[i].receiver].push_back(evaluated[i]);
        }
    }
    secondsLinks_ += secondsSince(start);
}

// HSA91's initial linking: Refine every ordered pair of patch sides that can see each other.
void RadiositySolver::linkPatches() {
    threshold_ = refinementThreshold();
    std::vector<PendingLink> pending;
    const int roots = static_cast<int>(2 * mesh_.patchCount());
    for (int r = 0; r < roots; ++r) {
        for (int s = 0; s < roots; ++s) {
            if (mayInteract(r, s)) {
                const KernelSamples k = kernelSamples(r, s);
                refine(r, s, k, k.spread(1.0f), pending);
            }
        }
    }
    evaluateLinks(pending);
    finishSplits();
}

// HSA91 "RefineLinks": every link whose error (linkErrors) now exceeds the threshold, with the
// radiance of the last solve, is replaced by the links Refine() makes for the pair. Returns
// whether any link was refined.
bool RadiositySolver::refineLinks() {
    threshold_ = refinementThreshold();
    std::vector<std::pair<int, Link>> candidates;
    for (size_t n = 0; n < links_.size(); ++n) {
        const int receiver = static_cast<int>(n);
        std::erase_if(links_[n], [&](const Link& link) {
            const LinkErrors errors = linkErrors(link.source, link.spread, link.Fmax);
            const bool refinable =
                std::max(errors.receiver, errors.source) > threshold_ &&
                (subdivisible(element(receiver)) || subdivisible(element(link.source)));
            if (refinable)
                candidates.emplace_back(receiver, link);
            return refinable;
        });
    }
    std::vector<PendingLink> pending;
    for (const auto& [receiver, link] : candidates) {
        refine(receiver, link.source, kernelSamples(receiver, link.source), link.spread, pending);
    }
    evaluateLinks(pending);
    finishSplits();
    refinedLinks_ += candidates.size();
    return !candidates.empty();
}

// The punctual lights under the same oracle as links: a leaf whose direct term spreads over it by
// more than the threshold (a light pool's falloff, a shadow boundary) is split, down to the
// minimum area, and its children sample their own. Returns whether any element was split.
bool RadiositySolver::refineDirect() {
    threshold_ = refinementThreshold();
    std::vector<int> queue;
    for (size_t e = 0; e < mesh_.elementCount(); ++e) {
        if (mesh_.isLeaf(static_cast<int>(e)))
            queue.push_back(static_cast<int>(e));
    }
    bool split = false;
    while (!queue.empty()) {
        for (const int e : queue) {
            const float spread = glm::max(Dspread_[node(e, true)], Dspread_[node(e, false)]);
            if (spread > threshold_ && mesh_.canSplit(e))
                children(e);
        }
        queue = created_;
        split = split || !created_.empty();
        finishSplits();
    }
    return split;
}

// --- Gather and push-pull ----------------------------------------------------------------------

Color RadiositySolver::emission(int n) const {
    const int e = element(n);
    return front(n) || mesh_.twoSided(e) ? mesh_.Le(e) : Color(0.0f);
}

// The source side of a link at first order: when the source has children, its radiance is not
// uniform, and the light the receiver gathers weighs each child by its share of the form factor,
// w_c = F(x -> child c) / sum_c F(x -> child c) at the receiver's centroid x (exact
// point-to-polygon values, form_factor.h), rather than by its area. The mean radiance alone leaves
// the first-order term of the source's gradient against the kernel's: measured over a lit room,
// 1 % of the interreflected light lost at epsilon = 0.01. This is the source side of a two-level
// quadrature of the transfer (Cohen and Wallace 1993, chapter 4, "area-to-area form factors by
// numerical integration"), using the one visible fraction of the link.
void RadiositySolver::setSourceWeights(int receiver, Link& link) const {
    const int es = element(link.source);
    if (mesh_.isLeaf(es))
        return;
    const int er = element(receiver);
    const Vec3 nr = front(receiver) ? mesh_.normal(er) : -mesh_.normal(er);
    const Vec3 ns = front(link.source) ? mesh_.normal(es) : -mesh_.normal(es);
    const Vec3 x = mesh_.centroid(er);
    // pointToPolygonFormFactor() is two-sided in the polygon: seen from behind, nothing.
    if (!(glm::dot(ns, x - mesh_.corners(es)[0]) > 0.0f))
        return;
    const int first = mesh_.firstChild(es);
    std::array<double, 4> F{};
    double sum = 0.0;
    for (int c = 0; c < RadiosityMesh::kChildren; ++c) {
        F[c] = pointToPolygonFormFactor(x, nr, mesh_.corners(first + c));
        sum += F[c];
    }
    if (!(sum > 0.0))
        return;
    for (int c = 0; c < RadiosityMesh::kChildren; ++c)
        link.w[c] = static_cast<float>(F[c] / sum);
}

// Sets the weights of links whose source has been split since they were made.
void RadiositySolver::updateSourceWeights() {
    tbb::parallel_for(size_t(0), links_.size(), [&](size_t n) {
        for (Link& link : links_[n]) {
            if (link.w[0] < 0.0f)
                setSourceWeights(static_cast<int>(n), link);
        }
    });
}

Color RadiositySolver::sourceRadiance(const Link& link) const {
    if (link.w[0] < 0.0f)
        return L_[link.source];
    const int first = mesh_.firstChild(element(link.source));
    const bool side = front(link.source);
    Color L(0.0f);
    for (int c = 0; c < RadiosityMesh::kChildren; ++c)
        L += link.w[c] * L_[node(first + c, side)];
    return L;
}

// HSA91 "GatherRad" with a linear push: a node gathers through its own links the radiance
// sum_j K_ij L_j at its centroid, and its gradient over the node, sum_j K_ij L_j g_ij (the
// receiver's rho is applied at the leaves, after the push, so that children keep their own rho).
void RadiositySolver::gather(int n) {
    Color H(0.0f);
    Mat3 G(0.0f);
    for (const Link& link : links_[n]) {
        const Color transfer = link.K * sourceRadiance(link);
        H += transfer;
        G += glm::outerProduct(transfer, link.g);
    }
    H_[n] = H;
    G_[n] = G;
}

void RadiositySolver::gatherTree(int n) {
    gather(n);
    const int e = element(n);
    if (mesh_.isLeaf(e))
        return;
    const int first = mesh_.firstChild(e);
    for (int c = first; c < first + RadiosityMesh::kChildren; ++c)
        gatherTree(node(c, front(n)));
}

// HSA91 "PushPullRad", with the gathered radiance pushed down as a linear function instead of a
// constant: a child receives its parent's function, evaluated at its own centroid, where a linear
// function takes its mean over the child; so the push moves no energy between children and still
// follows the first-order variation of each link's form factor over its receiver (a linear basis
// on the receiver side only; Gortler, Schroeder, Cohen and Hanrahan 1993, "Wavelet Radiosity",
// use higher-order bases on both). Each leaf forms L = Le + rho (D + H); a parent's radiance is
// the area-weighted mean of its children's. Also pulls the range of max(L) over each node's
// leaves for the oracle, and adds the leaves' change to `sums`.
Color RadiositySolver::pushPull(int n, const Color& Hdown, const Mat3& Gdown, ChangeSums& sums) {
    const int e = element(n);
    const Color H = H_[n] + Hdown;
    if (mesh_.isLeaf(e)) {
        // The limiter keeps every link's function non-negative; max() only absorbs rounding.
        const Color L = emission(n) + mesh_.rho(e) * (D_[n] + glm::max(H, Color(0.0f)));
        const double area = mesh_.area(e);
        sums.change += area * channelSum(glm::abs(L - L_[n]));
        sums.norm += area * channelSum(L);
        L_[n] = L;
        Lmin_[n] = Lmax_[n] = maxComponent(L);
        return L;
    }
    const Mat3 G = G_[n] + Gdown;
    const Vec3 center = mesh_.centroid(e);
    Color sum(0.0f);
    float lo = std::numeric_limits<float>::infinity(), hi = 0.0f;
    const int first = mesh_.firstChild(e);
    for (int c = first; c < first + RadiosityMesh::kChildren; ++c) {
        const int child = node(c, front(n));
        sum += mesh_.area(c) * pushPull(child, H + G * (mesh_.centroid(c) - center), G, sums);
        lo = glm::min(lo, Lmin_[child]);
        hi = glm::max(hi, Lmax_[child]);
    }
    L_[n] = sum / mesh_.area(e);
    Lmin_[n] = lo;
    Lmax_[n] = hi;
    return L_[n];
}

// One sweep over all patch sides; returns the relative change ||L_k - L_{k-1}|| / ||L_k||
// (area-weighted L1 over the leaves), which is also the relative residual of the Jacobi form of
// the equation at L_{k-1}. Jacobi gathers everything from the previous sweep's radiance (in
// parallel), then pushes and pulls each tree; Gauss-Seidel gathers and pushes-pulls one patch
// side at a time, so later patches already see the new radiance of earlier ones (Cohen and
// Wallace 1993, chapter 5, applied per tree as in HSA91's "SolveSystem").
double RadiositySolver::sweep() {
    const int roots = static_cast<int>(2 * mesh_.patchCount());
    ChangeSums total;
    if (settings_.iteration == RadiositySettings::Iteration::Jacobi) {
        tbb::parallel_for(size_t(0), links_.size(), [&](size_t n) { gather(static_cast<int>(n)); });
        tbb::combinable<ChangeSums> sums;
        tbb::parallel_for(0, roots,
                          [&](int r) { pushPull(r, Color(0.0f), Mat3(0.0f), sums.local()); });
        sums.combine_each([&](const ChangeSums& s) {
            total.change += s.change;
            total.norm += s.norm;
        });
    } else {
        for (int r = 0; r < roots; ++r) {
            gatherTree(r);
            pushPull(r, Color(0.0f), Mat3(0.0f), total);
        }
    }
    return total.norm > 0.0 ? total.change / total.norm : 0.0;
}

// Sweeps until the estimated relative error is below `threshold`. The estimate is the a
// posteriori bound of a contraction, ||L_k - L*|| <= q / (1 - q) ||L_k - L_{k-1}|| (Banach's
// fixed-point theorem's a posteriori estimate; e.g. Kress 1998, "Numerical Analysis", chapter 3),
// with the contraction
// factor q measured as the largest ratio of successive changes over the last three sweeps. A
// change alone would stop far too early for rho near 1, where it is only (1 - q) times the
// remaining error.
void RadiositySolver::iterate(double threshold, int round) {
    updateSourceWeights();
    std::vector<double> changes;
    converged_ = false;
    while (iterations_.size() < static_cast<size_t>(settings_.maxIterations)) {
        RadiosityIteration it;
        it.round = round;
        it.change = sweep();
        changes.push_back(it.change);
        it.errorBound = std::numeric_limits<double>::infinity();
        if (it.change == 0.0) {
            it.errorBound = 0.0;
        } else if (changes.size() >= 4) {
            double q = 0.0;
            for (size_t k = changes.size() - 3; k < changes.size(); ++k)
                q = std::max(q, changes[k] / changes[k - 1]);
            if (q < 1.0)
                it.errorBound = it.change * q / (1.0 - q);
        }
        iterations_.push_back(it);
        if (it.errorBound < threshold) {
            converged_ = true;
            return;
        }
    }
}

void RadiositySolver::computeVertexValues() {
    vertexReflected_.assign(2, std::vector<Color>(mesh_.vertexCount(), Color(0.0f)));
    std::vector<Color> values(mesh_.elementCount());
    // The back first, so that the mesh is left with the front's values.
    for (const bool side : {false, true}) {
        for (size_t e = 0; e < values.size(); ++e) {
            const int n = node(static_cast<int>(e), side);
            values[e] = glm::max(L_[n] - emission(n), Color(0.0f));
        }
        mesh_.setElementValues(values);
        std::vector<Color>& out = vertexReflected_[side ? 0 : 1];
        for (size_t v = 0; v < out.size(); ++v)
            out[v] = mesh_.vertexValue(static_cast<uint32_t>(v));
    }
}

// --- The whole solution ------------------------------------------------------------------------

// HSA91's "HierarchicalRadiosity" with brightness-weighted refinement: link the patches with the
// oracle on the initial radiance (emission and punctual direct light), then alternate solving and
// refining the links with the current radiance until nothing is refined.
void RadiositySolver::solve() {
    const auto start = std::chrono::steady_clock::now();

    // Stage 1: the punctual lights' direct light; the initial radiance is Le + rho D.
    std::vector<int> leaves;
    for (size_t e = 0; e < mesh_.elementCount(); ++e) {
        if (mesh_.isLeaf(static_cast<int>(e)))
            leaves.push_back(static_cast<int>(e));
    }
    computeDirect(leaves);
    const int roots = static_cast<int>(2 * mesh_.patchCount());
    ChangeSums ignored;
    for (int r = 0; r < roots; ++r)
        pushPull(r, Color(0.0f), Mat3(0.0f), ignored);
    refineDirect();
    for (int r = 0; r < roots; ++r)
        pushPull(r, Color(0.0f), Mat3(0.0f), ignored);
    secondsDirect_ = secondsSince(start);

    // Stage 2: initial links between the patches.
    auto stageStart = std::chrono::steady_clock::now();
    linkPatches();
    secondsLinking_ = secondsSince(stageStart);

    // Stage 3: gather sweeps and refinement rounds.
    const double roundThreshold = std::max(settings_.convergence, kRoundConvergence);
    stageStart = std::chrono::steady_clock::now();
    iterate(roundThreshold, 0);
    secondsSolve_ += secondsSince(stageStart);
    int round = 0;
    while (round < settings_.maxRefinements) {
        stageStart = std::chrono::steady_clock::now();
        bool refined = refineLinks();
        refined = refineDirect() || refined;
        secondsRefine_ += secondsSince(stageStart);
        if (!refined)
            break;
        ++round;
        rounds_ = round;
        stageStart = std::chrono::steady_clock::now();
        iterate(roundThreshold, round);
        secondsSolve_ += secondsSince(stageStart);
    }
    stageStart = std::chrono::steady_clock::now();
    iterate(settings_.convergence, round);
    computeVertexValues();
    secondsSolve_ += secondsSince(stageStart);
    secondsTotal_ = secondsSince(start);
}

Color RadiositySolver::radiance(uint32_t mesh, uint32_t triangle, Vec3 b, bool includeEmission,
                                bool front) const {
    const ElementPoint point = mesh_.locate(mesh, triangle, b);
    if (point.element < 0 || vertexReflected_.empty())
        return Color(0.0f);
    const auto& v = mesh_.vertices(point.element);
    const std::vector<Color>& values = vertexReflected_[front ? 0 : 1];
    Color L = point.weights.x * values[v[0]] + point.weights.y * values[v[1]] +
              point.weights.z * values[v[2]];
    if (includeEmission)
        L += emission(node(point.element, front));
    return L;
}

// --- The dense reference ---------------------------------------------------------------------

std::vector<Color> RadiositySolver::solveFullMatrix() const {
    std::vector<int> nodes;
    for (size_t e = 0; e < mesh_.elementCount(); ++e) {
        if (mesh_.isLeaf(static_cast<int>(e))) {
            nodes.push_back(node(static_cast<int>(e), true));
            nodes.push_back(node(static_cast<int>(e), false));
        }
    }
    // Rows of K_ij = F_ij V_ij over all pairs of leaf sides that can see each other.
    std::vector<std::vector<std::pair<size_t, Color>>> rows(nodes.size());
    tbb::parallel_for(size_t(0), nodes.size(), [&](size_t i) {
        for (size_t j = 0; j < nodes.size(); ++j) {
            if (!mayInteract(nodes[i], nodes[j]))
                continue;
            const float F = formFactor(nodes[i], nodes[j]);
            if (F <= 0.0f)
                continue;
            const Color K = F * visibility(nodes[i], nodes[j]);
            if (maxComponent(K) > 0.0f)
                rows[i].emplace_back(j, K);
        }
    });
    // Gauss-Seidel on L_i = Le_i + rho_i (D_i + sum_j K_ij L_j) (Cohen and Wallace 1993,
    // chapter 5), from L = Le + rho D.
    std::vector<Color> x(nodes.size());
    for (size_t i = 0; i < nodes.size(); ++i)
        x[i] = emission(nodes[i]) + mesh_.rho(element(nodes[i])) * D_[nodes[i]];
    for (int sweep = 0; sweep < 1000000; ++sweep) {
        ChangeSums sums;
        for (size_t i = 0; i < nodes.size(); ++i) {
            Color H(0.0f);
            for (const auto& [j, K] : rows[i])
                H += K * x[j];
            const int n = nodes[i];
            const Color L = emission(n) + mesh_.rho(element(n)) * (D_[n] + H);
            const double area = mesh_.area(element(n));
            sums.change += area * channelSum(glm::abs(L - x[i]));
            sums.norm += area * channelSum(L);
            x[i] = L;
        }
        if (!(sums.change > 1e-9 * sums.norm))
            break;
    }
    std::vector<Color> result(L_.size(), Color(0.0f));
    for (size_t i = 0; i < nodes.size(); ++i)
        result[nodes[i]] = x[i];
    return result;
}

// --- Statistics --------------------------------------------------------------------------------

PassStats RadiositySolver::stats() const {
    const RadiosityMeshStats mesh = mesh_.stats();
    const size_t links = linkCount();
    size_t memory = mesh.memoryBytes + links * sizeof(Link) +
                    links_.size() * (sizeof(std::vector<Link>) + 3 * sizeof(Color));
    for (const auto& side : vertexReflected_)
        memory += side.size() * sizeof(Color);
    const RadiosityIteration last = iterations_.empty() ? RadiosityIteration{} : iterations_.back();
    return {{"patches", std::to_string(mesh.patches)},
            {"elements", std::to_string(mesh.elements)},
            {"leaves", std::to_string(mesh.leaves)},
            {"links", std::to_string(links)},
            {"refinement_rounds", std::to_string(rounds_)},
            {"refined_links", std::to_string(refinedLinks_)},
            {"iterations", std::to_string(iterations_.size())},
            {"residual", format(last.change)},
            {"error_bound", format(last.errorBound)},
            {"converged", converged_ ? "yes" : "no"},
            {"rays", std::to_string(rays_)},
            {"memory_mib", format(static_cast<double>(memory) / (1024.0 * 1024.0))},
            {"seconds_direct", format(secondsDirect_)},
            {"seconds_linking", format(secondsLinking_)},
            {"seconds_form_factors", format(secondsLinks_)},
            {"seconds_refine", format(secondsRefine_)},
            {"seconds_solve", format(secondsSolve_)},
            {"seconds", format(secondsTotal_)}};
}

}  // namespace penumbra
