#include "cli/calculation_points.h"

#include "core/errors.h"

#include <unistd.h>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
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

namespace {

// The finite numbers of comma-separated `text`, or none when a field is not one.
std::vector<double> finiteNumbers(const std::string& text) {
    std::vector<double> v;
    for (const std::string& field : splitFields(text)) {
        double value = 0.0;
        if (!parseNumber(field, value) || !std::isfinite(value))
            return {};
        v.push_back(value);
    }
    return v;
}

// The cells of side `spacing` over [x0, x1] x [z0, z1] whose centre (x, z) `sensorHeight` puts
// on the workplane, with their sensors at the height it returns. `refuse` throws.
Workplane cellsOver(double x0, double z0, double x1, double z1, double spacing,
                    const std::function<std::optional<double>(double, double)>& sensorHeight,
                    const std::function<void(const std::string&)>& refuse) {
    Workplane grid;
    grid.columns = std::max(1, int(std::ceil((x1 - x0) / spacing - 1e-9)));
    grid.rows = std::max(1, int(std::ceil((z1 - z0) / spacing - 1e-9)));
    if (double(grid.columns) * double(grid.rows) > 1e6)
        refuse("more than a million points");
    for (int j = 0; j < grid.rows; ++j) {
        const double za = z0 + j * spacing, zb = std::min(z1, za + spacing);
        for (int i = 0; i < grid.columns; ++i) {
            const double xa = x0 + i * spacing, xb = std::min(x1, xa + spacing);
            const double x = 0.5 * (xa + xb), z = 0.5 * (za + zb);
            const std::optional<double> y = sensorHeight(x, z);
            if (!y)
                continue;
            CalculationPoint point;
            point.given = {x, *y, z, 0.0, 1.0, 0.0};
            grid.points.push_back(point);
            grid.cells.push_back(j * grid.columns + i);
        }
    }
    return grid;
}

// Whether (x, z) lies inside the polygon of vertices (xs[k], zs[k]) by the even-odd rule: the
// parity of the edges a ray towards +x crosses (Shimrat 1962; the crossing test of Haines,
// "Point in polygon strategies", Graphics Gems IV, 1994).
bool insidePolygon(const std::vector<double>& xs, const std::vector<double>& zs, double x,
                   double z) {
    bool inside = false;
    for (size_t a = 0, b = xs.size() - 1; a < xs.size(); b = a++) {
        if ((zs[a] > z) != (zs[b] > z) &&
            x < xs[b] + (xs[a] - xs[b]) * (z - zs[b]) / (zs[a] - zs[b]))
            inside = !inside;
    }
    return inside;
}

}  // namespace

Workplane workplaneGrid(const std::string& text) {
    const std::vector<double> v = finiteNumbers(text);
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
    return cellsOver(
        x0, z0, x1, z1, spacing, [height](double, double) { return height; }, refuse);
}

Workplane workplanePolygon(const std::string& text) {
    const std::vector<double> v = finiteNumbers(text);
    const auto refuse = [&](const std::string& why) {
        throw UsageError("--grid-polygon \"" + text + "\": " + why +
                         "; the form is HEIGHT,SPACING,X0,Z0,X1,Z1,X2,Z2[,...] (metres)");
    };
    if (v.size() < 8 || v.size() % 2 != 0)
        refuse("expected a height, a spacing and three or more vertices X,Z");
    const double height = v[0], spacing = v[1];
    if (!(spacing > 0.0))
        refuse("the spacing must be > 0");
    std::vector<double> xs, zs;
    for (size_t k = 2; k < v.size(); k += 2) {
        xs.push_back(v[k]);
        zs.push_back(v[k + 1]);
    }
    const auto [xMin, xMax] = std::minmax_element(xs.begin(), xs.end());
    const auto [zMin, zMax] = std::minmax_element(zs.begin(), zs.end());
    if (!(*xMin < *xMax) || !(*zMin < *zMax))
        refuse("the polygon has no area");
    const auto sensorHeight = [&](double x, double z) -> std::optional<double> {
        return insidePolygon(xs, zs, x, z) ? std::optional<double>(height) : std::nullopt;
    };
    return cellsOver(*xMin, *zMin, *xMax, *zMax, spacing, sensorHeight, refuse);
}

FloorWorkplane parseFloorWorkplane(const std::string& text) {
    const auto refuse = [&](const std::string& why) {
        throw UsageError("--grid-floor \"" + text + "\": " + why +
                         "; the form is NAME,HEIGHT,SPACING (a material's or a mesh's name, "
                         "metres above it)");
    };
    // The name is all before the last two commas (so it may hold commas itself).
    const size_t last = text.rfind(',');
    const size_t comma =
        last == std::string::npos || last == 0 ? std::string::npos : text.rfind(',', last - 1);
    if (comma == std::string::npos || comma == 0)
        refuse("expected a name and two numbers");
    const std::vector<double> v = finiteNumbers(text.substr(comma + 1));
    if (v.size() != 2)
        refuse("expected a name and two numbers");
    if (!(v[1] > 0.0))
        refuse("the spacing must be > 0");
    return FloorWorkplane{text, text.substr(0, comma), v[0], v[1]};
}

Workplane workplaneOverFloor(const FloorWorkplane& floor, const SceneDescription& scene) {
    // The floor's triangles facing up, in the file's frame, and the rectangle they span.
    std::vector<std::array<glm::dvec3, 3>> triangles;
    for (const Mesh& mesh : scene.meshes) {
        const std::string meshName = mesh.name.substr(0, mesh.name.rfind('/'));
        const bool named = scene.materials[size_t(mesh.material)].name == floor.surface ||
                           mesh.name == floor.surface || meshName == floor.surface;
        if (!named)
            continue;
        for (const glm::uvec3& t : mesh.triangles) {
            const std::array<glm::dvec3, 3> p = {glm::dvec3(mesh.positions[t.x]) + scene.origin,
                                                 glm::dvec3(mesh.positions[t.y]) + scene.origin,
                                                 glm::dvec3(mesh.positions[t.z]) + scene.origin};
            const glm::dvec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
            if (glm::length(n) > 0.0 && n.y > 0.5 * glm::length(n))
                triangles.push_back(p);
        }
    }
    const auto refuse = [&](const std::string& why) {
        throw UsageError("--grid-floor \"" + floor.text + "\": " + why);
    };
    if (triangles.empty()) {
        refuse("no surface facing up has the material or mesh name '" + floor.surface + "' in " +
               scene.file);
    }
    glm::dvec3 low(std::numeric_limits<double>::max()), high(-std::numeric_limits<double>::max());
    for (const auto& t : triangles) {
        for (const glm::dvec3& p : t) {
            low = glm::min(low, p);
            high = glm::max(high, p);
        }
    }
    // The floor under (x, z): the plane of the first triangle whose projection holds it.
    const auto sensorHeight = [&](double x, double z) -> std::optional<double> {
        for (const auto& t : triangles) {
            const std::vector<double> xs = {t[0].x, t[1].x, t[2].x}, zs = {t[0].z, t[1].z, t[2].z};
            if (!insidePolygon(xs, zs, x, z))
                continue;
            const glm::dvec3 n = glm::cross(t[1] - t[0], t[2] - t[0]);
            const double y = t[0].y - (n.x * (x - t[0].x) + n.z * (z - t[0].z)) / n.y;
            return y + floor.height;
        }
        return std::nullopt;
    };
    return cellsOver(low.x, low.z, high.x, high.z, floor.spacing, sensorHeight, refuse);
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
                           std::optional<double> skyHorizontalIlluminance,
                           const GroupColumns& groups) {
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
        for (const auto& [name, column] : groups)
            out << ",illuminance_lux_" << name << ",stderr_lux_" << name;
        out << "\n";
        for (size_t i = 0; i < points.size(); ++i) {
            for (double value : points[i].given)
                out << value << ",";
            out << results[i].lux << "," << results[i].standardError;
            if (skyHorizontalIlluminance) {
                const double percent = 100.0 / *skyHorizontalIlluminance;
                out << "," << results[i].lux * percent << "," << results[i].standardError * percent;
            }
            for (const auto& [name, column] : groups)
                out << "," << column[i].lux << "," << column[i].standardError;
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
