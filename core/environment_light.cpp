#include "core/environment_light.h"

#include <algorithm>
#include <array>
#include <span>
#include <sstream>
#include <stdexcept>

namespace penumbra {
namespace {

// The channels read as R, G and B: by name, else the first three, else the first as grey.
std::array<int, 3> radianceChannels(const Image& image) {
    const int r = image.channelIndex("R"), g = image.channelIndex("G"), b = image.channelIndex("B");
    if (r >= 0 && g >= 0 && b >= 0)
        return {r, g, b};
    if (image.channels() >= 3)
        return {0, 1, 2};
    return {0, 0, 0};
}

// The equirectangular mapping of the header (Mitsuba 0.5's envmap): a direction of the map's frame
// to image coordinates in [0, 1]², and back.
Vec2 directionToUv(const Vec3& local) {
    const float turn = 0.5f * std::atan2(local.x, -local.z) * kInvPi;  // in [-1/2, 1/2]
    const float u = turn < 0.0f ? turn + 1.0f : turn;
    const float v = std::acos(glm::clamp(local.y, -1.0f, 1.0f)) * kInvPi;
    return Vec2(std::min(u, 1.0f), v);
}

Vec3 uvToDirection(Vec2 uv) {
    const float phi = 2.0f * kPi * uv.x, theta = uv.y * kPi;
    const float sinTheta = std::sin(theta);
    return Vec3(sinTheta * std::sin(phi), std::cos(theta), -sinTheta * std::cos(phi));
}

// A piecewise-constant function f of n equal segments of [0, 1] as its density pdf = f / integral
// and its cdf (n + 1 entries) (pbrt-v3's Distribution1D, section 13.3.1). Where f is zero
// throughout, the cdf is uniform and the pdf zero, so a sample drawn from it gets density zero
// and is discarded. Returns the integral of f.
double tabulate(std::span<const float> f, std::span<float> pdf, std::span<float> cdf) {
    const size_t n = f.size();
    const double sum = fillCdf(f, cdf);
    for (size_t i = 0; i < n; ++i)
        pdf[i] = sum > 0.0 ? float(f[i] * double(n) / sum) : 0.0f;
    return sum / double(n);
}

// Distribution1D::SampleContinuous: u's place in [0, 1], linear within its segment.
float sampleContinuous(std::span<const float> cdf, float u, int& index) {
    const CdfEntry entry = invertCdf(cdf, u);
    index = int(entry.index);
    return float((double(entry.index) + entry.remainder) / double(cdf.size() - 1));
}

}  // namespace

EnvironmentLight::EnvironmentLight(const Image& radiance, const Mat3& worldToLocal, float scale,
                                   const Vec3& sceneCenter, float sceneRadius, std::string name,
                                   const std::optional<SunDisc>& sun, std::vector<Portal> portals)
    : width_(radiance.width()),
      height_(radiance.height()),
      worldToLocal_(worldToLocal),
      scale_(scale),
      sceneCenter_(sceneCenter),
      sceneRadius_(sceneRadius),
      name_(std::move(name)) {
    if (width_ <= 0 || height_ <= 0)
        throw std::invalid_argument("EnvironmentLight: empty image");
    if (!(sceneRadius > 0.0f) || !std::isfinite(sceneRadius))
        throw std::invalid_argument("EnvironmentLight: the scene radius must be positive");
    if (!(scale >= 0.0f) || !std::isfinite(scale))
        throw std::invalid_argument("EnvironmentLight: the scale must be finite and >= 0");

    const std::array<int, 3> channel = radianceChannels(radiance);
    pixels_.resize(size_t(width_) * size_t(height_));
    for (int y = 0; y < height_; ++y)
        for (int x = 0; x < width_; ++x)
            pixels_[size_t(y) * width_ + x] =
                scale * Color(radiance.at(x, y, channel[0]), radiance.at(x, y, channel[1]),
                              radiance.at(x, y, channel[2]));

    // The sampling weight of each pixel's cell (pbrt-v3's InfiniteAreaLight, section 14.2.4):
    // luminance times sin(theta), the Jacobian of the map, at the cell's centre row. The
    // luminance is that of the brightest of the 3 x 3 pixels around it, whose centres the
    // bilinear radiance over the cell interpolates, so that every direction where radiance() can
    // be positive has a positive density.
    std::vector<float> weight(pixels_.size());
    for (int y = 0; y < height_; ++y) {
        const float sinTheta = std::sin(kPi * (float(y) + 0.5f) / float(height_));
        for (int x = 0; x < width_; ++x) {
            Color brightest(0.0f);
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int row = std::clamp(y + dy, 0, height_ - 1);
                    const int column = (x + dx + width_) % width_;
                    brightest = glm::max(brightest, pixels_[size_t(row) * width_ + column]);
                }
            weight[size_t(y) * width_ + x] = luminance(brightest) * sinTheta;
        }
    }

    // The conditional density of u in each row, then the marginal density of v over rows
    // (pbrt-v3's Distribution2D, section 13.6.7).
    columnPdf_.resize(pixels_.size());
    columnCdf_.resize(size_t(height_) * (width_ + 1));
    std::vector<float> rowIntegral(height_);
    for (int y = 0; y < height_; ++y) {
        const size_t row = size_t(y) * width_;
        rowIntegral[y] = float(tabulate(
            std::span(weight).subspan(row, width_), std::span(columnPdf_).subspan(row, width_),
            std::span(columnCdf_).subspan(y * size_t(width_ + 1), width_ + 1)));
    }
    rowPdf_.resize(height_);
    rowCdf_.resize(height_ + 1);
    tabulate(rowIntegral, rowPdf_, rowCdf_);

    // The integral of the radiance over the sphere, for power(): each pixel's value, constant
    // over its cell, times the cell's solid angle (2 pi / W)(cos theta_top - cos theta_bottom).
    // It differs from the integral of the bilinear radiance by O(1 / H²) where the map is smooth.
    glm::dvec3 integral(0.0);
    for (int y = 0; y < height_; ++y) {
        const double solidAngle =
            2.0 * double(kPi) / width_ *
            (std::cos(double(kPi) * y / height_) - std::cos(double(kPi) * (y + 1) / height_));
        glm::dvec3 rowSum(0.0);
        for (int x = 0; x < width_; ++x)
            rowSum += glm::dvec3(pixels_[size_t(y) * width_ + x]);
        integral += rowSum * solidAngle;
    }
    integral_ = Color(integral);

    if (sun && sun->directNormalIlluminance > 0.0f) {
        if (!(sun->angularRadius > 0.0f) || !std::isfinite(sun->directNormalIlluminance))
            throw std::invalid_argument("EnvironmentLight: a sun needs a disc and a finite E_n");
        sun_ = sun;
        sun_->direction = glm::normalize(sun->direction);
        // The shares of the luminous power: the sun's E_n against the map's integral.
        const float map = luminance(integral_);
        sunProbability_ = sun->directNormalIlluminance / (sun->directNormalIlluminance + map);
    }
    if (!portals.empty()) {
        // Points of the portals' images closer than a bright pixel is wide (its bilinear
        // radiance spans two pixels, 2 pi / height), so that none is missed between them: a
        // cell spans at most 2 / kResolution radians (at the image's centre).
        const int supersampling = std::clamp(
            int(std::ceil(float(height_) / (kPi * float(PortalSet::kResolution)))), 1, 8);
        portals_ = PortalSet(
            std::move(portals), [this](const Vec3& d) { return luminance(mapRadiance(d)); },
            PortalSet::kResolution, supersampling);
    }
}

bool EnvironmentLight::inSun(const Vec3& towards) const {
    return sun_ && sun_->contains(towards);
}

Color EnvironmentLight::radiance(const Vec3& towards) const {
    return mapRadiance(towards) + sunRadiance(towards);
}

Color EnvironmentLight::sunRadiance(const Vec3& towards) const {
    return inSun(towards) ? Color(sun_->radiance()) : Color(0.0f);
}

Color EnvironmentLight::radiance(const Vec3& towards, EnvironmentPart part) const {
    return part == EnvironmentPart::Sun ? sunRadiance(towards) : mapRadiance(towards);
}

Color EnvironmentLight::mapRadiance(const Vec3& towards) const {
    const Vec2 uv = directionToUv(worldToLocal_ * towards);
    // Bilinear between pixel centres, pixel (x, y) centred at ((x + 0.5) / W, (y + 0.5) / H).
    const float x = uv.x * float(width_) - 0.5f, y = uv.y * float(height_) - 0.5f;
    const float x0 = std::floor(x), y0 = std::floor(y);
    const float fx = x - x0, fy = y - y0;
    const auto pixel = [&](int column, int row) {
        column = ((column % width_) + width_) % width_;  // wraps around in u
        row = std::clamp(row, 0, height_ - 1);           // clamped at the poles
        return pixels_[size_t(row) * width_ + column];
    };
    const int ix = int(x0), iy = int(y0);
    return (1.0f - fy) * ((1.0f - fx) * pixel(ix, iy) + fx * pixel(ix + 1, iy)) +
           fy * ((1.0f - fx) * pixel(ix, iy + 1) + fx * pixel(ix + 1, iy + 1));
}

// pbrt-v3's InfiniteAreaLight::Pdf_Li (section 14.2.4): the density p(u, v) of the image
// coordinates over the Jacobian of the map, d omega = 2 pi² sin(theta) du dv.
double EnvironmentLight::horizontalIlluminance() const {
    constexpr int kRings = 512, kSectors = 2048;
    const double dTheta = 0.5 * double(kPi) / kRings, dPhi = 2.0 * double(kPi) / kSectors;
    double sum = 0.0;
    for (int i = 0; i < kRings; ++i) {
        const double theta = (i + 0.5) * dTheta;
        const double weight = std::cos(theta) * std::sin(theta) * dTheta * dPhi;
        for (int j = 0; j < kSectors; ++j) {
            const double phi = (j + 0.5) * dPhi;
            const Vec3 up(float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
                          float(std::sin(theta) * std::sin(phi)));
            sum += double(luminance(mapRadiance(up))) * weight;
        }
    }
    return sum;
}

float EnvironmentLight::pdfDirection(const Vec3& from, const Vec3& towards) const {
    return pdfDirection(from, towards, portals_.empty() ? 0.0 : portals_.luminanceShown(from),
                        sunProbability_);
}

float EnvironmentLight::pdfDirection(const Vec3& from, const Vec3& towards,
                                     EnvironmentPart part) const {
    if (part == EnvironmentPart::Sun)
        return inSun(towards) ? 1.0f / sun_->solidAngle() : 0.0f;
    return pdfDirection(from, towards, portals_.empty() ? 0.0 : portals_.luminanceShown(from),
                        0.0f);
}

float EnvironmentLight::pdfDirection(const Vec3& from, const Vec3& towards, double shown,
                                     float sunShare) const {
    const float sun = inSun(towards) ? sunShare / sun_->solidAngle() : 0.0f;
    const float rest = 1.0f - sunShare;
    if (!(shown > 0.0))
        return rest * mapPdf(towards) + sun;
    return rest * ((1.0f - kPortalShare) * mapPdf(towards) +
                   kPortalShare * portals_.pdf(from, towards, shown)) +
           sun;
}

float EnvironmentLight::mapPdf(const Vec3& towards) const {
    const Vec3 local = worldToLocal_ * towards;
    const float sinTheta = safeSqrt(1.0f - sqr(glm::clamp(local.y, -1.0f, 1.0f)));
    if (!(sinTheta > 0.0f))
        return 0.0f;
    const Vec2 uv = directionToUv(local);
    const int x = std::min(int(uv.x * float(width_)), width_ - 1);
    const int y = std::min(int(uv.y * float(height_)), height_ - 1);
    const float p = rowPdf_[y] * columnPdf_[size_t(y) * width_ + x];
    return p / (2.0f * kPi * kPi * sinTheta);
}

std::optional<LightLiSample> EnvironmentLight::sampleLi(const LightSampleContext& ctx,
                                                        Vec2 u) const {
    return sampleMixture(ctx, u, sunProbability_, [this](const Vec3& wi) { return radiance(wi); });
}

std::optional<LightLiSample> EnvironmentLight::sampleLi(const LightSampleContext& ctx, Vec2 u,
                                                        EnvironmentPart part) const {
    if (part == EnvironmentPart::Sun && !sun_)
        return std::nullopt;
    return sampleMixture(ctx, u, part == EnvironmentPart::Sun ? 1.0f : 0.0f,
                         [this, part](const Vec3& wi) { return radiance(wi, part); });
}

template <typename Radiance>
std::optional<LightLiSample> EnvironmentLight::sampleMixture(const LightSampleContext& ctx, Vec2 u,
                                                             float sunShare,
                                                             const Radiance& radiance) const {
    // The sun, the portals (where they show the point some light) and the map with their
    // probabilities, u.x rescaled to [0, 1) for the part chosen.
    Vec3 wi;
    const double shown = portals_.empty() ? 0.0 : portals_.luminanceShown(ctx.p);
    if (u.x < sunShare) {
        wi = sun_->sample(Vec2(u.x / sunShare, u.y));
    } else {
        const float uRest = std::min((u.x - sunShare) / (1.0f - sunShare), 1.0f);
        if (!(shown > 0.0)) {
            wi = sampleMap(Vec2(uRest, u.y));
        } else if (uRest < kPortalShare) {
            const std::optional<Vec3> through =
                portals_.sample(ctx.p, Vec2(uRest / kPortalShare, u.y), shown);
            if (!through)
                return std::nullopt;
            wi = *through;
        } else {
            const float uMap = (uRest - kPortalShare) / (1.0f - kPortalShare);
            wi = sampleMap(Vec2(std::min(uMap, 1.0f), u.y));
        }
    }

    // The density is looked up again from wi, so that it is exactly what MIS gets from
    // pdfDirection() for the same direction.
    const float pdf = pdfDirection(ctx.p, wi, shown, sunShare);
    const Color L = radiance(wi);
    if (!(pdf > 0.0f) || maxComponent(L) <= 0.0f)
        return std::nullopt;
    // A target beyond the scene's bounding sphere, whatever the receiver's position.
    const float reach = glm::length(ctx.p - sceneCenter_) + 2.0f * sceneRadius_;
    return LightLiSample{L, wi, pdf, ctx.p + wi * reach, Vec3(0.0f), Vec3(0.0f)};
}

Vec3 EnvironmentLight::sampleMap(Vec2 u) const {
    // A row from the marginal, then u within the row from its conditional (section 13.6.7).
    int row = 0, column = 0;
    const float v = sampleContinuous(rowCdf_, u.y, row);
    const float uColumn = sampleContinuous(
        std::span(columnCdf_).subspan(size_t(row) * (width_ + 1), width_ + 1), u.x, column);
    return glm::transpose(worldToLocal_) * uvToDirection(Vec2(uColumn, v));
}

// pbrt-v4's ImageInfiniteLight::SampleLe: the direction from the distribution (as seen from the
// scene's centre, for the portals), the origin uniform on the disc of the bounding radius facing
// it, one radius behind the scene's centre.
std::optional<LightLeSample> EnvironmentLight::sampleLe(Vec2 uPosition, Vec2 uDirection) const {
    const std::optional<LightLiSample> li = sampleLi(LightSampleContext{sceneCenter_}, uDirection);
    if (!li)
        return std::nullopt;
    LightLeSample s;
    s.w = -li->wi;
    const Frame frame = Frame::fromNormal(s.w);
    const Vec2 d = sampleConcentricDisk(uPosition) * sceneRadius_;
    s.p = sceneCenter_ - s.w * sceneRadius_ + frame.s * d.x + frame.t * d.y;
    s.L = li->L;
    s.pdfPos = 1.0f / (kPi * sqr(sceneRadius_));
    s.pdfDir = li->pdf;
    return s;
}

Color EnvironmentLight::emittedLe(const LightLeSample&, const Vec3& w) const {
    return radiance(-w);
}

// pbrt-v4's ImageInfiniteLight::Phi: the flux through the disc of the bounding radius.
Color EnvironmentLight::power() const {
    const Color sun(sun_ ? sun_->directNormalIlluminance : 0.0f);
    return kPi * sqr(sceneRadius_) * (integral_ + sun);
}

std::string EnvironmentLight::describe() const {
    std::ostringstream out;
    out << "environment '" << name_ << "' " << width_ << " x " << height_ << ", scale " << scale_;
    if (sun_) {
        const Vec3& d = sun_->direction;
        out << ", sun " << sun_->directNormalIlluminance << " lux towards (" << d.x << ", " << d.y
            << ", " << d.z << ")";
    }
    return out.str();
}

std::string findBadEnvironmentPixel(const Image& radiance) {
    for (int y = 0; y < radiance.height(); ++y)
        for (int x = 0; x < radiance.width(); ++x)
            for (int c = 0; c < radiance.channels(); ++c) {
                const float value = radiance.at(x, y, c);
                if (std::isfinite(value) && value >= 0.0f)
                    continue;
                std::ostringstream out;
                out << "pixel (" << x << ", " << y << ") channel " << radiance.channelNames()[c]
                    << ": " << value;
                return out.str();
            }
    return "";
}

// Right-handed R_y(theta) = [[cos, 0, sin], [0, 1, 0], [-sin, 0, cos]] maps the map's frame to the
// world; worldToLocal is its transpose, written here by columns as GLM stores it.
Mat3 environmentRotation(float degrees) {
    const float theta = glm::radians(degrees);
    const float c = std::cos(theta), s = std::sin(theta);
    return Mat3(Vec3(c, 0.0f, s), Vec3(0.0f, 1.0f, 0.0f), Vec3(-s, 0.0f, c));
}

}  // namespace penumbra
