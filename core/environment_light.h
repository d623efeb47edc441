// An environment (infinite) light: radiance arriving from every direction, read from an
// equirectangular (latitude-longitude) image, as a sky photographed with a fisheye or an HDR
// panorama. Sampled in proportion to the image's luminance times sin(theta), the piecewise-constant
// 2D distribution of pbrt-v3's InfiniteAreaLight (Pharr, Jakob and Humphreys, "Physically Based
// Rendering", 3rd ed., section 14.2.4), so that next-event estimation finds the sun and the
// bright part of a sky; the tracers weigh it against BSDF sampling by multiple importance
// sampling (pdfDirection()).
//
// The map's frame. A direction d in world space (+Y up, glTF) is first taken into the map's own
// frame, d' = worldToLocal * d; its pixel is then
//     u = atan2(d'.x, -d'.z) / (2 pi)  (plus 1 where negative),   v = acos(d'.y) / pi,
// u across the image from its left edge, v down from its top row: the top row is the zenith, the
// middle row the horizon, the left edge looks along -Z, u grows turning from -Z to +X (a quarter
// across), the centre column looks along +Z. This is the mapping of Mitsuba 0.5's envmap
// (src/emitters/envmap.cpp, evalDirection and internalSampleDirection), so that a Mitsuba
// scene's `toWorld` is the inverse of worldToLocal. Units: the pixels, times `scale`, are radiance
// in cd/m² per linear-sRGB channel.
#pragma once

#include "core/image.h"
#include "core/light.h"
#include "core/math.h"
#include "core/portals.h"
#include "core/sampling.h"
#include "core/sun_disc.h"

#include <optional>
#include <string>
#include <vector>

namespace penumbra {

// The environment's two parts, which a render that files its light by group samples and weighs
// apart (core/light_groups.h): the map, with its ground, and the sun's disc.
enum class EnvironmentPart { Map, Sun };

class EnvironmentLight : public Light {
  public:
    // `radiance`: width x height pixels with at least one channel: R, G, B by the names "R", "G",
    // "B" when it has them, else the first three channels, else the first channel as grey. Every
    // value must be finite and >= 0 (validated by the caller, who knows the file's name: see
    // findBadEnvironmentPixel()). worldToLocal must be a rotation. The scene's bounding sphere
    // places shadow-ray targets beyond the scene and the photons' starting disc, and gives
    // power(). `name` is what describe() prints (the file).
    //
    // `sun`, when given, adds the sun's disc (core/sun_disc.h) to the map: radiance() sees it,
    // and sampling draws it with the probability of its share of the light's luminous power,
    // a uniform direction in its cone (a one-sample mixture of the two densities, which
    // pdfDirection() returns, so MIS weighs both parts).
    //
    // `portals`, when not empty, take kPortalShare of the samples the sun leaves at the points
    // they show some of the map (core/portals.h, built from the map without the sun): the
    // density then depends on the receiving point, which pdfDirection() takes.
    EnvironmentLight(const Image& radiance, const Mat3& worldToLocal, float scale,
                     const Vec3& sceneCenter, float sceneRadius, std::string name,
                     const std::optional<SunDisc>& sun = std::nullopt,
                     std::vector<Portal> portals = {});

    // The share of the non-sun samples that go through the portals, when there are any; the rest
    // follow the map, so that points the portals do not serve (outside, or by an opening without
    // a portal) still find the sky.
    static constexpr float kPortalShare = 0.75f;

    LightKind kind() const override { return LightKind::Environment; }
    bool isDelta() const override { return false; }

    // Radiance (cd/m²) arriving at any point from unit world direction `towards` (the direction
    // a ray that escapes the scene travels): the image bilinearly interpolated between pixel
    // centres, wrapping around in u and clamped in v, times the scale, plus the sun's radiance
    // inside its disc.
    Color radiance(const Vec3& towards) const;
    // The part's share of radiance(towards): the map's, or the sun's disc's (zero outside it and
    // without a sun).
    Color radiance(const Vec3& towards, EnvironmentPart part) const;
    // The horizontal illuminance (lux, the Rec. 709 luminance of the irradiance) that the map,
    // without the sun, gives an upward plane with nothing around it: the integral of
    // radiance() cos(theta) over the upper hemisphere in world axes, by the midpoint rule on
    // 512 x 2048 cells (the bilinear radiance is smooth between pixel centres, so the rule's
    // error is far below a percent for maps of 4096 pixels across or fewer).
    double horizontalIlluminance() const;
    // Solid-angle density (1/sr) with which sampleLi() from point `from` draws unit world
    // direction `towards`.
    float pdfDirection(const Vec3& from, const Vec3& towards) const;
    // The density of sampleLi(.., part).
    float pdfDirection(const Vec3& from, const Vec3& towards, EnvironmentPart part) const;

    // A direction drawn from the distribution; pLight a point beyond the scene's bounding sphere
    // along it (as DirectionalLight's), nLight zero; L = radiance(wi).
    std::optional<LightLiSample> sampleLi(const LightSampleContext& ctx, Vec2 u) const override;
    // The same for one part alone: a direction drawn from the map's distribution (through the
    // portals as above) or uniformly in the sun's cone, its density pdfDirection(.., part), and L
    // the part's radiance. Nothing for the sun's part without a sun.
    std::optional<LightLiSample> sampleLi(const LightSampleContext& ctx, Vec2 u,
                                          EnvironmentPart part) const;
    // Zero: no surface is the environment. Rays that escape ask pdfDirection().
    float pdfLi(const LightSampleContext&, const Vec3&, const SurfaceHit&) const override {
        return 0.0f;
    }
    // A photon: its direction w = -wi with wi drawn from the distribution (uDirection), its
    // origin uniform on the disc of the scene's bounding radius perpendicular to w, one radius
    // behind the sphere's centre (pbrt-v4's ImageInfiniteLight::SampleLe). pdfPos = 1 / (pi R²),
    // pdfDir = pdfDirection(centre, -w), L = radiance(-w), n zero: flux() is L / (pdfPos pdfDir).
    std::optional<LightLeSample> sampleLe(Vec2 uPosition, Vec2 uDirection) const override;
    // radiance(-w).
    Color emittedLe(const LightLeSample& origin, const Vec3& w) const override;
    // The flux (lm) through the disc of the bounding radius: pi R² times the integral of the
    // radiance over the sphere of directions (pbrt-v4's ImageInfiniteLight::Phi), the sun's
    // E_n included.
    Color power() const override;
    std::string describe() const override;

  private:
    int width_ = 0, height_ = 0;
    std::vector<Color> pixels_;  // scaled radiance, row-major, top row first
    Mat3 worldToLocal_{1.0f};
    float scale_ = 1.0f;  // already applied to pixels_; kept for describe()
    Vec3 sceneCenter_{0.0f};
    float sceneRadius_ = 0.0f;
    std::string name_;
    // The sampling distribution over pixels: the marginal over rows and one conditional per row.
    std::vector<float> rowCdf_;     // height_ + 1 entries
    std::vector<float> rowPdf_;     // height_ entries, density over v in [0, 1]
    std::vector<float> columnCdf_;  // height_ x (width_ + 1)
    std::vector<float> columnPdf_;  // height_ x width_, density over u in [0, 1] given the row
    Color integral_{0.0f};          // integral of the map's radiance over the sphere, cd/m² sr
    // The sun's disc and the probability with which sampling draws it.
    std::optional<SunDisc> sun_;
    float sunProbability_ = 0.0f;
    PortalSet portals_;

    // The map's own radiance, density and sample, before the mixture with the sun.
    Color mapRadiance(const Vec3& towards) const;
    float mapPdf(const Vec3& towards) const;
    Vec3 sampleMap(Vec2 u) const;
    // pdfDirection() with the portals' luminanceShown(from) already known, for a mixture that
    // draws the sun with probability sunShare (sunProbability_ for the whole, 0 for the map's
    // part, 1 for the sun's).
    float pdfDirection(const Vec3& from, const Vec3& towards, double shown, float sunShare) const;
    // sampleLi() from that mixture, L from `radiance`.
    template <typename Radiance>
    std::optional<LightLiSample> sampleMixture(const LightSampleContext& ctx, Vec2 u,
                                               float sunShare, const Radiance& radiance) const;
    Color sunRadiance(const Vec3& towards) const;
    bool inSun(const Vec3& towards) const;
};

// The first pixel of an environment image that is not a finite value >= 0, as "pixel (x, y)
// channel C: VALUE", or empty when every value is good: the loader names it with the file.
std::string findBadEnvironmentPixel(const Image& radiance);

// The rotation about +Y (counter-clockwise seen from above, right-handed) by `degrees`, as a
// world-to-local matrix: turning the environment by `degrees` about the up axis.
Mat3 environmentRotation(float degrees);

}  // namespace penumbra
