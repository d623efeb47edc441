// The CSV files of `penumbra illuminance`: calculation points in, their illuminance out.
//
// Input: one point per row, `x,y,z,nx,ny,nz` (metres in the glTF file's world frame, then the
// sensor's normal, any non-zero length); a first row that is not numbers is a header; blank lines
// and lines starting with '#' are skipped.
// Output: the header `x,y,z,nx,ny,nz,illuminance_lux,stderr_lux` and one row per input point, in
// the input's order, with the point and normal as the input gave them; with a daylight factor,
// the columns `daylight_factor_percent,stderr_percent` after them.
#pragma once

#include "core/math.h"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace penumbra::cli {

struct CalculationPoint {
    std::array<double, 6> given{};  // x, y, z, nx, ny, nz as read, echoed in the output
    Vec3 normal{0.0f, 1.0f, 0.0f};  // the given normal, of unit length
};

struct PointIlluminance {
    double lux = 0.0;            // mean illuminance (luminance-weighted, Rec. 709 Y)
    double standardError = 0.0;  // of that mean, lux
};

// Reads the points of `path`. Throws InputError naming the file and line for an unreadable file,
// a row that is not six finite numbers, a zero normal, or a file with no point.
std::vector<CalculationPoint> readCalculationPoints(const std::string& path);

// A workplane: the rectangle x in [X0, X1], z in [Z0, Z1] at height y = HEIGHT (metres, the
// file's world frame), cut into square cells of side SPACING (the last ones cut short), one
// upward sensor at each cell's centre, row by row from Z0 (the picture's top) and in each row from
// X0, written "X0,Z0,X1,Z1,HEIGHT,SPACING".
struct Workplane {
    std::vector<CalculationPoint> points;
    int columns = 0, rows = 0;  // along x and along z
};
// Throws UsageError for text that is not six finite numbers with X0 < X1, Z0 < Z1 and a spacing
// > 0, or for more than 10^6 points.
Workplane workplaneGrid(const std::string& text);

// Throws InputError unless `path` ends in .csv and its directory exists: checked before the work.
void checkPointsOutputPath(const std::string& path);

// Writes the results, first to a temporary file in the same directory, renamed over `path` when
// complete (nothing half-written is left on failure). Throws InputError when it cannot. With a
// sky's unobstructed horizontal illuminance E_h (lux), two more columns follow:
// daylight_factor_percent and its stderr_percent, 100 E / E_h.
void writePointIlluminance(const std::string& path, const std::vector<CalculationPoint>& points,
                           const std::vector<PointIlluminance>& results,
                           std::optional<double> skyHorizontalIlluminance = std::nullopt);

}  // namespace penumbra::cli
