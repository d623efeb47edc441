// Reads the density of a heterogeneous medium from an OpenVDB file (.vdb; Museth 2013, "VDB:
// High-Resolution Sparse Volumes with Dynamic Topology"), the format smoke and cloud simulations
// and Blender, Houdini and EmberGen export. The only file of the libraries that includes OpenVDB.
#pragma once

#include "core/math.h"

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace penumbra {

// A voxel grid's values as DensityGrid (core/density_grid.h) takes them: nodes at the voxel
// centres over the active voxels' bounding box grown by one voxel on every side (the background,
// zero, there, so the density fades to zero at the edge as OpenVDB's own trilinear sampling
// does), x fastest; `box` the centres' extent in the file's world frame (metres).
struct VoxelDensity {
    Bounds3 box;
    glm::ivec3 nodes{0};
    std::vector<float> values;
};

// The float grid named `gridName` of `file`; when `gridName` is empty, the file's only grid or
// else its grid named "density" (the name Blender and Houdini give a smoke's density).
// Refused (InputError naming the file and the grid): a file OpenVDB cannot read, a grid that is
// missing (the message lists those there are), not of floats, a level set (a distance, not a
// density), with no active voxel, with a background other than 0, with a rotated, sheared or
// mirrored voxel transform, with a value that is negative or not finite (the first one's voxel
// named), or with more than `maxNodes` nodes once made dense.
VoxelDensity readVdbDensity(const std::filesystem::path& file, const std::string& gridName,
                            size_t maxNodes);

}  // namespace penumbra
