// A goniometric point light: a point source whose luminous intensity varies with direction as a
// measured distribution says (an IES LM-63 or EULUMDAT file read into a CandelaTable,
// core/photometry.h), placed and turned by the glTF node that carries it (EXT_lights_ies). After
// pbrt-v4's GoniometricLight, which samples photons from a piecewise-constant distribution of its
// intensity; here that distribution lies on the file's own angle grid, not on an image of it.
//
// The luminaire's frame is the table's: the nadir (gamma 0) along -Z, C0 along +X, C90 along +Y.
// EXT_lights_ies aims a light along its node's -Z with C0 along the node's +X and C90 along its
// +Y, so the node's world rotation is luminaireToWorld.
#pragma once

#include "core/light.h"
#include "core/math.h"
#include "core/photometry.h"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace penumbra {

// Directions of the luminaire frame drawn with a density proportional to a table's intensity,
// piecewise constant in solid angle over cells of the table's own grid. Each interval between
// two of the table's angles is cut into equal pieces of at most kMaxCellDegrees; a cell's
// probability is its solid angle times the mean of the intensity at its four corners. The lookup
// is bilinear in the two angles (CandelaTable), so it is positive inside a cell exactly when one
// of the corners is: every direction with a positive intensity has a positive density, and none
// is drawn where the intensity is zero throughout a cell.
class CandelaDistribution {
  public:
    // On the thirteen files of scenes/ies/ the photons' flux spreads by 3-11 % (standard
    // deviation over mean) at 2.5 degrees, by 4-20 % on the tables' own grids and by 1-4 % at 1
    // degree, which takes six times the memory: a full table at 2.5 degrees has 144 x 72 cells,
    // 125 kB.
    static constexpr double kMaxCellDegrees = 2.5;

    explicit CandelaDistribution(const CandelaTable& table);

    struct Sample {
        Vec3 w;     // unit direction, luminaire frame
        float pdf;  // solid-angle density (1/sr) of w
    };
    // A direction from two uniform numbers in [0, 1), or nothing when the table is zero
    // everywhere. Within its cell the direction is uniform in solid angle: the plane angle and
    // the "area coordinate" (below) are uniform there.
    std::optional<Sample> sample(Vec2 u) const;
    // Solid-angle density (1/sr) of unit direction w of the luminaire frame; zero outside the
    // table's angles.
    float pdf(const Vec3& w) const;

  private:
    PhotometricSystem system_;
    // The cells' edges (degrees): across planes (C or V) and within them (gamma or H).
    std::vector<double> planeEdges_, inPlaneEdges_;
    // The marginal cdf over plane slices (planeEdges_.size() entries) and, per slice, the
    // conditional cdf over its cells (inPlaneEdges_.size() entries each).
    std::vector<double> planeCdf_, inPlaneCdf_;
    std::vector<float> density_;  // 1/sr, per cell, slice by slice
};

class GoniometricLight : public Light {
  public:
    // Intensity towards world direction w: colour × multiplier × table->intensity(w in the
    // luminaire frame), cd per linear-sRGB channel. `colour` (linear RGB) and `multiplier`
    // (dimensionless; EXT_lights_ies's defaults are white and 1) must be finite and >= 0;
    // luminaireToWorld must be a rotation (the node's scale removed). Throws
    // std::invalid_argument otherwise. Lights of one file share its table.
    GoniometricLight(std::shared_ptr<const CandelaTable> table, const Vec3& position,
                     const Mat3& luminaireToWorld, const Color& colour, float multiplier,
                     std::string name);

    LightKind kind() const override { return LightKind::Goniometric; }
    bool isDelta() const override { return true; }

    // Intensity (cd per channel) emitted in unit world direction w away from the light.
    Color intensity(const Vec3& w) const;
    // Solid-angle density (1/sr) with which sampleLe() draws unit world direction w.
    float pdfDirection(const Vec3& w) const;

    // L = intensity(-wi) / d² (no cosine at the receiver), pdf 1, pLight the light's position.
    std::optional<LightLiSample> sampleLi(const LightSampleContext& ctx, Vec2 u) const override;
    float pdfLi(const LightSampleContext&, const Vec3&, const SurfaceHit&) const override {
        return 0.0f;
    }
    // From the light's position (pdfPos 1), w drawn by the CandelaDistribution (pdfDir in 1/sr),
    // L = intensity(w): flux() = L / pdfDir, whose mean is power().
    std::optional<LightLeSample> sampleLe(Vec2 uPosition, Vec2 uDirection) const override;
    Color emittedLe(const LightLeSample&, const Vec3& w) const override { return intensity(w); }
    // colour × multiplier × the table's flux (lm per channel).
    Color power() const override { return power_; }
    std::string describe() const override;

  private:
    std::shared_ptr<const CandelaTable> table_;
    Vec3 position_;
    Mat3 luminaireToWorld_, worldToLuminaire_;
    Color scale_;  // colour × multiplier
    std::string name_;
    CandelaDistribution distribution_;
    Color power_;
};

}  // namespace penumbra
