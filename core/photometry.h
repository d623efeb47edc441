// Measured luminous intensity distributions of luminaires (goniophotometry), as the IES LM-63 and
// EULUMDAT readers (core/photometric_files.h) make them, for a goniometric point light.
//
// The luminaire frame. The light aims along -Z: the nadir (vertical angle 0) is -Z, the zenith
// (180) +Z, the C0 plane holds +X and the C90 plane +Y, so C grows counter-clockwise seen from
// +Z (from behind the luminaire, looking along its nadir). This is LM-63-2002's type C system
// (its key definitions: horizontal angles turn counter-clockwise; C0-C180 is the luminaire's
// length, which the file's luminous opening gives along X, its width along Y) and the frame
// EXT_lights_ies gives a light node.
//
// Two photometric systems (LM-63-2002's "photometric plane"; the C-gamma and B-beta systems of
// CIE 121-1996) share that frame:
//  - type C: the planes (C, 0-360) turn about the vertical axis Z; in each, gamma runs from the
//    nadir (0) to the zenith (180). A direction is (sin g cos C, sin g sin C, -cos g).
//  - type B: the planes (LM-63's vertical angle V, -90..90) turn about the horizontal axis Y, the
//    luminaire's width; V = 0 is the plane through the nadir, V = 90 the horizontal plane through
//    +X (LM-63's "photometric horizontal" at H 0, V 90, as in type C). In each plane the
//    horizontal angle H (-90..90) runs from its centre line towards -Y ("clockwise" in LM-63
//    seen from +Z at V = 90). A direction is (cos H sin V, -sin H, -cos H cos V).
// Both put (0, 0) at the nadir, where the renderer aims the light.
#pragma once

#include "core/math.h"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace penumbra {

enum class PhotometricSystem {
    TypeC,  // planes about the vertical axis: (C, gamma)
    TypeB,  // planes about the horizontal axis Y: (V, H)
};

// Intensity I (cd) on a grid of plane angle (C for type C, V for type B) by angle within the
// plane (gamma for type C, H for type B), interpolated bilinearly in the two angles (degrees),
// and zero outside the measured angles. A type C table covers every plane: its plane angles run
// from 0 to 360, the 360 column repeating the 0 one, so that C wraps.
class CandelaTable {
  public:
    // candela[p * inPlaneAngles.size() + q] is I at planeAngles[p], inPlaneAngles[q]. Both angle
    // lists increase, with at least two entries each; values finite and >= 0. Throws
    // std::invalid_argument otherwise: the readers check a file before they build its table.
    CandelaTable(PhotometricSystem system, std::vector<double> planeAngles,
                 std::vector<double> inPlaneAngles, std::vector<double> candela);

    PhotometricSystem system() const { return system_; }
    const std::vector<double>& planeAngles() const { return planeAngles_; }      // degrees
    const std::vector<double>& inPlaneAngles() const { return inPlaneAngles_; }  // degrees
    // I (cd) at the grid node (planeAngles()[p], inPlaneAngles()[q]).
    double candela(size_t p, size_t q) const { return candela_[p * inPlaneAngles_.size() + q]; }

    // I (cd) at a plane angle and an angle within the plane (degrees; a type C table takes any
    // C and wraps it into 0-360).
    double intensity(double planeAngle, double inPlaneAngle) const;
    // I (cd) emitted along direction w of the luminaire frame (above); w need not be unit.
    double intensity(const Vec3& w) const;

    // Luminous flux (lm): the integral of intensity() over the sphere, in closed form cell by
    // cell (below), so that it is the flux of exactly the distribution the lookup returns.
    double flux() const;

  private:
    PhotometricSystem system_;
    std::vector<double> planeAngles_, inPlaneAngles_, candela_;
};

// The symmetry a type C measurement claims, which says what part of the circle of C-planes the
// file stores and how the rest mirror it: LM-63 by the range of the horizontal angles, EULUMDAT
// by its indicator Isym.
enum class PlaneSymmetry {
    None,          // every plane measured (IES 0-360, or 1995's past 180; Isym 0)
    Rotational,    // one plane for all (IES a single angle, Isym 1)
    AboutC0C180,   // I(C) = I(360 - C) (IES 0-180, Isym 2)
    AboutC90C270,  // I(C) = I(180 - C) (IES 90-270, Isym 3 which stores C270-C90)
    Quadrant,      // both of the above (IES 0-90, Isym 4)
};

// The full type C table of a measurement stored for part of the circle: every stored plane at
// storedC[k] (degrees, any order, within 0-360) and its mirror images under the symmetry become
// planes of the table, the plane at 0 repeated at 360. candela[k * gamma.size() + j] is the
// stored I (cd) at storedC[k], gamma[j]. Throws std::invalid_argument if the planes do not
// reach C = 0 (the readers refuse such files first).
CandelaTable unfoldTypeC(PlaneSymmetry symmetry, const std::vector<double>& storedC,
                         std::vector<double> gamma, const std::vector<double>& candela);

// The full type B table of a measurement over V (planes) by H (within them), degrees within
// -90..90, candela[v * H.size() + h]. A range that starts at 0 is mirrored to negative angles:
// LM-63-2002 has a file store H from 0 when the luminaire is laterally symmetric, and requires
// complete explorations (V from -90 or 0 to 90), so V from 0 means I(-V) = I(V), as Blender's
// reader takes it.
CandelaTable unfoldTypeB(std::vector<double> V, std::vector<double> H,
                         const std::vector<double>& candela);

// TILT=INCLUDE of an IES file: how the lamp output changes as the luminaire tilts from its
// measured position. Kept for the light, which knows the luminaire's tilt; the table holds the
// output at the measured position.
struct IesTilt {
    // LM-63's code for how the lamp sits: 1 vertical; 2 and 3 horizontal, the two ways a
    // horizontal lamp can turn as the luminaire tilts.
    int lampToLuminaireGeometry = 1;
    std::vector<double> angles;   // degrees, increasing
    std::vector<double> factors;  // output multipliers at those angles
};

// An IES keyword and its text, [MORE] lines joined to it by a newline.
struct IesKeyword {
    std::string key, value;
};

// What an IES LM-63 file says besides its table, as written. The table (Photometry::candela)
// holds the file's candela values times candelaMultiplier times ballastFactor, times
// ballastLampFactor only for 1986-1995 files where that field is the "ballast-lamp photometric
// factor" (2002 calls it "future use"; 2019 the file generation type, a code, not a factor).
struct IesHeader {
    int lm63Year = 1986;  // 1986 (no format line), 1991, 1995, 2002 or 2019
    std::vector<IesKeyword> keywords;
    std::vector<std::string> labels;  // lines before TILT= that are not keywords (the 1986 text)
    std::optional<IesTilt> tilt;      // TILT=INCLUDE; TILT=NONE leaves it empty
    int lampCount = 1;
    double lumensPerLamp = -1;  // lm, rated; -1 means absolute photometry
    double candelaMultiplier = 1;
    int photometricType = 1;  // 1 C, 2 B
    int unitsType = 2;        // of the luminous opening: 1 feet, 2 metres
    // Luminous opening along Y, X and Z in unitsType; negative values describe round shapes
    // (LM-63-2002's luminous shapes). Kept, not yet used.
    double width = 0, length = 0, height = 0;
    double ballastFactor = 1;
    double ballastLampFactor = 1;  // see above
    double inputWatts = 0;         // W

    bool absolutePhotometry() const { return lumensPerLamp < 0; }
};

// One lamp set of an EULUMDAT file (its lines 26a-26f).
struct LdtLampSet {
    // Number of lamps; negative where the writer marks absolute photometry, and `flux` is then
    // the luminaire's own flux (see LdtHeader).
    int count = 1;
    std::string type;
    double flux = 0;  // lm: the total of the set's lamps, not per lamp
    std::string colour, colourRendering;
    double watts = 0;  // including ballast
};

// What an EULUMDAT file says besides its table, as written. Its intensities are in cd/klm; the
// table (Photometry::candela) holds them times conversionFactor times the lamp flux (the sum of
// the sets' fluxes) / 1000 lm, in cd.
struct LdtHeader {
    std::string identification;
    // Ityp: 0 point source without symmetry, 1 symmetric about the vertical, 2 linear, 3 other.
    int typeIndicator = 1;
    int symmetry = 0;  // Isym 0-4, see PlaneSymmetry
    std::string reportNumber, luminaireName, luminaireNumber, fileName, dateUser;
    // Luminaire and luminous area dimensions (mm); a width of 0 means round. Kept, not yet used.
    double length = 0, width = 0, height = 0;
    double luminousLength = 0, luminousWidth = 0;
    std::array<double, 4> luminousHeights{};  // at C0, C90, C180, C270
    double downwardFluxFraction = 100;        // DFF, %
    double lightOutputRatio = 100;            // LORL, %: luminaire flux / lamp flux
    double conversionFactor = 1;
    double tilt = 0;  // degrees, of the luminaire during measurement
    std::vector<LdtLampSet> lampSets;
    std::array<double, 10> directRatios{};  // for room indices 0.6 ... 5

    double lampFlux() const;  // lm: the sum of the sets' fluxes
    // A set with a negative lamp count: the intensities are still cd/klm of lampFlux(), which is
    // then the luminaire's flux (Aardvark.Data.Photometry's LDTLampData; eulumdat-rs's IES
    // conversion writes such files).
    bool absolutePhotometry() const;
};

// A luminaire's photometry: the intensity table in cd and the header of the file it came from.
struct Photometry {
    std::string source;  // the file name, as given to the reader
    CandelaTable candela;
    std::optional<IesHeader> ies;
    std::optional<LdtHeader> ldt;
};

}  // namespace penumbra
