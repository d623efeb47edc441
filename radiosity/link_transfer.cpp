// The transfer of a link between two nodes of the hierarchical solver: form factors, the
// oracle's kernel samples, the linear model and the visible fraction, and the isotropic kernel of
// the links with a cluster at an end.
#include "radiosity/link_transfer.h"

#include "core/closest_point.h"
#include "core/sampler.h"
#include "core/sampling.h"
#include "core/scene.h"
#include "radiosity/form_factor.h"
#include "radiosity/solver_nodes.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <optional>

namespace penumbra {

namespace {

// Seeds of the visibility samplers, apart from those of the element points
// (ElementExposure::kPointSeed) and the final gather (radiosity_solver.cpp), so that they never
// share a sequence.
constexpr uint32_t kVisibilitySeed = 0x9e3779b9u;
constexpr uint32_t kCoverOffsetSeed = 0x27d4eb2fu;

// Shadow rays a link casts before deciding whether it needs all of visibility_samples.
constexpr int kFirstVisibilityRays = 4;

// Pairs of points visibility() may draw per shadow ray: it skips, before their rays, the pairs
// that do not face each other and those whose cluster side does not take part.
constexpr int kDrawsPerRay = 4;

// Centroid distance, in longest edges of the pair, from which a link's form factor is the
// seven-point rule over the oracle's samples (formFactor).
constexpr float kFarLink = 4.0f;

// Fraction of the way from a receiver's corners to its centroid at which the oracle samples the
// kernel (kernelSamples): off the contact line with a touching source, still at the corner to a
// thousandth of the element's size for the linear model.
constexpr float kKernelInset = 1e-3f;

// Radius, in square roots of the smallest element area, under which two clusters (or a cluster
// and an element) close together are linked rather than split (clusterKernel).
constexpr float kClusterMinRadius = 2.0f;

}  // namespace

LinkTransfer::LinkTransfer(const Scene& scene, const RadiosityMesh& mesh,
                           const ElementExposure& exposure, const ClusterTree* clusters,
                           const RadiositySettings& settings)
    : scene_(scene),
      mesh_(mesh),
      exposure_(exposure),
      clusters_(clusters),
      visibilitySamples_(settings.visibilitySamples),
      clusterMinRadius_(
          clusters ? kClusterMinRadius * std::sqrt(settings.meshing(scene).minElementArea) : 0.0f) {
}

Vec3 LinkTransfer::nodeCenter(int n) const {
    return isCluster(n) ? (*clusters_)[cluster(n)].center : mesh_.centroid(element(n));
}

double LinkTransfer::nodeArea(int n) const {
    return isCluster(n) ? (*clusters_)[cluster(n)].area : mesh_.area(element(n));
}

float LinkTransfer::nodeRadius(int n) const {
    if (isCluster(n))
        return (*clusters_)[cluster(n)].radius;
    const int e = element(n);
    const Vec3 c = mesh_.centroid(e);
    float r = 0.0f;
    for (const Vec3& corner : mesh_.corners(e))
        r = glm::max(r, glm::distance(corner, c));
    return r;
}

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

}  // namespace

bool LinkTransfer::mayInteract(int receiver, int source) const {
    // A wholly covered side sends and receives nothing.
    if (!exposure_.exposed(receiver) || !exposure_.exposed(source))
        return false;
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
// point-to-polygon value (form_factor.h). The quadrature order (Gauss-Legendre points per axis of
// the collapsed map, order^2 point values) follows the centroid distance d between the elements
// relative to their size s (the longer of their longest edges). Measured against order 24 on 400
// random pairs of triangles in random orientations per distance, mean and largest relative error:
// order 3 at d = 3 s 2.6e-6 and 3.5e-5; order 4 at 1.5 s 3.8e-6 and 6e-5; order 5 at s 1.3e-5
// and 1.0e-3. Each order is used from that distance on, so no link's error exceeds that of the
// seven-point rule below, which the far pairs have taken since it was measured (mean 5e-5, largest
// 1.6e-3), and all are far under what a link's visible fraction from 16 shadow rays can resolve.
// Closer (adjacent) pairs take order 8, where the integrand is only Lipschitz: on 500 random pairs
// of triangles sharing an edge, at angles from 11 to 166 degrees and against order 40, order 8 is
// within 3.5e-4 on average (2.8e-2 at worst, for slivers) and order 10 within 1.5e-4 (1.2e-2);
// order 8 costs 64 point evaluations instead of 100 and keeps the closed furnace box within its
// 1 % (tests/radiosity/radiosity_furnace_test.cpp).
//
// Far pairs wholly in front of each other (centroid distance at least kFarLink longest edges)
// reuse the oracle's seven point values instead: the classical seven-point rule of degree 3 on the
// triangle, weights 1/20 at the corners, 2/15 at the edge midpoints and 9/20 at the centroid (see
// Stroud 1971, "Approximate Calculation of Multiple Integrals"). Measured against order 24 on
// 450 random facing triangle pairs at 4 edges: mean relative error 5e-5, largest 1.6e-3 (at 2
// edges 6e-4 and 1.2e-2, too much); a pair that straddles the other's plane needs the clipping of
// areaToAreaFormFactor and never takes the rule.
float LinkTransfer::formFactor(int receiver, int source, const KernelSamples* samples) const {
    const auto cr = sideCorners(mesh_, element(receiver), front(receiver));
    const auto cs = sideCorners(mesh_, element(source), front(source));
    const float size = glm::max(longestEdge(cr), longestEdge(cs));
    const float distance =
        glm::distance((cr[0] + cr[1] + cr[2]) / 3.0f, (cs[0] + cs[1] + cs[2]) / 3.0f);
    const auto inFront = [](const std::array<Vec3, 3>& c, const std::array<Vec3, 3>& plane) {
        const Vec3 n = glm::cross(plane[1] - plane[0], plane[2] - plane[0]);
        return glm::dot(n, c[0] - plane[0]) > 0.0f && glm::dot(n, c[1] - plane[0]) > 0.0f &&
               glm::dot(n, c[2] - plane[0]) > 0.0f;
    };
    if (samples && distance >= kFarLink * size && inFront(cs, cr) && inFront(cr, cs)) {
        const KernelSamples& k = *samples;
        return (k.corner[0] + k.corner[1] + k.corner[2]) / 20.0f +
               (k.mid[0] + k.mid[1] + k.mid[2]) * (2.0f / 15.0f) + k.centroid * (9.0f / 20.0f);
    }
    const int order = distance >= 3.0f * size   ? 3
                      : distance >= 1.5f * size ? 4
                      : distance >= size        ? 5
                                                : 8;
    return static_cast<float>(areaToAreaFormFactor(cr, cs, order));
}

// Point values of the unoccluded form factor F(x -> source) at the receiver's corners and
// centroid, for the oracle and the linear push. The corners (and so the edge midpoints) are taken
// a fraction kKernelInset of the way towards the centroid: where the receiver touches the
// source's plane (a wall standing on a floor, the floor running under a block), a point on the
// contact line lies in the source's plane and sees nothing of it (F = 0), while the limit from
// inside the receiver is the largest value of F over it (1/2 for a half-infinite perpendicular
// source). Taken exactly on the line, the samples put F at its smallest where it peaks: the oracle
// saw a small, smooth kernel and left such links at coarse receivers, whose mean F the linear push
// spreads evenly, so the receiver's elements along the contact line gathered up to a third too
// little (the furnace with a block on its floor, tests/radiosity/radiosity_robustness_test.cpp).
KernelSamples LinkTransfer::kernelSamples(int receiver, int source) const {
    const int er = element(receiver), es = element(source);
    const Vec3 nr = front(receiver) ? mesh_.normal(er) : -mesh_.normal(er);
    const Vec3 ns = front(source) ? mesh_.normal(es) : -mesh_.normal(es);
    auto cr = mesh_.corners(er);
    const auto cs = mesh_.corners(es);
    const Vec3 centroid = (cr[0] + cr[1] + cr[2]) / 3.0f;
    for (Vec3& corner : cr)
        corner += kKernelInset * (centroid - corner);
    // pointToPolygonFormFactor() is two-sided in the polygon: a point behind the source side sees
    // nothing of it.
    const auto F = [&](const Vec3& x) {
        return glm::dot(ns, x - cs[0]) > 0.0f
                   ? static_cast<float>(pointToPolygonFormFactor(x, nr, cs))
                   : 0.0f;
    };
    return {{F(cr[0]), F(cr[1]), F(cr[2])},
            {F(0.5f * (cr[0] + cr[1])), F(0.5f * (cr[1] + cr[2])), F(0.5f * (cr[2] + cr[0]))},
            F(centroid)};
}

// The linear model of a link's form factor over its receiver (see Link::g): the plane through
// the corner values, moved to have the link's exact mean F, its slope scaled down by the largest
// t in [0, 1] that keeps it non-negative at the corners (and so everywhere on the receiver).
// Returns the relative gradient and sets `limiter` to t.
Vec3 LinkTransfer::linearModel(int receiver, const KernelSamples& k, float F,
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

namespace {

// The pair's offset into its ends' cover samples (visibility), one per pair of nodes `pixel`.
Vec2 coverOffset(IVec2 pixel) {
    Sampler offsets(kCoverOffsetSeed);
    offsets.startPixelSample(pixel, 0);
    return offsets.get2D();
}

// The visible fractions of the children of a link's two ends (Link::childV) from the link's own
// rays: per end (0 the receiver, 1 the source) and child, the sums of the rays' transmittances
// (their channels' mean) and the ray counts, over all pairs and over the pairs facing each other.
class ChildTally {
  public:
    // A ray between the children (RadiosityMesh::childAt; -1 for a cluster end) with
    // transmittance T.
    void add(int receiverChild, int sourceChild, const Color& T, bool facing) {
        const float mean = (T.r + T.g + T.b) / 3.0f;
        const std::array<int, 2> child{receiverChild, sourceChild};
        for (size_t end = 0; end < 2; ++end) {
            if (child[end] < 0)
                continue;
            const auto c = static_cast<size_t>(child[end]);
            all_.sum[end][c] += mean;
            ++all_.count[end][c];
            if (facing) {
                facing_.sum[end][c] += mean;
                ++facing_.count[end][c];
            }
        }
    }
    // Each child's mean over the facing pairs or all, -1 where no ray fell in it.
    std::array<float, 4> means(size_t end, bool facingOnly) const {
        const Sums& s = facingOnly ? facing_ : all_;
        std::array<float, 4> V{};
        for (size_t c = 0; c < V.size(); ++c)
            V[c] =
                s.count[end][c] > 0 ? s.sum[end][c] / static_cast<float>(s.count[end][c]) : -1.0f;
        return V;
    }

  private:
    struct Sums {
        std::array<std::array<float, 4>, 2> sum{};
        std::array<std::array<int, 4>, 2> count{};
    };
    Sums all_, facing_;
};

}  // namespace

// Visible fraction between two element sides: the mean transmittance of n shadow rays between
// paired points of the two elements. The points are stratified: sample k on each element is point
// k of an Owen-scrambled (0,2)-sequence (core/sampler.h) mapped to the triangle by Heitz's
// area-preserving map, and the two elements use independently scrambled dimensions, so the pairs
// are decorrelated (HSA91 estimate visibility in the same way, by rays between jittered points of
// the two elements; Cohen and Wallace 1993, chapter 4). Thin glass transmits, as everywhere in
// penumbra. A cluster's points are points of its patches, chosen by area.
//
// With `adaptive`, the first kFirstVisibilityRays pairs, which are themselves stratified (the first
// 4 points of a (0,2)-sequence fall one in each quarter of the square), decide alone when they
// agree, i.e. the pair looks wholly visible or wholly hidden by the surfaces (a medium's
// transmittance varies smoothly over the pair: the rays cast give it); only pairs they see
// partly occluded get the full n (as HSA91 suggest, casting more rays only where a few disagree).
// Most links of an interior are unoccluded, so this saves most rays. An occluder missed by all four
// is small against the pair, and the caller asks for it only where even missing the whole transfer
// would be under the oracle's threshold (evaluateLinks).
//
// The same rays, binned by the child of each element end they leave or reach, give the children's
// visible fractions (`children`) for the link's child weights, about n/4 rays per child: the
// children exist or not yet, they are the element's 1:4 split (RadiosityMesh::childAt).
Color LinkTransfer::visibility(int receiver, int source, uint64_t& rays, bool adaptive,
                               ChildVisibility* children) const {
    const int n = visibilitySamples_;
    // Sample coordinates for the (IVec2) pixel of the sequence: cluster ids are negative. Ray k
    // takes sample k of the receiver's and the source's own dimensions (as a Sampler's first and
    // second get2D).
    const IVec2 pixel(receiver < 0 ? 0x40000000 - receiver : receiver,
                      source < 0 ? 0x40000000 - source : source);
    const SampleSequence2D receiverSequence(kVisibilitySeed, pixel, 1),
        sourceSequence(kVisibilitySeed, pixel, 2);
    struct NodeSample {
        ElementSample x;
        int element;
        int child;            // of an element node, RadiosityMesh::childAt; -1 for a cluster
        bool hidden = false;  // a covered point of a source
    };
    // A partly covered end (ElementExposure) takes its points from its cover samples: the receiver
    // those exposed on its side, so that V is the visible fraction of its exposed part, as its
    // radiance is that part's; the source any, its covered ones hidden, though a shadow ray may
    // reach them from inside the closed object that covers them (from the inner sides of a block,
    // the floor under it). Ray k takes the point k after an offset drawn per pair. The cover
    // samples are a power-of-two prefix of a (0,2)-sequence, whose aligned runs of 2^j points are
    // each stratified over the element: the source's offset is a multiple of the rays' power of
    // two, so its points are as stratified as fresh ones. Random points would leave the few pairs
    // that face each other across a straddled plane (the floor under a block, from the block's
    // face) to chance, and where none did, the link took the visible fraction of the pairs
    // behind it (estimate, below): the short block's face lost 8 % of its light.
    const CoverSamples* receiverCover = exposure_.coverSamplesOf(receiver);
    const CoverSamples* sourceCover = exposure_.coverSamplesOf(source);
    const Vec2 offset = receiverCover || sourceCover ? coverOffset(pixel) : Vec2(0.0f);
    const auto coverSample = [&](int node, const CoverSamples& cover, uint32_t k, bool receiving) {
        const std::vector<uint16_t>& exposed = cover.exposed[front(node) ? 0 : 1];
        if (receiving && !exposed.empty()) {
            const size_t m = exposed.size();
            const size_t point = exposed[(static_cast<size_t>(offset.x * m) + k) % m];
            return NodeSample{cover.points[point], element(node), cover.child[point], false};
        }
        const size_t m = cover.points.size();
        const size_t run = std::min(m, std::bit_ceil(static_cast<size_t>(n)));
        const size_t point = (static_cast<size_t>(offset.y * (m / run)) * run + k) % m;
        return NodeSample{cover.points[point], element(node), cover.child[point],
                          !receiving && !cover.isExposed(point, front(node))};
    };
    const auto elementSampler = [&](int node) {
        return isCluster(node)
                   ? std::nullopt
                   : std::optional<ElementSampler>(std::in_place, scene_, mesh_, element(node));
    };
    const std::optional<ElementSampler> receiverPoints = elementSampler(receiver),
                                        sourcePoints = elementSampler(source);
    const auto sample = [&](int node, const CoverSamples* cover, bool receiving, uint32_t k) {
        if (cover)
            return coverSample(node, *cover, k, receiving);
        Vec2 u = (receiving ? receiverSequence : sourceSequence)[k];  // samplePatch reuses u.x
        if (!isCluster(node)) {
            const Vec3 w = sampleUniformTriangle(u);
            return NodeSample{(receiving ? receiverPoints : sourcePoints)->at(w), element(node),
                              RadiosityMesh::childAt(w)};
        }
        const int patch = clusters_->samplePatch(cluster(node), u.x);
        return NodeSample{sampleElement(scene_, mesh_, patch, u), patch, -1};
    };
    // Whether a cluster's point takes part: the side of its patch facing the other point must be
    // exposed. The isotropic model already gives a side facing away nothing (the mean projected
    // area A/4 counts it at zero), so a ray from it, which leaves through the solid behind it
    // (the far face of a stair tread), must not count as occluded a second time; and a side
    // facing a sealed interior or covered receives and sends nothing.
    const auto takesPart = [&](int end, const NodeSample& s, const Vec3& toward) {
        if (!isCluster(end))
            return true;
        const bool side = glm::dot(s.x.n, toward - s.x.p) >= 0.0f;
        const float a = exposure_.fraction(node(s.element, side));
        if (a == 0.0f || a == 1.0f)
            return a == 1.0f;
        return !exposure_.covered(s.element, s.x, side ? s.x.n : -s.x.n, rays);
    };
    // The side normals of element nodes; a cluster has no side (zero: every pair counts).
    const auto sideNormal = [&](int node) {
        if (isCluster(node))
            return Vec3(0.0f);
        return front(node) ? mesh_.normal(element(node)) : -mesh_.normal(element(node));
    };
    const Vec3 nr = sideNormal(receiver), ns = sideNormal(source);
    Color sum(0.0f), facingSum(0.0f);
    // The surfaces' part of the sums, which alone decides whether the first rays agree.
    Color surfaceSum(0.0f), facingSurfaceSum(0.0f);
    int k = 0, counted = 0, facing = 0;
    ChildTally tally;
    // The form factor integrates only over the pairs of points in front of each other
    // (areaToAreaFormFactor), so the visible fraction that multiplies it is taken over the same
    // pairs. Over all pairs it would also count those that leave a side backwards through its own
    // surface, unoccluded: for an element whose source straddles its plane (the inside of a box
    // standing on a floor that runs under it) that made the visible fraction of its hidden part
    // too large and that of its facing part too small. A pair that does not face is known so
    // before its ray: it is skipped and another drawn (up to kDrawsPerRay per ray), so that the
    // rays go to the pairs that count. Only if none of the draws faces does the link take all
    // pairs; before, a straddling pair whose few facing pairs the draws missed took the pairs
    // behind the plane, often all hidden, and lost the link.
    bool facingOnly = true;
    const auto cast = [&](int until) {
        for (; counted < until && k < kDrawsPerRay * until; ++k) {
            const NodeSample xs = sample(receiver, receiverCover, true, static_cast<uint32_t>(k)),
                             ys = sample(source, sourceCover, false, static_cast<uint32_t>(k));
            const ElementSample &x = xs.x, &y = ys.x;
            if (!takesPart(receiver, xs, y.p) || !takesPart(source, ys, x.p))
                continue;
            const bool isFacing =
                glm::dot(nr, y.p - x.p) >= 0.0f && glm::dot(ns, x.p - y.p) >= 0.0f;
            if (facingOnly && !isFacing)
                continue;
            ++counted;
            const Color Ts =
                ys.hidden ? Color(0.0f)
                          : scene_.surfaceTransmittance(x.p, x.pError, x.n, y.p, y.pError, y.n);
            const Color T =
                maxComponent(Ts) > 0.0f ? Ts * scene_.mediumTransmittance(x.p, y.p) : Ts;
            sum += T;
            surfaceSum += Ts;
            if (isFacing) {
                facingSum += T;
                facingSurfaceSum += Ts;
                ++facing;
            }
            if (children)
                tally.add(xs.child, ys.child, T, isFacing);
        }
    };
    const auto estimate = [&](const Color& all, const Color& facingOnes) {
        if (facing > 0)
            return facingOnes / static_cast<float>(facing);
        return counted > 0 ? all / static_cast<float>(counted) : Color(0.0f);
    };
    const int firstRays = adaptive ? std::min(n, kFirstVisibilityRays) : n;
    cast(firstRays);
    if (counted == 0) {
        facingOnly = false;
        k = 0;
        cast(firstRays);
    }
    const Color first = estimate(surfaceSum, facingSurfaceSum);
    const float firstSum = first.r + first.g + first.b;
    const bool agree = firstSum == 0.0f || firstSum == 3.0f;
    if (!agree)
        cast(n);
    rays += static_cast<uint64_t>(counted);
    if (children) {
        // Over the same pairs as the link's estimate.
        children->receiver = ChildVisibility::encode(tally.means(0, facing > 0));
        children->source = ChildVisibility::encode(tally.means(1, facing > 0));
    }
    return estimate(sum, facingSum);
}

// The form factor of a link over the exposed part of a partly covered receiver, from F over the
// whole receiver. The exposed part's visible fraction is visibility()'s, so covered points that
// shadow rays find hidden are accounted for; but where the source's own plane hides them (the
// floor under a block, from the block's faces), F over the whole receiver counts them as zero,
// and the exposed strip along the block's foot got only a fraction a of its light. With the
// points of the receiver in front of the source's plane taken to share one mean F (its ratio
// estimator over the receiver's cover samples), the exposed part's F is F P(front | exposed) /
// P(front): F itself when all points lie on one side.
float LinkTransfer::exposedFormFactor(int receiver, int source, float F) const {
    const CoverSamples* cover = exposure_.coverSamplesOf(receiver);
    if (!cover || isCluster(source) || !(F > 0.0f))
        return F;
    const int es = element(source);
    const Vec3 ns = front(source) ? mesh_.normal(es) : -mesh_.normal(es);
    const Vec3 origin = mesh_.corners(es)[0];
    const auto inFrontOfSource = [&](size_t point) {
        return glm::dot(ns, cover->points[point].p - origin) > 0.0f;
    };
    size_t inFront = 0;
    for (size_t k = 0; k < cover->points.size(); ++k)
        inFront += inFrontOfSource(k) ? 1 : 0;
    const std::vector<uint16_t>& exposed = cover->exposed[front(receiver) ? 0 : 1];
    if (inFront == 0 || inFront == cover->points.size() || exposed.empty())
        return F;
    size_t exposedInFront = 0;
    for (const uint16_t k : exposed)
        exposedInFront += inFrontOfSource(k) ? 1 : 0;
    return F * (static_cast<float>(exposedInFront) / static_cast<float>(exposed.size())) /
           (static_cast<float>(inFront) / static_cast<float>(cover->points.size()));
}

// The receiver-side spread of an unoccluded link from its samples: the centroid's departure from
// the plane through the corners (zero for a linear F), plus the part of the corners' spread that
// the positivity limiter takes out of the model.
float KernelSamples::spread(float limiter) const {
    const float lo = glm::min(corner[0], glm::min(corner[1], corner[2]));
    const float hi = glm::max(corner[0], glm::max(corner[1], corner[2]));
    float curvature = std::abs(centroid - cornerMean());
    for (int i = 0; i < 3; ++i)
        curvature =
            glm::max(curvature, std::abs(mid[i] - 0.5f * (corner[i] + corner[(i + 1) % 3])));
    return curvature + (1.0f - limiter) * (hi - lo);
}

// Whether a pair with a cluster at one end or both may exchange light at all: a wholly covered
// element side nothing, and an element side sees nothing of a cluster whose bounding sphere lies
// wholly behind its plane.
bool LinkTransfer::mayInteractWithCluster(int receiver, int source) const {
    if (!exposure_.exposed(receiver) || !exposure_.exposed(source))
        return false;
    const auto inFront = [&](int side, int other) {
        if (isCluster(side))
            return true;
        const int e = element(side);
        const Vec3 n = front(side) ? mesh_.normal(e) : -mesh_.normal(e);
        return glm::dot(n, nodeCenter(other) - mesh_.centroid(e)) > -nodeRadius(other);
    };
    return inFront(receiver, source) && inFront(source, receiver);
}

// The isotropic cluster model (Sillion 1995, section 4; Smits, Arvo and Greenberg 1994, section
// 3): a cluster of surface sides of total area A_c and mean radiance L_c radiates like a point
// source of intensity I = L_c A_c / 4 in every direction (the mean projected area of a randomly
// oriented one-sided surface of area A is A/4), and receives as a randomly oriented surface: its
// sides get on average the irradiance I' / (4 r^2) of a point source of intensity I'. With
// radiance units (H = E / pi, as the solver gathers) and r the distance of the centres:
//     element i <- cluster S:  K = A_S cos(theta_i) / (4 pi r^2)
//     cluster R <- element j:  K = A_j cos(theta_j) / (4 pi r^2)
//     cluster R <- cluster S:  K = A_S / (16 pi r^2)
// so that A_R K_RS = A_S K_SR for every pair (reciprocity, hence energy balance). A pair may be
// linked only when the two cannot touch: the nearest they can come, g, is d - r_R - r_S for two
// bounding spheres, and at an element end that cannot be split the distance of its triangle
// from the other's sphere (the larger of the two bounds), and must be positive.
//
// The error the oracle weighs (as a radiance per unit source radiance) has three parts:
//  - Sillion's, the variation of the kernel over the two ends, from 1/r^2 between the centres'
//    distance d and the nearest the two can come: K ((d / g)^2 - 1);
//  - the isotropic model's own error, of the order of the transfer K itself;
//  - for flat clusters (Cluster::flatness up to 1, coplanar patches facing one way), which
//    radiate and receive from 0 to 4 times the isotropic mean: 3 K flatness.
// Without the last two the closed furnace box forced into clusters came out 8 % low (1.3 % with
// the flat term alone at rho = 0.9); with them it keeps the 1 % of the element links, at 5.4 M
// links instead of 2.9 M in the modern hall (docs/radiosity.md, "Clusters"). `Kmax` is the kernel's
// largest value (a side facing the source gets 4 times a receiving cluster's mean), for the
// visibility's shortcut.
ClusterKernel LinkTransfer::clusterKernel(int receiver, int source, float softRadius) const {
    ClusterKernel k;
    const Vec3 cr = nodeCenter(receiver), cs = nodeCenter(source);
    const float rr = nodeRadius(receiver), rs = nodeRadius(source);
    const float d = glm::distance(cr, cs);
    float gap = d - rr - rs;
    // At an element end that cannot be split, the nearest its triangle comes to the other's
    // sphere: its bounding sphere is far too loose for a sliver (the grey-white room's skirting
    // strips, 3.4 m long and 0.5 mm wide, overlapped every cluster within 1.7 m of their middle;
    // as the strip could not be split, every such cluster was refined down to its patches against
    // it). An element that can be split is, where its sphere is too loose, and the kernel at the
    // centres stays an estimate of the whole element's; one that cannot has under four times the
    // smallest element's area, so the transfer that estimate may miss is small.
    const auto unsplittable = [&](int n) {
        return !isCluster(n) && !mesh_.subdivisible(element(n));
    };
    const auto nearest = [&](int elementNode, const Vec3& centre, float radius) {
        const std::array<Vec3, 3> t = mesh_.corners(element(elementNode));
        return glm::distance(centre, closestPointOnTriangle(centre, t[0], t[1], t[2])) - radius;
    };
    if (unsplittable(receiver))
        gap = glm::max(gap, nearest(receiver, cs, rs));
    if (unsplittable(source))
        gap = glm::max(gap, nearest(source, cr, rr));
    // Two small nodes are not split for being close (dense foliage would link every pair of its
    // leaves): their kernel takes the softened distance sqrt(d^2 + (r_R + r_S)^2), bounded as
    // the disc approximation of Wallace, Elmquist and Haines 1989 is, and its error is ignored.
    // In a hurry (a soft radius) neither is a pair with an element end that cannot be split,
    // whatever their sizes: such a pair would be split on the other side down to the patches
    // about the element (the grey-white room's time-limited oracle went on 17 levels past its
    // deadline, 3.9 M links to evaluate instead of 1.6 M; docs/radiosity.md, "Under a time
    // limit").
    const bool small = glm::max(rr, rs) < glm::max(clusterMinRadius_, softRadius) ||
                       (softRadius > 0.0f && (unsplittable(receiver) || unsplittable(source)));
    if (!(gap > 0.0f) && !small)
        return k;
    const float dSoft = small && !(gap > 0.0f) ? std::sqrt(d * d + (rr + rs) * (rr + rs)) : d;
    if (!(gap > 0.0f))
        gap = dSoft - rr - rs > 0.0f ? dSoft - rr - rs : dSoft;
    const Vec3 dir = d > 0.0f ? (cs - cr) / d : Vec3(0.0f);
    const auto sideNormal = [&](int n) {
        const int e = element(n);
        return front(n) ? mesh_.normal(e) : -mesh_.normal(e);
    };
    // Cosine at an element end, at the centres. Where the other end is not wholly in front of
    // the element's plane (a chair standing on the floor), the cosine may change sign over it, and
    // the error is the whole kernel: the oracle refines such a link only where the light it
    // carries matters, not up front (which would link every element of the floor with every
    // triangle of every chair on it).
    float cosine = 1.0f;
    bool straddles = false;
    if (!isCluster(receiver)) {
        cosine = glm::dot(sideNormal(receiver), dir);
        straddles = !(cosine * d > rs);
    }
    if (!isCluster(source)) {
        cosine = glm::dot(sideNormal(source), -dir);
        straddles = !(cosine * d > rr);
    }
    cosine = glm::max(cosine, 0.0f);
    const bool clusterToCluster = isCluster(receiver) && isCluster(source);
    const double As = nodeArea(source);
    const double K = As * cosine / ((clusterToCluster ? 16.0 : 4.0) * kPi * dSoft * dSoft);
    const double ratio = small ? 1.0 : static_cast<double>(d) / gap;
    k.K = static_cast<float>(K);
    k.Kmax = static_cast<float>(As / (4.0 * kPi * static_cast<double>(gap) * gap) *
                                (isCluster(receiver) ? 4.0 : 1.0));
    double flatness = 0.0;
    for (const int n : {receiver, source}) {
        if (isCluster(n))
            flatness = std::max(flatness, static_cast<double>((*clusters_)[cluster(n)].flatness));
    }
    k.error =
        straddles && !small ? k.Kmax : static_cast<float>(K * (ratio * ratio + 3.0 * flatness));
    k.linkable = true;
    return k;
}

}  // namespace penumbra
