// EULUMDAT photometric files (proposed by A. Stockmar, Light Consult, Berlin, 1990; the layout
// as paulbourke.net/dataformats/ldt lists it): one field per line,
//   1 identification, 2 Ityp, 3 Isym, 4 Mc (C-planes in 0-360), 5 Dc, 6 Ng (angles per plane),
//   7 Dg, 8-12 report number, luminaire name and number, file name, date/user,
//   13-21 dimensions (mm), 22 DFF (%), 23 LORL (%), 24 conversion factor, 25 tilt, 26 n lamp
//   sets, then per set: number of lamps, type, total flux (lm), colour, colour rendering, watts,
//   then 10 direct ratios, Mc C angles, Ng gamma angles, and the intensities (cd/klm) of the
//   stored planes Mc1..Mc2, each over all gamma angles.
// Numbers may have a decimal comma (parseDecimal).
#include "core/photometric_files.h"
#include "core/photometric_text.h"

#include <algorithm>
#include <utility>

namespace penumbra {

namespace {

// The fields of the file, one a line.
class Fields : public NumberReader {
  public:
    Fields(const std::vector<std::string_view>& lines, const std::string& name)
        : NumberReader(name), lines_(lines) {}

    // A text field, without the blanks at its ends.
    std::string text(const std::string& what) {
        const std::optional<std::string> field = next();
        if (!field)
            throw error("the file ends where the " + what + " should be");
        return *field;
    }
    // The first line after the fields read that is not blank, if any.
    std::optional<int> moreText() const {
        for (size_t n = next_; n < lines_.size(); ++n)
            if (!trimBlanks(lines_[n]).empty())
                return int(n + 1);
        return std::nullopt;
    }

  protected:
    std::optional<std::string> next() override {
        if (next_ == lines_.size())
            return std::nullopt;
        line_ = int(++next_);
        return std::string(trimBlanks(lines_[next_ - 1]));
    }

  private:
    const std::vector<std::string_view>& lines_;
    size_t next_ = 0;  // index of the next line to read
};

PlaneSymmetry planeSymmetry(int isym) {
    constexpr PlaneSymmetry kByIsym[] = {PlaneSymmetry::None, PlaneSymmetry::Rotational,
                                         PlaneSymmetry::AboutC0C180, PlaneSymmetry::AboutC90C270,
                                         PlaneSymmetry::Quadrant};
    return kByIsym[isym];
}

// The C-planes a file stores for its symmetry, as indices into its Mc C angles (Stockmar:
// Mc1..Mc2, 1-based): all; the first; C0-C180; C270-C90 through C0 (Mc1 = 3 Mc/4 + 1, Mc2 =
// Mc1 + Mc/2, wrapping past Mc; Aardvark.Data.Photometry and tinyldt read it so too); C0-C90.
std::vector<size_t> storedPlanes(int isym, size_t mc) {
    size_t first = 0, count = mc;
    if (isym == 1)
        count = 1;
    else if (isym == 2 || isym == 3)
        count = mc / 2 + 1;
    else if (isym == 4)
        count = mc / 4 + 1;
    if (isym == 3)
        first = 3 * mc / 4;
    std::vector<size_t> planes;
    for (size_t k = 0; k < count; ++k)
        planes.push_back((first + k) % mc);
    return planes;
}

}  // namespace

Photometry parseLdt(std::string_view text, const std::string& name) {
    const std::vector<std::string_view> lines = splitLines(text);
    if (lines.empty())
        throw PhotometricFileError(name, 1, "the file is empty");
    Fields fields(lines, name);
    LdtHeader header;
    header.identification = fields.text("identification");
    header.typeIndicator = fields.integer("type indicator Ityp");
    if (header.typeIndicator < 0 || header.typeIndicator > 3)
        throw fields.error("the type indicator Ityp must be 0 to 3, got " +
                           std::to_string(header.typeIndicator));
    header.symmetry = fields.integer("symmetry indicator Isym");
    if (header.symmetry < 0 || header.symmetry > 4)
        throw fields.error(
            "the symmetry indicator Isym must be 0 (none), 1 (about the vertical "
            "axis), 2 (C0-C180 plane), 3 (C90-C270 plane) or 4 (both), got " +
            std::to_string(header.symmetry));
    const int isym = header.symmetry;
    const int mc = fields.integer("number of C-planes Mc");
    if (mc < 1)
        throw fields.error("the number of C-planes Mc must be at least 1");
    // Isym 2 and 3 store half the planes and 4 a quarter, with the mirror planes among them.
    const int divisor = isym == 4 || isym == 3 ? 4 : isym == 2 ? 2 : 1;
    if (mc % divisor != 0)
        throw fields.error("Isym " + std::to_string(isym) + " needs Mc divisible by " +
                           std::to_string(divisor) + ", got " + std::to_string(mc));
    fields.number("C-plane distance Dc");
    const int ng = fields.integer("number of intensities per C-plane Ng");
    if (ng < 2)
        throw fields.error("a table needs at least 2 intensities per C-plane, got " +
                           std::to_string(ng));
    fields.number("intensity angle distance Dg");
    header.reportNumber = fields.text("measurement report number");
    header.luminaireName = fields.text("luminaire name");
    header.luminaireNumber = fields.text("luminaire number");
    header.fileName = fields.text("file name");
    header.dateUser = fields.text("date/user");
    header.length = fields.number("luminaire length");
    header.width = fields.number("luminaire width");
    header.height = fields.number("luminaire height");
    header.luminousLength = fields.number("luminous area length");
    header.luminousWidth = fields.number("luminous area width");
    for (size_t k = 0; k < 4; ++k)
        header.luminousHeights[k] = fields.number("luminous area height");
    header.downwardFluxFraction = fields.number("downward flux fraction DFF");
    header.lightOutputRatio = fields.number("light output ratio LORL");
    if (header.lightOutputRatio < 0)
        throw fields.error("the light output ratio LORL must be >= 0");
    header.conversionFactor = fields.number("conversion factor for luminous intensities");
    if (!(header.conversionFactor > 0))
        throw fields.error("the conversion factor for luminous intensities must be positive");
    header.tilt = fields.number("tilt of the luminaire during measurement");
    const int sets = fields.integer("number of lamp sets");
    if (sets < 1)
        throw fields.error("a file needs at least 1 lamp set");
    int firstFluxLine = 0;
    for (int s = 0; s < sets; ++s) {
        LdtLampSet set;
        set.count = fields.integer("number of lamps");
        set.type = fields.text("type of lamps");
        set.flux = fields.number("total luminous flux of lamps");
        firstFluxLine = firstFluxLine == 0 ? fields.line() : firstFluxLine;
        if (set.flux < 0)
            throw fields.error("the total luminous flux of lamps must be >= 0");
        set.colour = fields.text("colour appearance");
        set.colourRendering = fields.text("colour rendering");
        set.watts = fields.number("wattage including ballast");
        header.lampSets.push_back(std::move(set));
    }
    if (!(header.lampFlux() > 0))
        throw fields.error(
            "the lamp sets' total luminous flux must be positive: the intensities are cd "
            "per 1000 lm of it",
            firstFluxLine);
    for (double& ratio : header.directRatios)
        ratio = fields.number("direct ratio");

    const int firstCLine = fields.line() + 1;
    const std::vector<double> C = fields.angles(mc, "C-plane angle", 0.0, 360.0);
    if (C.front() != 0 || C.back() >= 360)
        throw fields.error("the C-plane angles must start at 0 and stay below 360",
                           C.front() != 0 ? firstCLine : fields.line());
    const std::vector<size_t> stored = storedPlanes(isym, size_t(mc));
    // The stored planes must start and end on the symmetry's mirror planes.
    auto expectPlane = [&](size_t index, const char* end, double angle) {
        if (C[index] != angle)
            throw fields.error("Isym " + std::to_string(isym) + " stores C-planes " + end + " C" +
                                   formatNumber(angle) + ", but C-plane " +
                                   std::to_string(index + 1) + " is at " + formatNumber(C[index]),
                               firstCLine + int(index));
    };
    if (isym == 2 || isym == 3 || isym == 4)
        expectPlane(stored.back(), "up to", isym == 2 ? 180.0 : 90.0);
    if (isym == 3)
        expectPlane(stored.front(), "from", 270.0);
    std::vector<double> gamma = fields.angles(ng, "gamma angle", 0.0, 180.0);

    std::vector<double> storedC;
    for (size_t k : stored)
        storedC.push_back(C[k]);
    const double scale = header.conversionFactor * header.lampFlux() / 1000.0;
    std::vector<double> candela;
    for (size_t k : stored)
        for (int j = 0; j < ng; ++j) {
            const double I = fields.number([&] {
                return "intensity at C" + formatNumber(C[k]) + ", gamma " +
                       formatNumber(gamma[size_t(j)]);
            });
            if (I < 0)
                throw fields.error("intensity " + formatNumber(I) + " is negative");
            candela.push_back(I * scale);
        }
    if (const std::optional<int> extra = fields.moreText())
        throw fields.error("text after the " + std::to_string(candela.size()) +
                               " intensities that Isym " + std::to_string(isym) + ", Mc " +
                               std::to_string(mc) + " and Ng " + std::to_string(ng) + " call for",
                           *extra);

    CandelaTable table = unfoldTypeC(planeSymmetry(isym), storedC, std::move(gamma), candela);
    return Photometry{name, std::move(table), std::nullopt, std::move(header)};
}

Photometry readLdt(const std::filesystem::path& file) {
    return parseLdt(readPhotometricText(file), file.string());
}

}  // namespace penumbra
