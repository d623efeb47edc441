#include "cli/calculation_points.h"

#include "core/errors.h"

#include <unistd.h>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

namespace penumbra::cli {

namespace {

namespace fs = std::filesystem;

std::string trimmed(const std::string& text) {
    const size_t first = text.find_first_not_of(" \t\r");
    if (first == std::string::npos)
        return "";
    const size_t last = text.find_last_not_of(" \t\r");
    return text.substr(first, last - first + 1);
}

std::vector<std::string> splitFields(const std::string& line) {
    std::vector<std::string> fields;
    std::stringstream stream(line);
    std::string field;
    while (std::getline(stream, field, ','))
        fields.push_back(trimmed(field));
    if (!line.empty() && line.back() == ',')
        fields.emplace_back();
    return fields;
}

bool parseNumber(const std::string& text, double& value) {
    const char* begin = text.data();
    const char* end = begin + text.size();
    // from_chars takes no leading '+'.
    if (begin != end && *begin == '+')
        ++begin;
    const auto [stop, error] = std::from_chars(begin, end, value);
    return error == std::errc() && stop == end && begin != end;
}

}  // namespace

std::vector<CalculationPoint> readCalculationPoints(const std::string& path) {
    std::ifstream in(path);
    if (!in)
        throw InputError(path + ": cannot read the calculation points");
    std::vector<CalculationPoint> points;
    std::string line;
    int lineNumber = 0;
    bool firstRow = true;
    while (std::getline(in, line)) {
        ++lineNumber;
        const std::string text = trimmed(line);
        if (text.empty() || text.front() == '#')
            continue;
        const std::vector<std::string> fields = splitFields(text);
        const std::string place = path + ":" + std::to_string(lineNumber) + ": ";
        CalculationPoint point;
        bool numbers = fields.size() == 6;
        for (size_t i = 0; numbers && i < 6; ++i)
            numbers = parseNumber(fields[i], point.given[i]);
        if (!numbers) {
            double ignored = 0.0;
            const bool header = firstRow && !fields.empty() && !parseNumber(fields[0], ignored);
            firstRow = false;
            if (header)
                continue;
            throw InputError(place + "expected six numbers x,y,z,nx,ny,nz, found \"" + text + "\"");
        }
        firstRow = false;
        for (double value : point.given) {
            if (!std::isfinite(value))
                throw InputError(place + "a value is not finite: \"" + text + "\"");
        }
        const Vec3 normal(float(point.given[3]), float(point.given[4]), float(point.given[5]));
        const float length = glm::length(normal);
        if (!(length > 0.0f) || !std::isfinite(length))
            throw InputError(place + "the normal (nx,ny,nz) is zero: \"" + text + "\"");
        point.normal = normal / length;
        points.push_back(point);
    }
    if (points.empty())
        throw InputError(path + ": no calculation point (rows x,y,z,nx,ny,nz)");
    return points;
}

Workplane workplaneGrid(const std::string& text) {
    std::vector<double> v;
    for (const std::string& field : splitFields(text)) {
        double value = 0.0;
        if (!parseNumber(field, value) || !std::isfinite(value)) {
            v.clear();
            break;
        }
        v.push_back(value);
    }
    const auto refuse = [&](const std::string& why) {
        throw UsageError("--grid \"" + text + "\": " + why +
                         "; the form is X0,Z0,X1,Z1,HEIGHT,SPACING (metres)");
    };
    if (v.size() != 6)
        refuse("expected six numbers");
    const double x0 = v[0], z0 = v[1], x1 = v[2], z1 = v[3], height = v[4], spacing = v[5];
    if (!(x0 < x1) || !(z0 < z1))
        refuse("expected X0 < X1 and Z0 < Z1");
    if (!(spacing > 0.0))
        refuse("the spacing must be > 0");
    Workplane grid;
    grid.columns = int(std::ceil((x1 - x0) / spacing - 1e-9));
    grid.rows = int(std::ceil((z1 - z0) / spacing - 1e-9));
    if (double(grid.columns) * double(grid.rows) > 1e6)
        refuse("more than a million points");
    for (int j = 0; j < grid.rows; ++j) {
        const double za = z0 + j * spacing, zb = std::min(z1, za + spacing);
        for (int i = 0; i < grid.columns; ++i) {
            const double xa = x0 + i * spacing, xb = std::min(x1, xa + spacing);
            CalculationPoint point;
            point.given = {0.5 * (xa + xb), height, 0.5 * (za + zb), 0.0, 1.0, 0.0};
            grid.points.push_back(point);
        }
    }
    return grid;
}

void checkPointsOutputPath(const std::string& path) {
    const fs::path output(path);
    if (output.extension() != ".csv")
        throw UsageError(path + ": the output of `illuminance` is a .csv file");
    const fs::path directory = output.parent_path().empty() ? fs::path(".") : output.parent_path();
    std::error_code error;
    if (!fs::is_directory(directory, error))
        throw UsageError(path + ": the directory " + directory.string() + " does not exist");
}

void writePointIlluminance(const std::string& path, const std::vector<CalculationPoint>& points,
                           const std::vector<PointIlluminance>& results,
                           std::optional<double> skyHorizontalIlluminance) {
    const fs::path output(path);
    fs::path temporary = output;
    temporary.replace_filename(output.stem().string() + ".tmp-" + std::to_string(getpid()) +
                               output.extension().string());
    {
        std::ofstream out(temporary);
        out.precision(9);
        out << "x,y,z,nx,ny,nz,illuminance_lux,stderr_lux";
        if (skyHorizontalIlluminance)
            out << ",daylight_factor_percent,stderr_percent";
        out << "\n";
        for (size_t i = 0; i < points.size(); ++i) {
            for (double value : points[i].given)
                out << value << ",";
            out << results[i].lux << "," << results[i].standardError;
            if (skyHorizontalIlluminance) {
                const double percent = 100.0 / *skyHorizontalIlluminance;
                out << "," << results[i].lux * percent << "," << results[i].standardError * percent;
            }
            out << "\n";
        }
        out.flush();
        if (!out) {
            std::error_code ignored;
            fs::remove(temporary, ignored);
            throw InputError(path + ": cannot write the results");
        }
    }
    std::error_code error;
    fs::rename(temporary, output, error);
    if (error) {
        std::error_code ignored;
        fs::remove(temporary, ignored);
        throw InputError(path + ": cannot write the results: " + error.message());
    }
}

}  // namespace penumbra::cli
