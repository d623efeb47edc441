// IES LM-63 photometric files. The layout (LM-63-2002, as every version since 1986 keeps it):
// a format line (none in 1986), keyword lines "[KEY] text" (free text in 1986), "TILT=...",
// then numbers delimited by spaces, tabs, commas or line ends:
//   [TILT=INCLUDE: lamp-to-luminaire geometry, n, n angles, n multiplying factors]
//   lamps, lumens per lamp, candela multiplier, vertical angles V, horizontal angles H,
//   photometric type, units type, width, length, height
//   ballast factor, ballast-lamp photometric factor (2002: future use; 2019: file generation
//   type), input watts
//   V vertical angles, H horizontal angles, then H times V candela values, each horizontal
//   angle's values over all the vertical angles.
#include "core/photometric_files.h"
#include "core/photometric_text.h"

#include <algorithm>
#include <utility>

namespace penumbra {

namespace {

// The year of a format line, 0 if the line is none (a 1986 file starts with its text), or an
// error for a format line of a version LM-63 does not have.
int formatYear(std::string_view line, const std::string& name) {
    line = trimBlanks(line);
    const std::pair<std::string_view, int> known[] = {{"IESNA91", 1991},
                                                      {"IESNA:LM-63-1995", 1995},
                                                      {"IESNA:LM-63-2002", 2002},
                                                      {"IES:LM-63-2019", 2019}};
    for (const auto& [text, year] : known)
        if (line == text)
            return year;
    if (line.starts_with("IESNA") || line.starts_with("IES:"))
        throw PhotometricFileError(name, 1,
                                   "unknown format line \"" + std::string(line) +
                                       "\"; LM-63 files start with IESNA91, IESNA:LM-63-1995, "
                                       "IESNA:LM-63-2002, IES:LM-63-2019 or (1986) no format line");
    return 0;
}

// The numbers after the TILT= line, delimited by spaces, tabs, commas and line ends.
class Numbers : public NumberReader {
  public:
    // From lines[first], the line after the TILT= line, which is line `first` of the file.
    Numbers(const std::vector<std::string_view>& lines, size_t first, const std::string& name)
        : NumberReader(name), lines_(lines), next_(first) {
        line_ = int(first);  // until a number is read, messages point at the TILT= line
    }

    // Whether the numbers are all read; if not, error() points at the one left over.
    bool atEnd() { return !next(); }

  protected:
    std::optional<std::string> next() override {
        constexpr std::string_view kDelimiters = " \t,";
        for (;;) {
            const size_t start = rest_.find_first_not_of(kDelimiters);
            if (start != std::string_view::npos) {
                rest_.remove_prefix(start);
                const size_t end = std::min(rest_.find_first_of(kDelimiters), rest_.size());
                const std::string token(rest_.substr(0, end));
                rest_.remove_prefix(end);
                return token;
            }
            if (next_ == lines_.size())
                return std::nullopt;
            rest_ = lines_[next_++];
            line_ = int(next_);
        }
    }

  private:
    const std::vector<std::string_view>& lines_;
    size_t next_;            // index of the next line to read
    std::string_view rest_;  // what is left of the current line
};

// TILT=INCLUDE's table.
IesTilt readTilt(Numbers& numbers) {
    IesTilt tilt;
    tilt.lampToLuminaireGeometry = numbers.integer("lamp-to-luminaire geometry");
    if (tilt.lampToLuminaireGeometry < 1 || tilt.lampToLuminaireGeometry > 3)
        throw numbers.error("the lamp-to-luminaire geometry must be 1, 2 or 3, got " +
                            std::to_string(tilt.lampToLuminaireGeometry));
    const int count = numbers.integer("number of tilt angles");
    if (count < 1)
        throw numbers.error("the number of tilt angles must be at least 1");
    tilt.angles = numbers.angles(count, "tilt angle", -180.0, 180.0);
    for (int i = 0; i < count; ++i) {
        tilt.factors.push_back(numbers.number("tilt multiplying factor"));
        if (tilt.factors.back() < 0)
            throw numbers.error("a tilt multiplying factor must be >= 0");
    }
    return tilt;
}

// The symmetry a type C file claims by the range of its horizontal angles (LM-63-2002: the
// first is 0, or 90 for symmetry about the 90-270 plane; the last 0, 90, 180 or 360). LM-63-1995
// let an unsymmetric file end past 180 short of 360; it wraps to the plane at 0 if the gap is
// no wider than the file's widest step, else part of the circle was never measured (AGi32's
// knowledge base, "complete explorations", on a file ending at 181).
PlaneSymmetry typeCSymmetry(const std::vector<double>& H, Numbers& numbers) {
    const double first = H.front(), last = H.back();
    if (H.size() == 1)
        return PlaneSymmetry::Rotational;
    if (first == 0 && last == 90)
        return PlaneSymmetry::Quadrant;
    if (first == 0 && last == 180)
        return PlaneSymmetry::AboutC0C180;
    if (first == 90 && last == 270)
        return PlaneSymmetry::AboutC90C270;
    double widestStep = 0;
    for (size_t h = 1; h < H.size(); ++h)
        widestStep = std::max(widestStep, H[h] - H[h - 1]);
    if (first == 0 && last > 180 && 360 - last <= widestStep)
        return PlaneSymmetry::None;
    throw numbers.error("horizontal angles from " + formatNumber(first) + " to " +
                        formatNumber(last) +
                        " declare no symmetry of type C: they must be a single angle, or run "
                        "0 to 90, 0 to 180, 90 to 270 or 0 to 360");
}

}  // namespace

Photometry parseIes(std::string_view text, const std::string& name) {
    const std::vector<std::string_view> lines = splitLines(text);
    if (lines.empty())
        throw PhotometricFileError(name, 1, "the file is empty");
    IesHeader header;
    const int year = formatYear(lines.front(), name);
    header.lm63Year = year == 0 ? 1986 : year;

    // Keywords (or the 1986 free text) up to the TILT= line.
    size_t n = year == 0 ? 0 : 1;
    for (; n < lines.size() && !trimBlanks(lines[n]).starts_with("TILT="); ++n) {
        const std::string_view line = trimBlanks(lines[n]);
        const size_t close = line.find(']');
        if (line.starts_with('[') && close != std::string_view::npos) {
            const std::string key(line.substr(1, close - 1));
            const std::string value(trimBlanks(line.substr(close + 1)));
            if (key == "MORE" && !header.keywords.empty())
                header.keywords.back().value += "\n" + value;
            else
                header.keywords.push_back({key, value});
        } else if (!line.empty()) {
            header.labels.emplace_back(line);
        }
    }
    if (n == lines.size())
        throw PhotometricFileError(name, int(lines.size()),
                                   "no TILT= line: LM-63 has one after the keywords");
    const std::string_view tilt = trimBlanks(trimBlanks(lines[n]).substr(5));
    Numbers numbers(lines, n + 1, name);
    if (tilt == "INCLUDE")
        header.tilt = readTilt(numbers);
    else if (tilt != "NONE")
        throw PhotometricFileError(name, int(n + 1),
                                   "TILT=" + std::string(tilt) +
                                       ": a tilt table in another file is not supported; put it "
                                       "in this one with TILT=INCLUDE, or write TILT=NONE");

    header.lampCount = numbers.integer("number of lamps");
    if (header.lampCount < 1)
        throw numbers.error("the number of lamps must be at least 1");
    header.lumensPerLamp = numbers.number("lumens per lamp");
    if (!(header.lumensPerLamp > 0 || header.lumensPerLamp == -1))
        throw numbers.error("lumens per lamp must be positive, or -1 for absolute photometry");
    header.candelaMultiplier = numbers.number("candela multiplier");
    if (!(header.candelaMultiplier > 0))
        throw numbers.error("the candela multiplier must be positive");
    const int vertical = numbers.integer("number of vertical angles");
    if (vertical < 2)
        throw numbers.error("a table needs at least 2 vertical angles, got " +
                            std::to_string(vertical));
    const int horizontal = numbers.integer("number of horizontal angles");
    if (horizontal < 1)
        throw numbers.error("a table needs at least 1 horizontal angle");
    header.photometricType = numbers.integer("photometric type");
    if (header.photometricType == 3)
        throw numbers.error(
            "photometric type 3 (type A, for automotive lamps) is not supported: "
            "penumbra reads types 1 (C) and 2 (B)");
    if (header.photometricType != 1 && header.photometricType != 2)
        throw numbers.error("unknown photometric type " + std::to_string(header.photometricType) +
                            "; LM-63 has 1 (type C), 2 (type B) and 3 (type A)");
    const bool typeC = header.photometricType == 1;
    if (!typeC && horizontal < 2)
        throw numbers.error("a type B table needs at least 2 horizontal angles");
    header.unitsType = numbers.integer("units type");
    if (header.unitsType != 1 && header.unitsType != 2)
        throw numbers.error("the units type must be 1 (feet) or 2 (metres), got " +
                            std::to_string(header.unitsType));
    header.width = numbers.number("luminous opening width");
    header.length = numbers.number("luminous opening length");
    header.height = numbers.number("luminous opening height");
    header.ballastFactor = numbers.number("ballast factor");
    if (!(header.ballastFactor > 0))
        throw numbers.error("the ballast factor must be positive");
    header.ballastLampFactor =
        numbers.number(header.lm63Year >= 2019   ? "file generation type"
                       : header.lm63Year >= 2002 ? "future-use field"
                                                 : "ballast-lamp photometric factor");
    const bool lampFactorApplies = header.lm63Year < 2002;
    if (lampFactorApplies && !(header.ballastLampFactor > 0))
        throw numbers.error("the ballast-lamp photometric factor must be positive");
    header.inputWatts = numbers.number("input watts");
    if (header.inputWatts < 0)
        throw numbers.error("input watts must be >= 0");

    // Type C angles are gamma (0 nadir, 180 zenith) and C; type B angles V and H, both
    // within -90..90 (LM-63-2002 has them start at -90 or 0 and end at 90).
    const double lowV = typeC ? 0.0 : -90.0, highV = typeC ? 180.0 : 90.0;
    std::vector<double> V = numbers.angles(vertical, "vertical angle", lowV, highV);
    std::vector<double> H =
        numbers.angles(horizontal, "horizontal angle", typeC ? 0.0 : -90.0, typeC ? 360.0 : 90.0);
    // Type B mirrors by its own rule (unfoldTypeB).
    const PlaneSymmetry symmetry = typeC ? typeCSymmetry(H, numbers) : PlaneSymmetry::None;

    const double scale = header.candelaMultiplier * header.ballastFactor *
                         (lampFactorApplies ? header.ballastLampFactor : 1.0);
    std::vector<double> candela(size_t(vertical) * size_t(horizontal));
    for (int h = 0; h < horizontal; ++h)
        for (int v = 0; v < vertical; ++v) {
            const double I = numbers.number([&] {
                return "candela value at horizontal angle " + formatNumber(H[size_t(h)]) +
                       ", vertical angle " + formatNumber(V[size_t(v)]);
            });
            if (I < 0)
                throw numbers.error("candela value " + formatNumber(I) + " is negative");
            // Type C planes are the horizontal angles, type B planes the vertical ones.
            const size_t index = typeC ? size_t(h) * size_t(vertical) + size_t(v)
                                       : size_t(v) * size_t(horizontal) + size_t(h);
            candela[index] = I * scale;
        }
    if (!numbers.atEnd())
        throw numbers.error("numbers after the " + std::to_string(vertical * horizontal) +
                            " candela values that the " + std::to_string(vertical) +
                            " vertical by " + std::to_string(horizontal) +
                            " horizontal angles call for");

    CandelaTable table = typeC ? unfoldTypeC(symmetry, H, std::move(V), candela)
                               : unfoldTypeB(std::move(V), std::move(H), candela);
    return Photometry{name, std::move(table), std::move(header), std::nullopt};
}

Photometry readIes(const std::filesystem::path& file) {
    return parseIes(readPhotometricText(file), file.string());
}

}  // namespace penumbra
