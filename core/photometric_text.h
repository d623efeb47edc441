// What the IES and EULUMDAT readers (core/photometric_files.h) share: a file's text and lines,
// and reading its numbers one at a time with the line each stands on, for messages. Not part of
// the readers' interface.
#pragma once

#include "core/photometric_files.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace penumbra {

// The whole file as bytes (both formats are ASCII with the odd Latin-1 byte in their text).
inline std::string readPhotometricText(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in)
        throw InputError(file.string() + ": cannot be opened");
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// The lines of a text without their ends (LF, CR LF or a lone CR: files come from every system);
// line n of the file is element n - 1.
inline std::vector<std::string_view> splitLines(std::string_view text) {
    std::vector<std::string_view> lines;
    while (!text.empty()) {
        const size_t end = text.find_first_of("\r\n");
        lines.push_back(text.substr(0, end));
        if (end == std::string_view::npos)
            break;
        const bool crlf = text[end] == '\r' && end + 1 < text.size() && text[end + 1] == '\n';
        text.remove_prefix(end + (crlf ? 2 : 1));
    }
    return lines;
}

// s without the spaces and tabs at its ends.
inline std::string_view trimBlanks(std::string_view s) {
    const size_t first = s.find_first_not_of(" \t");
    if (first == std::string_view::npos)
        return {};
    return s.substr(first, s.find_last_not_of(" \t") - first + 1);
}

// A number for a message, as short as it reads (45, 22.5, 0.0706).
inline std::string formatNumber(double value) {
    std::ostringstream out;
    out << value;
    return out.str();
}

// The finite number a whole token spells, in the plain decimals both formats write ("5000.",
// ".33", "-1", "2.5E+01", a leading "+"), or nothing. A decimal comma reads as a point, as
// European EULUMDAT writers use it (an IES token never holds a comma: LM-63 delimits by it).
inline std::optional<double> parseDecimal(std::string_view token) {
    std::string text(token.starts_with('+') ? token.substr(1) : token);
    std::replace(text.begin(), text.end(), ',', '.');
    double value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || error != std::errc() || end != text.data() + text.size() ||
        !std::isfinite(value))
        return std::nullopt;
    return value;
}

// Reads a file's numbers one at a time; each format says where the next one is (next()).
// Errors name the file and the line of the number read last.
class NumberReader {
  public:
    explicit NumberReader(const std::string& name) : name_(name) {}
    virtual ~NumberReader() = default;

    // The next number. `what` names it in messages: a string, or a function that makes one,
    // called only for a message (a table's thousands of values then cost no strings).
    template <typename What>
    double number(const What& what) {
        const std::optional<std::string> token = next();
        if (!token)
            throw error("the file ends where the " + describe(what) + " should be");
        const std::optional<double> value = parseDecimal(*token);
        if (!value)
            throw error("expected the " + describe(what) + ", a number, got \"" + *token + "\"");
        return *value;
    }
    int integer(const std::string& what) {
        const double value = number(what);
        if (value != std::floor(value) || std::abs(value) > 1e9)
            throw error("the " + what + " must be a whole number, got " + formatNumber(value));
        return int(value);
    }
    // `count` numbers, each greater than the one before and within [lowest, highest].
    std::vector<double> angles(int count, const std::string& what, double lowest, double highest) {
        std::vector<double> angles;
        for (int i = 0; i < count; ++i) {
            const double angle = number(what);
            if (angle < lowest || angle > highest)
                throw error("the " + what + " " + formatNumber(angle) + " is outside " +
                            formatNumber(lowest) + " to " + formatNumber(highest));
            if (!angles.empty() && angle <= angles.back())
                throw error("the " + what + "s must increase: " + formatNumber(angle) + " after " +
                            formatNumber(angles.back()));
            angles.push_back(angle);
        }
        return angles;
    }

    int line() const { return line_; }  // 1-based line of the number read last
    // An error at `line`, by default the line of the number read last.
    PhotometricFileError error(const std::string& what, int line = 0) const {
        return PhotometricFileError(name_, line == 0 ? line_ : line, what);
    }

  protected:
    // The text of the next number, nothing at the end of the file; sets line_.
    virtual std::optional<std::string> next() = 0;

    int line_ = 0;

  private:
    template <typename What>
    static std::string describe(const What& what) {
        if constexpr (std::is_invocable_v<What>)
            return what();
        else
            return what;
    }

    const std::string& name_;
};

}  // namespace penumbra
