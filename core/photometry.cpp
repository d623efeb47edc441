#include "core/photometry.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <utility>

namespace penumbra {

namespace {

constexpr double kPiD = 3.14159265358979323846;
constexpr double kRadians = kPiD / 180.0;
// Two angles closer than this (degrees) are the same plane: file angles are short decimals, so
// mirror images such as 180 - 22.5 come out exact or within rounding.
constexpr double kSameAngle = 1e-6;

bool increasing(const std::vector<double>& a) {
    return std::adjacent_find(a.begin(), a.end(), std::greater_equal<>()) == a.end();
}

// Where x falls in the increasing list a: the interval [a[i], a[i + 1]] and the fraction t
// along it, or nothing outside [a.front(), a.back()].
struct Bracket {
    size_t i;
    double t;
};

std::optional<Bracket> bracket(const std::vector<double>& a, double x) {
    if (!(x >= a.front() && x <= a.back()))
        return std::nullopt;
    const size_t upper = size_t(std::upper_bound(a.begin(), a.end(), x) - a.begin());
    const size_t i = std::min(upper, a.size() - 1) - 1;
    return Bracket{i, (x - a[i]) / (a[i + 1] - a[i])};
}

// Degrees into [0, 360).
double wrap360(double c) {
    const double w = std::fmod(c, 360.0);
    return w < 0 ? w + 360.0 : w;
}

// Integrals of the two linear "hat" halves on [a, b] (radians) against sin(t + shift): the
// rising one (t - a) / (b - a) and the falling one (b - t) / (b - a). By parts,
//   integral (t - a) sin(t + s) dt = [sin(t + s) - (t - a) cos(t + s)] from a to b.
// Type C weighs gamma by sin gamma (dOmega = sin g dg dC), type B weighs H by cos H =
// sin(H + pi/2) (H is a latitude about the polar axis Y: dOmega = cos H dH dV).
std::pair<double, double> hatIntegrals(double a, double b, double shift) {
    const double d = b - a;
    const double rising = (std::sin(b + shift) - std::sin(a + shift)) / d - std::cos(b + shift);
    const double whole = std::cos(a + shift) - std::cos(b + shift);
    return {rising, whole - rising};
}

}  // namespace

CandelaTable::CandelaTable(PhotometricSystem system, std::vector<double> planeAngles,
                           std::vector<double> inPlaneAngles, std::vector<double> candela)
    : system_(system),
      planeAngles_(std::move(planeAngles)),
      inPlaneAngles_(std::move(inPlaneAngles)),
      candela_(std::move(candela)) {
    if (planeAngles_.size() < 2 || inPlaneAngles_.size() < 2 || !increasing(planeAngles_) ||
        !increasing(inPlaneAngles_))
        throw std::invalid_argument("CandelaTable: angles must increase, at least two of each");
    if (candela_.size() != planeAngles_.size() * inPlaneAngles_.size())
        throw std::invalid_argument("CandelaTable: one candela value per pair of angles");
    if (!std::all_of(candela_.begin(), candela_.end(),
                     [](double I) { return std::isfinite(I) && I >= 0; }))
        throw std::invalid_argument("CandelaTable: candela values must be finite and >= 0");
    if (system_ == PhotometricSystem::TypeC &&
        (planeAngles_.front() != 0 || planeAngles_.back() != 360))
        throw std::invalid_argument("CandelaTable: type C planes run from 0 to 360");
}

double CandelaTable::intensity(double planeAngle, double inPlaneAngle) const {
    if (system_ == PhotometricSystem::TypeC)
        planeAngle = wrap360(planeAngle);
    const std::optional<Bracket> p = bracket(planeAngles_, planeAngle);
    const std::optional<Bracket> q = bracket(inPlaneAngles_, inPlaneAngle);
    if (!p || !q)
        return 0;
    // Bilinear in the two angles: linear within each plane, then across the planes.
    auto inPlane = [&](size_t plane) {
        return (1 - q->t) * candela(plane, q->i) + q->t * candela(plane, q->i + 1);
    };
    return (1 - p->t) * inPlane(p->i) + p->t * inPlane(p->i + 1);
}

double CandelaTable::intensity(const Vec3& w) const {
    const double x = w.x, y = w.y, z = w.z;
    if (system_ == PhotometricSystem::TypeC) {
        const double gamma = std::atan2(std::hypot(x, y), -z) / kRadians;
        return intensity(std::atan2(y, x) / kRadians, gamma);
    }
    const double V = std::atan2(x, -z) / kRadians;
    const double H = std::atan2(-y, std::hypot(x, z)) / kRadians;
    return intensity(V, H);
}

// The zonal-lumen sum of the interpolating function (IES Lighting Handbook, "zonal lumens"),
// made exact for it: I is a sum of products of hat functions a_p(plane) b_q(angle), so
//   flux = sum_pq I_pq (integral of a_p dplane) (integral of b_q w(angle) dangle),
// the first the trapezoid weight of plane p, the second hatIntegrals() over q's two intervals.
double CandelaTable::flux() const {
    const double shift = system_ == PhotometricSystem::TypeC ? 0.0 : kPiD / 2;
    std::vector<double> planeWeight(planeAngles_.size(), 0.0);
    for (size_t p = 0; p + 1 < planeAngles_.size(); ++p) {
        const double half = 0.5 * (planeAngles_[p + 1] - planeAngles_[p]) * kRadians;
        planeWeight[p] += half;
        planeWeight[p + 1] += half;
    }
    std::vector<double> angleWeight(inPlaneAngles_.size(), 0.0);
    for (size_t q = 0; q + 1 < inPlaneAngles_.size(); ++q) {
        const auto [rising, falling] =
            hatIntegrals(inPlaneAngles_[q] * kRadians, inPlaneAngles_[q + 1] * kRadians, shift);
        angleWeight[q] += falling;
        angleWeight[q + 1] += rising;
    }
    double sum = 0;
    for (size_t p = 0; p < planeAngles_.size(); ++p)
        for (size_t q = 0; q < inPlaneAngles_.size(); ++q)
            sum += planeWeight[p] * angleWeight[q] * candela(p, q);
    return sum;
}

CandelaTable unfoldTypeC(PlaneSymmetry symmetry, const std::vector<double>& storedC,
                         std::vector<double> gamma, const std::vector<double>& candela) {
    // The mirror images of a plane C: the reflections that the symmetry leaves the
    // distribution unchanged by, as functions of C (degrees, wrapped afterwards).
    std::vector<double (*)(double)> images = {[](double c) { return c; }};
    switch (symmetry) {
        case PlaneSymmetry::None:
        case PlaneSymmetry::Rotational:
            break;
        case PlaneSymmetry::AboutC0C180:
            images.push_back([](double c) { return -c; });
            break;
        case PlaneSymmetry::AboutC90C270:
            images.push_back([](double c) { return 180.0 - c; });
            break;
        case PlaneSymmetry::Quadrant:
            images.push_back([](double c) { return -c; });
            images.push_back([](double c) { return 180.0 - c; });
            images.push_back([](double c) { return 180.0 + c; });
            break;
    }
    // Every image of every stored plane, each naming the stored plane it copies; a rotational
    // table is its one plane at 0.
    std::vector<std::pair<double, size_t>> planes;
    if (symmetry == PlaneSymmetry::Rotational)
        planes.emplace_back(0.0, 0);
    else
        for (size_t k = 0; k < storedC.size(); ++k)
            for (auto image : images)
                planes.emplace_back(wrap360(image(storedC[k])), k);
    // In C order; where images coincide (a plane on the mirror, or 360 stored beside 0) the
    // first stored plane stands.
    std::stable_sort(planes.begin(), planes.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    planes.erase(std::unique(planes.begin(), planes.end(),
                             [](const auto& a, const auto& b) {
                                 return b.first - a.first < kSameAngle ||
                                        360.0 - b.first < kSameAngle;
                             }),
                 planes.end());
    if (planes.empty() || planes.front().first > kSameAngle)
        throw std::invalid_argument("unfoldTypeC: the planes must include C = 0");
    planes.front().first = 0.0;
    planes.emplace_back(360.0, planes.front().second);

    std::vector<double> C, I;
    for (const auto& [c, k] : planes) {
        C.push_back(c);
        I.insert(I.end(), candela.begin() + std::ptrdiff_t(k * gamma.size()),
                 candela.begin() + std::ptrdiff_t((k + 1) * gamma.size()));
    }
    return CandelaTable(PhotometricSystem::TypeC, std::move(C), std::move(gamma), std::move(I));
}

namespace {

// An angle list from 0 and its mirror image, -a[n-1] ... -a[1], a[0] ... a[n-1], as the
// indices into the original list (a list that does not start at 0 is kept as it is).
std::vector<size_t> mirroredIndices(const std::vector<double>& a) {
    std::vector<size_t> indices;
    if (a.front() == 0)
        for (size_t i = a.size() - 1; i > 0; --i)
            indices.push_back(i);
    for (size_t i = 0; i < a.size(); ++i)
        indices.push_back(i);
    return indices;
}

}  // namespace

CandelaTable unfoldTypeB(std::vector<double> V, std::vector<double> H,
                         const std::vector<double>& candela) {
    const std::vector<size_t> v = mirroredIndices(V), h = mirroredIndices(H);
    // A mirrored index stands for the negative angle up to the first non-negative one.
    auto angles = [](const std::vector<double>& a, const std::vector<size_t>& indices) {
        std::vector<double> out;
        const size_t mirrored = indices.size() - a.size();
        for (size_t n = 0; n < indices.size(); ++n)
            out.push_back(n < mirrored ? -a[indices[n]] : a[indices[n]]);
        return out;
    };
    std::vector<double> I;
    for (size_t vi : v)
        for (size_t hi : h)
            I.push_back(candela[vi * H.size() + hi]);
    return CandelaTable(PhotometricSystem::TypeB, angles(V, v), angles(H, h), std::move(I));
}

double LdtHeader::lampFlux() const {
    double sum = 0;
    for (const LdtLampSet& set : lampSets)
        sum += set.flux;
    return sum;
}

bool LdtHeader::absolutePhotometry() const {
    return std::any_of(lampSets.begin(), lampSets.end(),
                       [](const LdtLampSet& set) { return set.count < 0; });
}

}  // namespace penumbra
