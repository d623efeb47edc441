// Form factors between planar polygons: Lambert's contour integral and its area average.
#include "radiosity/form_factor.h"

#include "core/batch_math.h"

#include <glm/gtc/constants.hpp>

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace penumbra {
namespace {

using DVec3 = glm::dvec3;

constexpr double kPiD = glm::pi<double>();

// An edge whose sine, as seen from p, is below this is treated as passing through p: its plane
// through p is undefined and its term is dropped. Double rounding of coordinates given in float
// leaves sines of ~1e-16, so only points on the edge's line within rounding are affected.
constexpr double kEdgeSine = 1e-12;

// Lambert's terms of a contour's edges (a, b), both relative to p, summed: the angle gamma the
// edge subtends at p times the cosine between n and the normal of the plane through p and the
// edge (Baum, Rushmeier and Winget 1989, "Improving Radiosity Solutions Through the Use of
// Analytically Determined Form-Factors", Section 2; Hottel and Sarofim 1967). gamma from atan2 of
// |a x b| and a . b is accurate at every angle, including near 0 and pi. The atan2s, a third of
// the radiosity solve's time when taken one by one, are taken four edges at a time.
class EdgeTermSum {
  public:
    explicit EdgeTermSum(const DVec3& n) : n_(n) {}

    void add(const DVec3& a, const DVec3& b) {
        const DVec3 c = glm::cross(a, b);
        const double sineSquared = glm::dot(c, c);
        if (!(sineSquared > kEdgeSine * kEdgeSine * glm::dot(a, a) * glm::dot(b, b)))
            return;
        const double sine = std::sqrt(sineSquared);
        sine_[size_] = sine;
        cosine_[size_] = glm::dot(a, b);
        weight_[size_] = glm::dot(n_, c) / sine;
        if (++size_ == kAtan2BatchSize)
            flush();
    }

    double total() {
        flush();
        return sum_;
    }

  private:
    void flush() {
        if (size_ == 0)
            return;
        // Unused lanes: atan2(0, 1) = 0, weighed 0.
        for (size_t i = size_; i < kAtan2BatchSize; ++i) {
            sine_[i] = 0.0;
            cosine_[i] = 1.0;
            weight_[i] = 0.0;
        }
        const Atan2Batch gamma = atan2Batch(sine_, cosine_);
        for (size_t i = 0; i < kAtan2BatchSize; ++i)
            sum_ += gamma[i] * weight_[i];
        size_ = 0;
    }

    DVec3 n_;
    Atan2Batch sine_{}, cosine_{}, weight_{};
    size_t size_ = 0;
    double sum_ = 0.0;
};

// Heights within this angle (radians) of a plane, seen from the plane's reference point, count as
// on the plane. It absorbs the rounding of vertex coordinates given in float (2^-24 ~ 6e-8), so
// that coplanar polygons, and a polygon and itself, never see each other through rounding; a
// vertex this close to the plane changes a form factor by about as much.
constexpr double kPlaneAngle = 1e-6;

// Sutherland-Hodgman clip of a convex polygon to the half-space n . (x - origin) >= 0, streamed:
// emit(x) receives the clipped polygon's vertices in order. Vertices on the plane count as inside,
// so edges lying in it are kept whole. Returns false, and the emitted vertices are to be ignored,
// when no vertex is strictly above the plane (nothing, or a flat polygon in the plane).
template <typename Emit>
bool clipToHalfSpace(std::span<const DVec3> polygon, const DVec3& origin, const DVec3& n,
                     const Emit& emit) {
    const auto height = [&](const DVec3& x) {
        const DVec3 r = x - origin;
        const double h = glm::dot(n, r);
        return h * h <= kPlaneAngle * kPlaneAngle * glm::dot(r, r) ? 0.0 : h;
    };
    DVec3 a = polygon.back();
    double ha = height(a);
    bool anyAbove = false;
    for (const DVec3& b : polygon) {
        const double hb = height(b);
        if ((ha < 0.0 && hb > 0.0) || (ha > 0.0 && hb < 0.0))
            emit(a + (b - a) * (ha / (ha - hb)));
        if (hb >= 0.0)
            emit(b);
        anyAbove = anyAbove || hb > 0.0;
        a = b;
        ha = hb;
    }
    return anyAbove;
}

// Lambert's formula F = 1/(2 pi) |sum_i gamma_i n . (R_i x R_i+1) / |R_i x R_i+1||, R_i = v_i - p,
// over the polygon clipped to the tangent plane of p. The clipped contour is streamed: each
// vertex closes an edge with the previous one, so nothing is stored. The absolute value makes the
// result independent of the winding.
double pointToPolygon(const DVec3& p, const DVec3& n, std::span<const DVec3> polygon) {
    if (polygon.size() < 3)
        return 0.0;
    EdgeTermSum sum(n);
    DVec3 first(0.0), previous(0.0);
    bool started = false;
    const bool above = clipToHalfSpace(polygon, p, n, [&](const DVec3& x) {
        const DVec3 r = x - p;
        if (started)
            sum.add(previous, r);
        else
            first = r;
        previous = r;
        started = true;
    });
    // A polygon on or below the tangent plane subtends no projected solid angle.
    if (!above)
        return 0.0;
    sum.add(previous, first);
    return std::abs(sum.total()) / (2.0 * kPiD);
}

// Newell's normal: twice the area times the unit normal, robust for nearly degenerate polygons.
DVec3 newellNormal(std::span<const DVec3> polygon) {
    DVec3 sum(0.0);
    for (size_t i = 0; i < polygon.size(); ++i)
        sum += glm::cross(polygon[i], polygon[(i + 1) % polygon.size()]);
    return sum;
}

// A polygon's vertices in double precision: on the stack for up to kStackVertices (the solver's
// triangles, called millions of times), on the heap beyond.
class DoublePolygon {
  public:
    explicit DoublePolygon(std::span<const Vec3> polygon) : size_(polygon.size()) {
        if (size_ > kStackVertices)
            heap_.resize(size_);
        DVec3* out = size_ > kStackVertices ? heap_.data() : stack_.data();
        for (size_t i = 0; i < size_; ++i)
            out[i] = DVec3(polygon[i]);
    }
    std::span<const DVec3> span() const {
        return {size_ > kStackVertices ? heap_.data() : stack_.data(), size_};
    }

  private:
    static constexpr size_t kStackVertices = 8;
    size_t size_;
    std::array<DVec3, kStackVertices> stack_;
    std::vector<DVec3> heap_;
};

// Gauss-Legendre rule with n points mapped to [0, 1] (weights sum to 1). Nodes are the roots of
// the Legendre polynomial P_n, found by Newton's method on the three-term recurrence
// (n+1) P_n+1 = (2n+1) x P_n - n P_n-1, with the weights 2 / ((1 - x^2) P_n'(x)^2) of Abramowitz
// and Stegun 1964, Eq. 25.4.29.
struct QuadratureRule {
    std::vector<double> x, w;
};

QuadratureRule gaussLegendre(int n) {
    QuadratureRule rule;
    rule.x.resize(n);
    rule.w.resize(n);
    for (int i = 0; i < (n + 1) / 2; ++i) {
        // Initial guess: the leading term of Tricomi's asymptotic form of the i-th largest root.
        double z = std::cos(kPiD * (i + 0.75) / (n + 0.5));
        double derivative = 1.0;
        for (int iteration = 0; iteration < 100; ++iteration) {
            double pn = z, pnMinus1 = 1.0;
            for (int k = 2; k <= n; ++k) {
                const double next = ((2 * k - 1) * z * pn - (k - 1) * pnMinus1) / k;
                pnMinus1 = pn;
                pn = next;
            }
            derivative = n * (z * pn - pnMinus1) / (z * z - 1.0);
            const double step = pn / derivative;
            z -= step;
            if (std::abs(step) < 1e-15)
                break;
        }
        const double weight = 1.0 / ((1.0 - z * z) * derivative * derivative);
        rule.x[i] = 0.5 * (1.0 - z);
        rule.x[n - 1 - i] = 0.5 * (1.0 + z);
        rule.w[i] = rule.w[n - 1 - i] = weight;
    }
    return rule;
}

// The rules of orders up to kCachedOrders, computed once (a function-local static is initialised
// once, thread-safely): the solver asks for them millions of times.
constexpr int kCachedOrders = 16;
const QuadratureRule& cachedGaussLegendre(int n) {
    static const std::array<QuadratureRule, kCachedOrders + 1> rules = [] {
        std::array<QuadratureRule, kCachedOrders + 1> r;
        for (int order = 1; order <= kCachedOrders; ++order)
            r[static_cast<size_t>(order)] = gaussLegendre(order);
        return r;
    }();
    return rules[static_cast<size_t>(n)];
}

// int_T f dA over a triangle by the collapsed map of the unit square (Duffy 1982, "Quadrature
// over a pyramid or cube of integrands with a singularity at a vertex", SIAM J. Numer. Anal.
// 19(6)): x(s, t) = v0 + s ((1 - t)(v1 - v0) + t (v2 - v0)), dA = 2 A s ds dt.
template <typename F>
double integrateTriangle(const DVec3& v0, const DVec3& v1, const DVec3& v2,
                         const QuadratureRule& rule, const F& f) {
    const double twiceArea = glm::length(glm::cross(v1 - v0, v2 - v0));
    double sum = 0.0;
    for (size_t i = 0; i < rule.x.size(); ++i) {
        const double s = rule.x[i];
        for (size_t j = 0; j < rule.x.size(); ++j) {
            const double t = rule.x[j];
            const DVec3 x = v0 + s * ((1.0 - t) * (v1 - v0) + t * (v2 - v0));
            sum += rule.w[i] * rule.w[j] * s * f(x);
        }
    }
    return sum * twiceArea;
}

// int_Q f dA over a convex quad by its bilinear map from the unit square,
// dA = |dx/ds x dx/dt| ds dt.
template <typename F>
double integrateQuad(std::span<const DVec3> q, const QuadratureRule& rule, const F& f) {
    double sum = 0.0;
    for (size_t i = 0; i < rule.x.size(); ++i) {
        const double s = rule.x[i];
        for (size_t j = 0; j < rule.x.size(); ++j) {
            const double t = rule.x[j];
            const DVec3 x =
                (1 - s) * (1 - t) * q[0] + s * (1 - t) * q[1] + s * t * q[2] + (1 - s) * t * q[3];
            const DVec3 ds = (1 - t) * (q[1] - q[0]) + t * (q[2] - q[3]);
            const DVec3 dt = (1 - s) * (q[3] - q[0]) + s * (q[2] - q[1]);
            sum += rule.w[i] * rule.w[j] * glm::length(glm::cross(ds, dt)) * f(x);
        }
    }
    return sum;
}

// int_P f dA over a convex polygon: one map for a triangle or a quad, a fan of triangles
// otherwise (a clipped quad can have five vertices).
template <typename F>
double integratePolygon(std::span<const DVec3> polygon, const QuadratureRule& rule, const F& f) {
    if (polygon.size() == 4)
        return integrateQuad(polygon, rule, f);
    double sum = 0.0;
    for (size_t i = 1; i + 1 < polygon.size(); ++i)
        sum += integrateTriangle(polygon[0], polygon[i], polygon[i + 1], rule, f);
    return sum;
}

}  // namespace

double pointToPolygonFormFactor(const Vec3& p, const Vec3& n, std::span<const Vec3> polygon) {
    const DVec3 nd(n);
    const double length = glm::length(nd);
    if (!(length > 0.0))
        return 0.0;
    return pointToPolygon(DVec3(p), nd / length, DoublePolygon(polygon).span());
}

double areaToAreaFormFactor(std::span<const Vec3> from, std::span<const Vec3> to, int order) {
    if (order < 1)
        throw std::invalid_argument("areaToAreaFormFactor: order must be >= 1, got " +
                                    std::to_string(order));
    if (from.size() < 3 || to.size() < 3)
        return 0.0;
    const DoublePolygon fromPolygon(from), toPolygon(to);
    const std::span<const DVec3> fromD = fromPolygon.span(), toD = toPolygon.span();
    const DVec3 fromNormal = newellNormal(fromD), toNormal = newellNormal(toD);
    const double fromArea = 0.5 * glm::length(fromNormal);
    if (!(fromArea > 0.0) || !(glm::length(toNormal) > 0.0))
        return 0.0;
    const DVec3 nFrom = glm::normalize(fromNormal);
    // Only the part of `from` in front of `to` sees its front side.
    // A convex polygon clipped by a plane gains at most one vertex.
    std::vector<DVec3> visible;
    visible.reserve(from.size() + 1);
    if (!clipToHalfSpace(fromD, toD[0], glm::normalize(toNormal),
                         [&](const DVec3& x) { visible.push_back(x); }))
        return 0.0;
    const QuadratureRule uncached = order > kCachedOrders ? gaussLegendre(order) : QuadratureRule{};
    const QuadratureRule& rule = order > kCachedOrders ? uncached : cachedGaussLegendre(order);
    const double integral = integratePolygon(
        visible, rule, [&](const DVec3& x) { return pointToPolygon(x, nFrom, toD); });
    return integral / fromArea;
}

double diskApproximationFormFactor(const Vec3& p, const Vec3& np, const Vec3& q, const Vec3& nq,
                                   double areaQ) {
    const DVec3 d = DVec3(q) - DVec3(p);
    const double r2 = glm::dot(d, d);
    if (!(r2 > 0.0) || !(areaQ > 0.0))
        return 0.0;
    const double r = std::sqrt(r2);
    const double cosP = glm::dot(DVec3(np), d) / r;
    const double cosQ = -glm::dot(DVec3(nq), d) / r;
    if (cosP <= 0.0 || cosQ <= 0.0)
        return 0.0;
    return areaQ * cosP * cosQ / (kPiD * r2 + areaQ);
}

double triangleSolidAngle(const Vec3& o, const std::array<Vec3, 3>& corners) {
    const glm::dvec3 a = glm::dvec3(corners[0]) - glm::dvec3(o);
    const glm::dvec3 b = glm::dvec3(corners[1]) - glm::dvec3(o);
    const glm::dvec3 c = glm::dvec3(corners[2]) - glm::dvec3(o);
    const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
    const double numerator = glm::dot(a, glm::cross(c, b));
    const double denominator =
        la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la;
    return 2.0 * std::atan2(numerator, denominator);
}

}  // namespace penumbra
