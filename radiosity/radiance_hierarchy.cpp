// HSA91's GatherRad and PushPullRad over the element quadtrees and the cluster tree.
#include "radiosity/radiance_hierarchy.h"

#include "radiosity/solver_nodes.h"

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>

namespace penumbra {

RadianceHierarchy::RadianceHierarchy(const RadiosityMesh& mesh, const ElementExposure& exposure,
                                     const DirectIrradiance& irradiance,
                                     const ClusterTree* clusters, const LinkTransfer& transfer,
                                     const LinkHierarchy& links,
                                     RadiositySettings::Iteration iteration)
    : mesh_(mesh),
      exposure_(exposure),
      irradiance_(irradiance),
      clusters_(clusters),
      transfer_(transfer),
      links_(links),
      iteration_(iteration) {
    if (clusters_) {
        const size_t n = clusters_->size();
        clusterL_.assign(n, Color(0.0f));
        clusterH_.assign(n, Color(0.0f));
        clusterW_.assign(n, Mat3(0.0f));
        clusterQ_.assign(n, SecondMoment{});
        clusterM_.assign(n, Mat3(0.0f));
        clusterLmin_.assign(n, 0.0f);
        clusterLmax_.assign(n, 0.0f);
    }
}

void RadianceHierarchy::resize() {
    const size_t nodes = 2 * mesh_.elementCount();
    L_.resize(nodes, Color(0.0f));
    Lmin_.resize(nodes, 0.0f);
    Lmax_.resize(nodes, 0.0f);
    H_.resize(nodes, Color(0.0f));
    G_.resize(nodes, Mat3(0.0f));
    Hchild_.resize(nodes, {Color(0.0f), Color(0.0f), Color(0.0f), Color(0.0f)});
    if (!correction_.empty()) {
        correction_.resize(nodes, Color(0.0f));
        directCorrection_.resize(nodes, Color(0.0f));
    }
    if (!direct_.empty())
        direct_.resize(nodes, Color(0.0f));
}

void RadianceHierarchy::inherit(int childNode, int parentNode) {
    const auto child = static_cast<size_t>(childNode), parent = static_cast<size_t>(parentNode);
    L_[child] = L_[parent];
    Lmin_[child] = Lmax_[child] = maxComponent(L_[parent]);
    // The final gather's correction is its patch side's, the same for every leaf of it.
    if (!correction_.empty()) {
        correction_[child] = correction_[parent];
        directCorrection_[child] = directCorrection_[parent];
    }
    if (!direct_.empty())
        direct_[child] = direct_[parent];
}

// L = Le + rho (D + H) over the exposed part; a wholly covered leaf side receives nothing.
Color RadianceHierarchy::leafRadiance(int n, const Color& H) const {
    if (!(exposure_.fraction(n) > 0.0f))
        return emission(n);
    const Color L =
        emission(n) + mesh_.rho(element(n)) * (irradiance_.D(n) + glm::max(H, Color(0.0f)));
    if (correction_.empty())
        return L;
    return glm::max(L + correction_[static_cast<size_t>(n)], emission(n));
}

const Color& RadianceHierarchy::nodeRadiance(int n) const {
    return isCluster(n) ? clusterL_[static_cast<size_t>(cluster(n))] : L_[static_cast<size_t>(n)];
}

float RadianceHierarchy::nodeLmin(int n) const {
    return isCluster(n) ? clusterLmin_[static_cast<size_t>(cluster(n))]
                        : Lmin_[static_cast<size_t>(n)];
}

float RadianceHierarchy::nodeLmax(int n) const {
    return isCluster(n) ? clusterLmax_[static_cast<size_t>(cluster(n))]
                        : Lmax_[static_cast<size_t>(n)];
}

Color RadianceHierarchy::emission(int n) const {
    const int e = element(n);
    return front(n) || mesh_.twoSided(e) ? mesh_.Le(e) : Color(0.0f);
}

// A source cluster's radiance towards the receiver, to first order in the direction (the
// source-side counterpart of sweepCluster's directional push): a side of area A, normal n and
// radiance L radiates the intensity A L max(0, n.d) towards d, 1/4 + n.d / 2 in first-order
// spherical harmonics (Ramamoorthi and Hanrahan 2001), so the cluster radiates
// I(d) = A_c L_c / 4 + M.d / 2 with M = sum over its patches of A (L_front - L_back) n
// (clusterM_), i.e. the isotropic model's mean radiance L_c (Sillion 1995) plus 2 M.d / A_c. The
// isotropic model alone shows every viewer a quarter of a flat cluster's one-sided area: the lit
// side of a wall seen from the room it lights at cos = 0.5 radiates twice what the model sends,
// so in an interior, where every receiver sees the walls' lit sides, the clusters' links carried
// too little (the modern hall's indirect light 13 % low; docs/radiosity.md, "Clusters").
Color RadianceHierarchy::clusterRadianceToward(int cluster, const Vec3& toward) const {
    const Vec3 d = toward - (*clusters_)[cluster].center;
    const float length = glm::length(d);
    const size_t c = static_cast<size_t>(cluster);
    if (!(length > 0.0f))
        return clusterL_[c];
    const float scale = 2.0f / static_cast<float>((*clusters_)[cluster].area);
    return glm::max(clusterL_[c] + scale * (clusterM_[c] * (d / length)), Color(0.0f));
}

Color RadianceHierarchy::sourceRadiance(int receiver, const Link& link) const {
    if (isCluster(link.source))
        return clusterRadianceToward(cluster(link.source), transfer_.nodeCenter(receiver));
    if (link.w[0] < 0.0f)
        return nodeRadiance(link.source);
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
void RadianceHierarchy::gather(int n) {
    Color H(0.0f);
    Mat3 G(0.0f);
    std::array<Color, 4> Hchild{Color(0.0f), Color(0.0f), Color(0.0f), Color(0.0f)};
    for (const Link& link : links_.linksOf(n)) {
        const Color transfer = link.K * sourceRadiance(n, link);
        H += transfer;
        G += glm::outerProduct(transfer, link.g);
        if (link.u[0] >= 0.0f) {
            for (int c = 0; c < RadiosityMesh::kChildren; ++c)
                Hchild[c] += (link.u[c] - 1.0f) * transfer;
        }
    }
    H_[n] = H;
    G_[n] = G;
    Hchild_[n] = Hchild;
}

// A cluster gathers its mean H = sum K L, the vector W = sum K L d of the directions d towards
// the sources (Link::g) and their second moment Q = sum K L d d^T, for the directional push of
// sweepCluster.
void RadianceHierarchy::gatherCluster(int c) {
    Color H(0.0f);
    Mat3 W(0.0f);
    SecondMoment Q{};
    for (const Link& link : links_.linksOf(clusterNode(c))) {
        const Color transfer = link.K * sourceRadiance(clusterNode(c), link);
        H += transfer;
        W += glm::outerProduct(transfer, link.g);
        Q.add(transfer, link.g);
    }
    clusterH_[static_cast<size_t>(c)] = H;
    clusterW_[static_cast<size_t>(c)] = W;
    clusterQ_[static_cast<size_t>(c)] = Q;
}

void RadianceHierarchy::gatherTree(int n) {
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
// use higher-order bases on both). A partly occluded link's transfer is shared by the visible
// fractions of the children instead (Hchild_, setReceiverWeights), which keeps its total too. Each
// leaf forms L = Le + rho (D + H); a parent's radiance is the mean of its children's over its
// exposed part (exposedMean): H, D and L are all means over the exposed parts, which alone send
// and receive light, so that a leaf straddling the foot of a block shows its lit part's light,
// and as a source (whose links' visible fractions count its covered part as hidden) sends it.
// Also pulls the range of max(L) over each node's leaves for the oracle, and adds the leaves'
// change to `sums`.
Color RadianceHierarchy::pushPull(int n, const Color& Hdown, const Mat3& Gdown, ChangeSums& sums) {
    const int e = element(n);
    const Color H = H_[n] + Hdown;
    if (mesh_.isLeaf(e)) {
        // The limiter keeps every link's function non-negative; max() only absorbs rounding.
        const Color L = leafRadiance(n, H);
        const double area = mesh_.area(e);
        sums.change += area * channelSum(glm::abs(L - L_[n]));
        sums.norm += area * channelSum(L);
        L_[n] = L;
        Lmin_[n] = Lmax_[n] = maxComponent(L);
        return L;
    }
    const Mat3 G = G_[n] + Gdown;
    const Vec3 center = mesh_.centroid(e);
    std::array<Color, 4> Lchild;
    float lo = std::numeric_limits<float>::infinity(), hi = 0.0f;
    const int first = mesh_.firstChild(e);
    for (int c = first; c < first + RadiosityMesh::kChildren; ++c) {
        const int child = node(c, front(n));
        Lchild[c - first] =
            pushPull(child, H + Hchild_[n][c - first] + G * (mesh_.centroid(c) - center), G, sums);
        lo = glm::min(lo, Lmin_[child]);
        hi = glm::max(hi, Lmax_[child]);
    }
    L_[n] = exposure_.exposedMean(n, Lchild);
    Lmin_[n] = lo;
    Lmax_[n] = hi;
    return L_[n];
}

// The cluster tree's push-pull (Sillion 1995, section 5): what a cluster gathered, plus what its
// ancestors gathered, goes to every element side inside it, and its radiance is the area-weighted
// mean of its children's. With gatherNow, each cluster and each patch tree gathers just before it
// is pushed (the Gauss-Seidel order of sweep()).
//
// The isotropic model gives every side the same mean H, so the outward backs of the walls of a
// room would get as much as their lit fronts. The push follows the direction of the light
// instead, to second order: the clamped cosine of a side of normal n lit from direction d,
// 4 max(0, n.d) in units of its mean, is 1 + 2 n.d + (5/4) P2(n.d) to second order in spherical
// harmonics (Ramamoorthi and Hanrahan 2001, "An Efficient Representation for Irradiance
// Environment Maps", SIGGRAPH '01: the clamped cosine's Legendre coefficients are 1/4, 1/2 and
// 5/16; P2(x) = (3x^2 - 1) / 2), so a side gets H + 2 W.n + (5/8)(3 n^T Q n - H) with W and Q the
// gathered sum_links K L d and sum_links K L d d^T, clipped at 0. Over the sides of a closed
// object (normals every way) the two higher terms average to zero, so the push keeps the light
// the cluster received; the first-order push alone had to be clipped where it went negative
// (1 - 2 = -1 on the side facing away from a single source), which added 12.5 % to a sphere lit
// from one side once the far side's rays no longer counted as occluded (visibility()), and gave
// a side facing the source 3H of its 4H (4.25H now). (Giving the clipped side's share to the
// other side, as once done, capped a facing patch at 2H; in the modern hall, with the isotropic
// source, the indirect light on the walls was 13 % low, 10 % with the first-order push and the
// directional source.)
// Also pulls each cluster's M (clusterRadianceToward) from its patches' two sides.
Color RadianceHierarchy::sweepCluster(int c, const Color& Hdown, const Mat3& Wdown,
                                      const SecondMoment& Qdown, ChangeSums& sums, bool gatherNow) {
    if (gatherNow)
        gatherCluster(c);
    const Color H = clusterH_[static_cast<size_t>(c)] + Hdown;
    const Mat3 W = clusterW_[static_cast<size_t>(c)] + Wdown;
    const SecondMoment Q = clusterQ_[static_cast<size_t>(c)] + Qdown;
    const Cluster& cl = (*clusters_)[c];
    Color sum(0.0f);
    Mat3 M(0.0f);
    float lo = std::numeric_limits<float>::infinity(), hi = 0.0f;
    const auto add = [&](int n, const Color& L, double area) {
        sum += static_cast<float>(area) * L;
        lo = glm::min(lo, nodeLmin(n));
        hi = glm::max(hi, nodeLmax(n));
    };
    if (cl.isLeaf()) {
        for (const int patch : clusters_->patches(c)) {
            const Vec3& normal = mesh_.normal(patch);
            const Color slope = 2.0f * (W * normal);
            // (5/8)(3 n^T Q n - H), the same on both sides.
            const Color even = 0.625f * (3.0f * Q.along(normal) - H);
            const std::array<Color, 2> Hside{
                glm::max(H + slope + even, Color(0.0f)),
                glm::max(H - slope + even, Color(0.0f))};  // front, back
            std::array<Color, 2> L;                        // front, back
            for (const bool side : {true, false}) {
                const int n = node(patch, side);
                if (gatherNow)
                    gatherTree(n);
                L[side ? 0 : 1] = pushPull(n, Hside[side ? 0 : 1], Mat3(0.0f), sums);
                add(n, L[side ? 0 : 1], mesh_.area(patch));
            }
            M += glm::outerProduct(static_cast<float>(mesh_.area(patch)) * (L[0] - L[1]), normal);
        }
    } else {
        for (const int child : cl.children) {
            add(clusterNode(child), sweepCluster(child, H, W, Q, sums, gatherNow),
                (*clusters_)[child].area);
            M += clusterM_[static_cast<size_t>(child)];
        }
    }
    const size_t i = static_cast<size_t>(c);
    clusterM_[i] = M;
    clusterL_[i] = sum / static_cast<float>(cl.area);
    clusterLmin_[i] = lo;
    clusterLmax_[i] = hi;
    return clusterL_[i];
}

// Pushes and pulls every tree with what was gathered last, without gathering.
void RadianceHierarchy::pushPullAll() {
    ChangeSums ignored;
    if (clusters_) {
        sweepCluster(0, Color(0.0f), Mat3(0.0f), SecondMoment{}, ignored, false);
        return;
    }
    const int roots = static_cast<int>(2 * mesh_.patchCount());
    for (int r = 0; r < roots; ++r)
        pushPull(r, Color(0.0f), Mat3(0.0f), ignored);
}

// One sweep over all patch sides; returns the area-weighted L1 norms over the leaves of the change
// ||L_k - L_{k-1}|| and of L_k, whose ratio is also the relative residual of the Jacobi form of
// the equation at L_{k-1}. Jacobi gathers everything from the previous sweep's radiance (in
// parallel), then pushes and pulls each tree; Gauss-Seidel gathers and pushes-pulls one patch
// side at a time, so later patches already see the new radiance of earlier ones (Cohen and
// Wallace 1993, chapter 5, applied per tree as in HSA91's "SolveSystem").
ChangeSums RadianceHierarchy::sweep() {
    const int roots = static_cast<int>(2 * mesh_.patchCount());
    ChangeSums total;
    if (clusters_) {
        if (iteration_ == RadiositySettings::Iteration::Jacobi) {
            tbb::parallel_for(size_t(0), links_.elementSides(),
                              [&](size_t n) { gather(static_cast<int>(n)); });
            tbb::parallel_for(size_t(0), links_.clusters(),
                              [&](size_t c) { gatherCluster(static_cast<int>(c)); });
        }
        sweepCluster(0, Color(0.0f), Mat3(0.0f), SecondMoment{}, total,
                     iteration_ == RadiositySettings::Iteration::GaussSeidel);
    } else if (iteration_ == RadiositySettings::Iteration::Jacobi) {
        tbb::parallel_for(size_t(0), links_.elementSides(),
                          [&](size_t n) { gather(static_cast<int>(n)); });
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
    return total;
}

// The first reflection of the sources' light, for indirectRadiance(): what each leaf side gathers
// from the emission alone, through its own links and its ancestors', plus the punctual lights'
// direct light, times rho: direct_i = rho_i (D_i + sum_j K_ij Le_j) (D_i of the sources only: not
// the flux transferred through specular surfaces, which is indirect light), pushed and pulled like
// the whole solution. The indirect part L - Le - direct is then the solution's light that has been
// reflected at least twice (paths L D D+), by the same links, form factors and visibility as the
// solution itself, so that a ray tracer adding its own direct light back counts every path once
// (the two-pass method of Wallace, Cohen and Greenberg 1987; Sillion and Puech 1989).
//
// It is one Jacobi sweep of the machinery the solution uses, run on the emission: the solution is
// set aside, the emission is pushed and pulled to every node (a gather of nothing, with D = 0),
// every node gathers from it, the push-pull forms Le + rho (D + H_e) at the leaves, and the
// solution is put back. The cost is one sweep.
void RadianceHierarchy::computeDirectPart(DirectIrradiance& irradiance) {
    std::vector<Color> L = L_, H = H_, clusterL = clusterL_, clusterH = clusterH_;
    std::vector<std::array<Color, 4>> Hchild = Hchild_;
    std::vector<Mat3> G = G_, clusterW = clusterW_, clusterM = clusterM_;
    std::vector<SecondMoment> clusterQ = clusterQ_;
    std::vector<float> Lmin = Lmin_, Lmax = Lmax_, clusterLmin = clusterLmin_,
                       clusterLmax = clusterLmax_;
    // The links' first reflection alone: the final gather's correction of it is kept apart
    // (directCorrection_), and the rest of its correction is indirect light.
    std::vector<Color> correction;
    std::swap(correction, correction_);
    // The emission at every node (a parent's: its leaves' area mean, as a source shows it).
    irradiance.show(DirectIrradiance::Part::None);
    std::fill(H_.begin(), H_.end(), Color(0.0f));
    std::fill(Hchild_.begin(), Hchild_.end(),
              std::array<Color, 4>{Color(0.0f), Color(0.0f), Color(0.0f), Color(0.0f)});
    std::fill(G_.begin(), G_.end(), Mat3(0.0f));
    std::fill(clusterH_.begin(), clusterH_.end(), Color(0.0f));
    std::fill(clusterW_.begin(), clusterW_.end(), Mat3(0.0f));
    std::fill(clusterQ_.begin(), clusterQ_.end(), SecondMoment{});
    pushPullAll();
    // Every node gathers from the emission; then Le + rho (D + H_e) at the leaves, D of the
    // sources only (the transferred flux is indirect light).
    irradiance.show(DirectIrradiance::Part::Sources);
    tbb::parallel_for(size_t(0), links_.elementSides(),
                      [&](size_t n) { gather(static_cast<int>(n)); });
    tbb::parallel_for(size_t(0), links_.clusters(),
                      [&](size_t c) { gatherCluster(static_cast<int>(c)); });
    pushPullAll();
    irradiance.show(DirectIrradiance::Part::All);
    direct_.assign(L_.size(), Color(0.0f));
    for (size_t n = 0; n < L_.size(); ++n) {
        if (mesh_.isLeaf(element(static_cast<int>(n))))
            direct_[n] = glm::max(L_[n] - emission(static_cast<int>(n)), Color(0.0f));
    }
    L_ = std::move(L);
    H_ = std::move(H);
    Hchild_ = std::move(Hchild);
    G_ = std::move(G);
    Lmin_ = std::move(Lmin);
    Lmax_ = std::move(Lmax);
    clusterL_ = std::move(clusterL);
    clusterH_ = std::move(clusterH);
    clusterW_ = std::move(clusterW);
    clusterQ_ = std::move(clusterQ);
    clusterM_ = std::move(clusterM);
    clusterLmin_ = std::move(clusterLmin);
    clusterLmax_ = std::move(clusterLmax);
    correction_ = std::move(correction);
}

Color RadianceHierarchy::elementDirect(int e, bool side) const {
    const auto n = static_cast<size_t>(node(e, side));
    if (n >= direct_.size())
        return Color(0.0f);
    if (n >= directCorrection_.size())
        return direct_[n];
    return glm::max(direct_[n] + directCorrection_[n], Color(0.0f));
}

Color RadianceHierarchy::elementIndirect(int e, bool side) const {
    const int n = node(e, side);
    if (static_cast<size_t>(n) >= direct_.size() || !mesh_.isLeaf(e))
        return Color(0.0f);
    return glm::max(L_[n] - emission(n) - elementDirect(e, side), Color(0.0f));
}

}  // namespace penumbra
