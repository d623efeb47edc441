#include "radiosity/link_hierarchy.h"

#include "radiosity/form_factor.h"
#include "radiosity/solver_nodes.h"

#include <tbb/parallel_for.h>

namespace penumbra {

namespace {

// Whether a link's visible fraction is below 1 in some channel (K = F V).
bool partlyOccluded(const Color& K, float F) {
    return glm::min(K.r, glm::min(K.g, K.b)) < F;
}

// A link's visible fraction, the mean over the channels.
float meanVisibility(const Color& K, float F) {
    return (K.r + K.g + K.b) / (3.0f * F);
}

}  // namespace

LinkHierarchy::LinkHierarchy(const RadiosityMesh& mesh, const ElementExposure& exposure,
                             size_t clusters)
    : mesh_(mesh), exposure_(exposure), clusterLinks_(clusters) {}

void LinkHierarchy::resize() {
    links_.resize(2 * mesh_.elementCount());
}

std::vector<Link>& LinkHierarchy::linksOf(int n) {
    return isCluster(n) ? clusterLinks_[static_cast<size_t>(cluster(n))]
                        : links_[static_cast<size_t>(n)];
}

const std::vector<Link>& LinkHierarchy::linksOf(int n) const {
    return isCluster(n) ? clusterLinks_[static_cast<size_t>(cluster(n))]
                        : links_[static_cast<size_t>(n)];
}

size_t LinkHierarchy::linkCount() const {
    size_t count = 0;
    for (const auto& links : links_)
        count += links.size();
    for (const auto& links : clusterLinks_)
        count += links.size();
    return count;
}

// The source side of a link at first order: when the source has children, its radiance is not
// uniform, and the light the receiver gathers weighs each child by its share of the form factor,
// w_c = F(x -> child c) / sum_c F(x -> child c) at the receiver's centroid x (exact
// point-to-polygon values, form_factor.h), rather than by its area. The mean radiance alone leaves
// the first-order term of the source's gradient against the kernel's: measured over a lit room,
// 1 % of the interreflected light lost at epsilon = 0.01. This is the source side of a two-level
// quadrature of the transfer (Cohen and Wallace 1993, chapter 4, "area-to-area form factors by
// numerical integration"), and for a partly occluded link the quadrature takes each child's own
// visible fraction V_c too (from the link's own rays, Link::childV): w_c = F_c V_c / sum_c F_c V_c.
// With the link's one visible fraction
// instead, the children the receiver cannot see (the floor under a block, in its shadow, dark)
// counted as much as the lit ones it sees, and the link carried their mean: the correlation of
// the source's radiance with its visibility was lost, always in the same direction, as what is
// hidden from a receiver is mostly also hidden from the light. That was half of the hierarchical
// solution's deficit against the dense solve on the same leaves on the Cornell box (floor -0.8 %,
// back wall -0.5 %, ceiling -0.45 %, block faces to -3 %).
void LinkHierarchy::setSourceWeights(int receiver, Link& link) const {
    if (isCluster(receiver) || isCluster(link.source))
        return;
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
    for (int c = 0; c < RadiosityMesh::kChildren; ++c)
        F[c] = pointToPolygonFormFactor(x, nr, mesh_.corners(first + c));
    if (partlyOccluded(link.K, link.F)) {
        const std::array<float, 4> V =
            ChildVisibility::decode(link.childV.source, meanVisibility(link.K, link.F));
        std::array<double, 4> FV{};
        for (int c = 0; c < RadiosityMesh::kChildren; ++c)
            FV[c] = F[c] * V[c];
        // The children the rays saw lit have no form factor at the receiver's centroid, though
        // the link carries light: keep the form factor's shares.
        if (FV[0] + FV[1] + FV[2] + FV[3] > 0.0)
            F = FV;
    }
    const double sum = F[0] + F[1] + F[2] + F[3];
    if (!(sum > 0.0))
        return;
    for (int c = 0; c < RadiosityMesh::kChildren; ++c)
        link.w[c] = static_cast<float>(F[c] / sum);
}

// The receiver side of the same correlation: a link gathered by an element side with children
// gives them its transfer in proportion to their own visible fractions of the source (over their
// exposed parts, from the link's own rays: visibility(), Link::childV), u_c = V_c sum_k a_k / sum_k
// a_k V_k with a_k the children's exposed fractions (the children have equal areas, so the shares
// keep the transfer over the exposed area, sum_c a_c u_c = sum_c a_c), rather than evenly. Evenly,
// the children hidden from the source (under a block standing on the floor, above the light that
// hangs 0.1 mm under the Cornell ceiling) received light they cannot have, which is lost, since
// they show it to nobody, and the children that see the source got too little. An unoccluded link,
// or one whose children all miss the source, shares evenly (u = 1). Only one level down: the
// children pass what they get evenly to their own children.
void LinkHierarchy::setReceiverWeights(int receiver, Link& link) const {
    if (isCluster(receiver) || isCluster(link.source) || mesh_.isLeaf(element(receiver)))
        return;
    link.u = {1.0f, 1.0f, 1.0f, 1.0f};
    if (!partlyOccluded(link.K, link.F))
        return;
    const std::array<float, 4> V =
        ChildVisibility::decode(link.childV.receiver, meanVisibility(link.K, link.F));
    const int first = mesh_.firstChild(element(receiver));
    float sum = 0.0f, exposed = 0.0f;
    for (int c = 0; c < RadiosityMesh::kChildren; ++c) {
        const float a = exposure_.fraction(node(first + c, front(receiver)));
        sum += a * V[c];
        exposed += a;
    }
    if (!(sum > 0.0f))
        return;
    for (int c = 0; c < RadiosityMesh::kChildren; ++c)
        link.u[c] = V[c] * exposed / sum;
}

void LinkHierarchy::updateChildWeights() {
    tbb::parallel_for(size_t(0), links_.size(), [&](size_t n) {
        for (Link& link : links_[n]) {
            if (link.w[0] < 0.0f)
                setSourceWeights(static_cast<int>(n), link);
            if (link.u[0] < 0.0f)
                setReceiverWeights(static_cast<int>(n), link);
        }
    });
}

}  // namespace penumbra
