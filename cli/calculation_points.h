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
#include "core/scene_description.h"

#include <array>
#include <optional>
#include <string>
#include <utility>
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

// A workplane: square cells of side SPACING over a rectangle x in [X0, X1], z in [Z0, Z1]
// (metres, the file's world frame; the last cells cut short), rows from Z0 (the picture's top),
// each row from X0, and an upward sensor at the centre of each cell that lies on the workplane.
struct Workplane {
    std::vector<CalculationPoint> points;
    std::vector<int> cells;     // per point, its cell: row x columns + column
    int columns = 0, rows = 0;  // along x and along z
};

// `--grid X0,Z0,X1,Z1,HEIGHT,SPACING`: the whole rectangle at y = HEIGHT. Throws UsageError for
// text that is not six finite numbers with X0 < X1, Z0 < Z1 and a spacing > 0, or for more than
// 10^6 cells.
Workplane workplaneGrid(const std::string& text);

// `--grid-polygon HEIGHT,SPACING,X0,Z0,X1,Z1,X2,Z2[,...]`: the cells whose centre lies inside
// the polygon (seen from above; the even-odd rule, so any simple polygon, convex or not), at
// y = HEIGHT. Throws UsageError as workplaneGrid, and for fewer than three vertices.
Workplane workplanePolygon(const std::string& text);

// `--grid-floor NAME,HEIGHT,SPACING`, read before the scene is loaded: the floor NAME, a
// material's or a mesh's name, and the workplane's height above it.
struct FloorWorkplane {
    std::string text;  // as given, for messages
    std::string surface;
    double height = 0.0, spacing = 0.0;
};
// Throws UsageError unless the text is a name and two finite numbers, the spacing > 0.
FloorWorkplane parseFloorWorkplane(const std::string& text);
// The cells over the floor: those whose centre lies above a triangle facing up (its normal within
// 60 degrees of +Y) of a mesh whose material or own name (glTF mesh name, or
// "NAME/PRIMITIVE") is floor.surface, over the bounding rectangle of those triangles; each
// sensor floor.height above that triangle's plane (a room's floor at any level, a sloped one, an
// L-shaped one). `origin` is where the scene's stored positions start in the file's frame
// (SceneDescription::origin). Throws UsageError when no triangle facing up has that name.
Workplane workplaneOverFloor(const FloorWorkplane& floor, const SceneDescription& scene);

// Throws InputError unless `path` ends in .csv and its directory exists: checked before the work.
void checkPointsOutputPath(const std::string& path);

// Writes the results, first to a temporary file in the same directory, renamed over `path` when
// complete (nothing half-written is left on failure). Throws InputError when it cannot. With a
// sky's unobstructed horizontal illuminance E_h (lux), two more columns follow:
// daylight_factor_percent and its stderr_percent, 100 E / E_h.
// After them, for each light group (render's --light-groups, core/light_groups.h), the columns
// illuminance_lux_GROUP,stderr_lux_GROUP.
using GroupColumns = std::vector<std::pair<std::string, std::vector<PointIlluminance>>>;
void writePointIlluminance(const std::string& path, const std::vector<CalculationPoint>& points,
                           const std::vector<PointIlluminance>& results,
                           std::optional<double> skyHorizontalIlluminance = std::nullopt,
                           const GroupColumns& groups = {});

}  // namespace penumbra::cli
