#include "core/goniometric_light.h"

#include "core/sampling.h"

#include <algorithm>
#include <cmath>
#include <span>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace penumbra {
namespace {

constexpr double kRadians = 3.14159265358979323846 / 180.0;

// The coordinate within a plane in which solid angle is uniform, d omega = d(plane angle, rad)
// d(area): type C weighs gamma by sin gamma, so area = -cos gamma; type B weighs H by cos H
// (H is a latitude about the axis Y), so area = sin H. Both increase with the angle over the
// tables' ranges (gamma 0-180, H -90-90).
double areaCoordinate(PhotometricSystem system, double inPlaneDegrees) {
    const double angle = inPlaneDegrees * kRadians;
    return system == PhotometricSystem::TypeC ? -std::cos(angle) : std::sin(angle);
}

double inPlaneDegrees(PhotometricSystem system, double area) {
    area = std::clamp(area, -1.0, 1.0);
    return (system == PhotometricSystem::TypeC ? std::acos(-area) : std::asin(area)) / kRadians;
}

// The direction of the luminaire frame at a plane angle and an angle within the plane (degrees),
// by the formulas of core/photometry.h's header.
Vec3 direction(PhotometricSystem system, double planeDegrees, double inPlane) {
    const double a = planeDegrees * kRadians, b = inPlane * kRadians;
    if (system == PhotometricSystem::TypeC)
        return Vec3(float(std::sin(b) * std::cos(a)), float(std::sin(b) * std::sin(a)),
                    float(-std::cos(b)));
    return Vec3(float(std::cos(b) * std::sin(a)), float(-std::sin(b)),
                float(-std::cos(b) * std::cos(a)));
}

// And back: the (plane, in-plane) angles (degrees) of direction w, as
// CandelaTable::intensity(Vec3) finds them, a type C plane angle wrapped into 0-360.
std::pair<double, double> angles(PhotometricSystem system, const Vec3& w) {
    const double x = w.x, y = w.y, z = w.z;
    if (system == PhotometricSystem::TypeC) {
        const double C = std::atan2(y, x) / kRadians;
        return {C < 0 ? C + 360.0 : C, std::atan2(std::hypot(x, y), -z) / kRadians};
    }
    return {std::atan2(x, -z) / kRadians, std::atan2(-y, std::hypot(x, z)) / kRadians};
}

// The table's angles with every interval cut into equal pieces of at most `step` degrees.
std::vector<double> subdivide(const std::vector<double>& angles, double step) {
    std::vector<double> edges{angles.front()};
    for (size_t i = 0; i + 1 < angles.size(); ++i) {
        const double a = angles[i], b = angles[i + 1];
        const int pieces = std::max(1, int(std::ceil((b - a) / step)));
        for (int k = 1; k < pieces; ++k)
            edges.push_back(a + (b - a) * k / pieces);
        edges.push_back(b);
    }
    return edges;
}

// The interval [edges[i], edges[i + 1]] holding x, or nothing outside the edges.
std::optional<size_t> intervalOf(const std::vector<double>& edges, double x) {
    if (!(x >= edges.front() && x <= edges.back()))
        return std::nullopt;
    const size_t upper = size_t(std::upper_bound(edges.begin(), edges.end(), x) - edges.begin());
    return std::min(upper, edges.size() - 1) - 1;
}

const CandelaTable& checkedTable(const std::shared_ptr<const CandelaTable>& table) {
    if (!table)
        throw std::invalid_argument("GoniometricLight: no candela table");
    return *table;
}

}  // namespace

CandelaDistribution::CandelaDistribution(const CandelaTable& table)
    : system_(table.system()),
      planeEdges_(subdivide(table.planeAngles(), kMaxCellDegrees)),
      inPlaneEdges_(subdivide(table.inPlaneAngles(), kMaxCellDegrees)) {
    const bool typeC = system_ == PhotometricSystem::TypeC;
    const double lowest = typeC ? 0.0 : -90.0, highest = typeC ? 180.0 : 90.0;
    if (inPlaneEdges_.front() < lowest || inPlaneEdges_.back() > highest)
        throw std::invalid_argument("CandelaDistribution: angles within the planes out of range");

    // The intensity at every corner of the cells, (P + 1) x (Q + 1).
    const size_t P = planeEdges_.size() - 1, Q = inPlaneEdges_.size() - 1;
    std::vector<double> corner((P + 1) * (Q + 1));
    for (size_t i = 0; i <= P; ++i)
        for (size_t j = 0; j <= Q; ++j)
            corner[i * (Q + 1) + j] = table.intensity(planeEdges_[i], inPlaneEdges_[j]);
    std::vector<double> area(Q + 1);
    for (size_t j = 0; j <= Q; ++j)
        area[j] = areaCoordinate(system_, inPlaneEdges_[j]);

    // Each cell's weight, the mean of its corners times its solid angle; each slice's total.
    std::vector<double> weight(P * Q), solidAngle(P * Q), sliceWeight(P, 0.0);
    for (size_t p = 0; p < P; ++p)
        for (size_t q = 0; q < Q; ++q) {
            const double mean =
                0.25 * (corner[p * (Q + 1) + q] + corner[p * (Q + 1) + q + 1] +
                        corner[(p + 1) * (Q + 1) + q] + corner[(p + 1) * (Q + 1) + q + 1]);
            solidAngle[p * Q + q] =
                (planeEdges_[p + 1] - planeEdges_[p]) * kRadians * (area[q + 1] - area[q]);
            weight[p * Q + q] = mean * solidAngle[p * Q + q];
            sliceWeight[p] += weight[p * Q + q];
        }

    // A slice from the marginal, then a cell of it from its conditional (pbrt-v4's
    // PiecewiseConstant2D); a cell's density is its probability over its solid angle.
    double total = 0.0;
    for (double w : sliceWeight)
        total += w;
    density_.assign(P * Q, 0.0f);
    if (!(total > 0))
        return;  // a dark table: planeCdf_ stays empty and sample() gives nothing
    planeCdf_.resize(P + 1);
    fillCdf(std::span<const double>(sliceWeight), planeCdf_);
    inPlaneCdf_.resize(P * (Q + 1));
    for (size_t p = 0; p < P; ++p)
        fillCdf(std::span<const double>(weight).subspan(p * Q, Q),
                std::span(inPlaneCdf_).subspan(p * (Q + 1), Q + 1));
    for (size_t c = 0; c < P * Q; ++c)
        density_[c] = float(weight[c] / total / solidAngle[c]);
}

std::optional<CandelaDistribution::Sample> CandelaDistribution::sample(Vec2 u) const {
    if (planeCdf_.empty())
        return std::nullopt;
    const size_t Q = inPlaneEdges_.size() - 1;
    const CdfEntry slice = invertCdf(std::span<const double>(planeCdf_), u.x);
    const CdfEntry cell =
        invertCdf(std::span<const double>(inPlaneCdf_).subspan(slice.index * (Q + 1), Q + 1), u.y);
    const float density = density_[slice.index * Q + cell.index];
    if (!(density > 0.0f))
        return std::nullopt;
    // Uniform in solid angle within the cell: the plane angle and the area coordinate linear
    // in the two remainders.
    const size_t p = slice.index, q = cell.index;
    const double plane = planeEdges_[p] + (planeEdges_[p + 1] - planeEdges_[p]) * slice.remainder;
    const double a0 = areaCoordinate(system_, inPlaneEdges_[q]);
    const double a1 = areaCoordinate(system_, inPlaneEdges_[q + 1]);
    const double inPlane = inPlaneDegrees(system_, a0 + (a1 - a0) * cell.remainder);
    return Sample{direction(system_, plane, inPlane), density};
}

float CandelaDistribution::pdf(const Vec3& w) const {
    const auto [planeAngle, inPlaneAngle] = angles(system_, w);
    const std::optional<size_t> p = intervalOf(planeEdges_, planeAngle);
    const std::optional<size_t> q = intervalOf(inPlaneEdges_, inPlaneAngle);
    if (!p || !q)
        return 0.0f;
    return density_[*p * (inPlaneEdges_.size() - 1) + *q];
}

GoniometricLight::GoniometricLight(std::shared_ptr<const CandelaTable> table, const Vec3& position,
                                   const Mat3& luminaireToWorld, const Color& colour,
                                   float multiplier, std::string name)
    : table_(std::move(table)),
      position_(position),
      luminaireToWorld_(luminaireToWorld),
      worldToLuminaire_(glm::transpose(luminaireToWorld)),
      scale_(colour * multiplier),
      name_(std::move(name)),
      distribution_(checkedTable(table_)),
      power_(scale_ * float(table_->flux())) {
    if (!isFinite(colour) || glm::min(colour.r, glm::min(colour.g, colour.b)) < 0.0f ||
        !std::isfinite(multiplier) || multiplier < 0.0f)
        throw std::invalid_argument("GoniometricLight: colour and multiplier must be finite, >= 0");
    // A rotation keeps lengths and handedness: R^T R = I, det R = 1. The bound is loose against
    // float rounding of a unit quaternion's matrix (1e-7) and tight against a node's scale.
    const Mat3 gram = worldToLuminaire_ * luminaireToWorld_;
    float offIdentity = 0.0f;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            offIdentity = std::max(offIdentity, std::abs(gram[i][j] - (i == j ? 1.0f : 0.0f)));
    if (!(offIdentity < 1e-4f) || !(glm::determinant(luminaireToWorld_) > 0.0f))
        throw std::invalid_argument("GoniometricLight: luminaireToWorld must be a rotation");
}

Color GoniometricLight::intensity(const Vec3& w) const {
    return scale_ * float(table_->intensity(worldToLuminaire_ * w));
}

float GoniometricLight::pdfDirection(const Vec3& w) const {
    return distribution_.pdf(worldToLuminaire_ * w);
}

// A point source: E = I cos / d² at the receiver, whose cosine the caller applies.
std::optional<LightLiSample> GoniometricLight::sampleLi(const LightSampleContext& ctx, Vec2) const {
    const Vec3 toLight = position_ - ctx.p;
    const float d2 = glm::dot(toLight, toLight);
    if (!(d2 > 0.0f))
        return std::nullopt;
    const Vec3 wi = toLight / std::sqrt(d2);
    const Color L = intensity(-wi) / d2;
    if (maxComponent(L) <= 0.0f)
        return std::nullopt;
    return LightLiSample{L, wi, 1.0f, position_, Vec3(0.0f), Vec3(0.0f)};
}

// pbrt-v4's GoniometricLight::SampleLe: a delta position, the direction importance-sampled from
// the intensity. L is looked up from the world direction, as emittedLe() does.
std::optional<LightLeSample> GoniometricLight::sampleLe(Vec2, Vec2 uDirection) const {
    const std::optional<CandelaDistribution::Sample> d = distribution_.sample(uDirection);
    if (!d)
        return std::nullopt;
    LightLeSample s;
    s.p = position_;
    s.w = luminaireToWorld_ * d->w;
    s.L = intensity(s.w);
    s.pdfPos = 1.0f;
    s.pdfDir = d->pdf;
    if (maxComponent(s.L) <= 0.0f)
        return std::nullopt;
    return s;
}

std::string GoniometricLight::describe() const {
    std::ostringstream out;
    out << "goniometric '" << name_ << "' " << luminance(power_) << " lm at (" << position_.x
        << ", " << position_.y << ", " << position_.z << ")";
    return out.str();
}

}  // namespace penumbra
