#include "core/vdb_reader.h"

#include "core/errors.h"

#include <openvdb/openvdb.h>

#include <cmath>
#include <mutex>

namespace penumbra {
namespace {

std::string describe(const openvdb::Coord& c) {
    return "(" + std::to_string(c.x()) + ", " + std::to_string(c.y()) + ", " +
           std::to_string(c.z()) + ")";
}

// The grid to read: `gridName`, or else the only one or the one named "density"; its absence
// names what the file holds.
openvdb::GridBase::Ptr readGrid(openvdb::io::File& vdb, const std::string& fileName,
                                const std::string& gridName) {
    std::vector<std::string> names;
    for (auto name = vdb.beginName(); name != vdb.endName(); ++name)
        names.push_back(name.gridName());
    std::string list;
    for (const std::string& name : names)
        list += (list.empty() ? "" : ", ") + ("\"" + name + "\"");
    const bool single = names.size() == 1;
    if (gridName.empty() && !single && !vdb.hasGrid("density")) {
        throw InputError(fileName + ": " + std::to_string(names.size()) +
                         " grids and none named \"density\"; name the density's with "
                         "density_grid (the file holds " +
                         (list.empty() ? "none" : list) + ")");
    }
    const std::string name = !gridName.empty() ? gridName : single ? names.front() : "density";
    if (!vdb.hasGrid(name)) {
        throw InputError(fileName + ": no grid \"" + name + "\" (the file holds " +
                         (list.empty() ? "none" : list) + ")");
    }
    return vdb.readGrid(name);
}

// The voxel transform's scale per axis, when it is one (no rotation, shear or mirror).
openvdb::Vec3d axisAlignedScale(const openvdb::math::Transform& transform,
                                const std::string& where) {
    const openvdb::Vec3d origin = transform.indexToWorld(openvdb::Vec3d(0.0));
    openvdb::Vec3d scale;
    bool aligned = transform.isLinear();
    for (int axis = 0; axis < 3 && aligned; ++axis) {
        openvdb::Vec3d unit(0.0);
        unit[axis] = 1.0;
        const openvdb::Vec3d step = transform.indexToWorld(unit) - origin;
        scale[axis] = step[axis];
        for (int other = 0; other < 3; ++other) {
            if (other != axis && std::abs(step[other]) > 1e-6 * std::abs(step[axis]))
                aligned = false;
        }
        aligned = aligned && step[axis] > 0.0;
    }
    if (!aligned)
        throw InputError(where +
                         ": the voxel transform rotates, shears or mirrors the grid; "
                         "penumbra reads axis-aligned grids with a positive scale");
    return scale;
}

}  // namespace

VoxelDensity readVdbDensity(const std::filesystem::path& file, const std::string& gridName,
                            size_t maxNodes) {
    static std::once_flag initialized;
    std::call_once(initialized, [] { openvdb::initialize(); });
    const std::string fileName = file.string();
    if (!std::filesystem::is_regular_file(file))
        throw InputError(fileName + ": cannot be opened (no such file)");
    openvdb::GridBase::Ptr base;
    try {
        openvdb::io::File vdb(fileName);
        vdb.open();
        base = readGrid(vdb, fileName, gridName);
        vdb.close();
    } catch (const openvdb::Exception& e) {
        throw InputError(fileName + ": not a readable OpenVDB file (" + e.what() + ")");
    }
    const std::string where = fileName + ": grid \"" + base->getName() + "\"";
    const openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
    if (!grid)
        throw InputError(where + ": holds " + base->valueType() + " values; a density is float");
    if (grid->getGridClass() == openvdb::GRID_LEVEL_SET)
        throw InputError(where + ": is a level set (a signed distance), not a density");
    if (grid->background() != 0.0f)
        throw InputError(where + ": background " + std::to_string(grid->background()) +
                         ", expected 0 (no medium outside the active voxels)");
    const openvdb::CoordBBox active = grid->evalActiveVoxelBoundingBox();
    if (active.empty())
        throw InputError(where + ": has no active voxel");
    const openvdb::Vec3d scale = axisAlignedScale(grid->transform(), where);

    // One voxel of background around the active ones.
    const openvdb::Coord lo = active.min() - openvdb::Coord(1),
                         hi = active.max() + openvdb::Coord(1);
    VoxelDensity density;
    density.nodes = glm::ivec3(hi.x() - lo.x() + 1, hi.y() - lo.y() + 1, hi.z() - lo.z() + 1);
    const size_t count =
        size_t(density.nodes.x) * size_t(density.nodes.y) * size_t(density.nodes.z);
    if (count > maxNodes)
        throw InputError(where + ": " + std::to_string(count) + " voxels once made dense (" +
                         describe(active.dim()) + " active), more than the " +
                         std::to_string(maxNodes) + " penumbra holds");
    const openvdb::Vec3d worldLo = grid->transform().indexToWorld(lo.asVec3d());
    density.box.extend(Vec3(float(worldLo.x()), float(worldLo.y()), float(worldLo.z())));
    density.box.extend(Vec3(float(worldLo.x() + scale.x() * (hi.x() - lo.x())),
                            float(worldLo.y() + scale.y() * (hi.y() - lo.y())),
                            float(worldLo.z() + scale.z() * (hi.z() - lo.z()))));

    density.values.reserve(count);
    const openvdb::FloatGrid::ConstAccessor voxels = grid->getConstAccessor();
    for (int z = lo.z(); z <= hi.z(); ++z)
        for (int y = lo.y(); y <= hi.y(); ++y)
            for (int x = lo.x(); x <= hi.x(); ++x) {
                const openvdb::Coord ijk(x, y, z);
                const float value = voxels.getValue(ijk);
                if (!(value >= 0.0f && std::isfinite(value)))
                    throw InputError(where + ": voxel " + describe(ijk) + " holds " +
                                     std::to_string(value) + ", expected a finite value >= 0");
                density.values.push_back(value);
            }
    return density;
}

}  // namespace penumbra
