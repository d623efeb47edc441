// The OpenVDB reader (core/vdb_reader.h) on files this test writes with OpenVDB itself: the values
// land on the lattice at the voxel centres the file's transform places them, with a border of
// zero; and every bad file is refused with a message that names the file, the grid and the fault.
#include "core/vdb_reader.h"
#include "core/density_grid.h"
#include "core/errors.h"

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>

#include <filesystem>
#include <fstream>
#include <random>

namespace penumbra::test {
namespace {

class VdbReader : public ::testing::Test {
  protected:
    static void SetUpTestSuite() { openvdb::initialize(); }
    void SetUp() override {
        folder_ = std::filesystem::temp_directory_path() /
                  ("penumbra_vdb_reader_" + std::to_string(::getpid()));
        std::filesystem::create_directories(folder_);
    }
    void TearDown() override { std::filesystem::remove_all(folder_); }

    // A grid of voxel size 0.1 m, offset by (1, 2, 3) m, holding value 1 + i + 10 j + 100 k at
    // voxel (i, j, k) of the 2 x 3 x 4 block from (5, 6, 7).
    static openvdb::FloatGrid::Ptr block() {
        openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
        openvdb::math::Transform::Ptr transform =
            openvdb::math::Transform::createLinearTransform(0.1);
        transform->postTranslate(openvdb::Vec3d(1.0, 2.0, 3.0));
        grid->setTransform(transform);
        grid->setName("density");
        openvdb::FloatGrid::Accessor voxels = grid->getAccessor();
        for (int k = 0; k < 4; ++k)
            for (int j = 0; j < 3; ++j)
                for (int i = 0; i < 2; ++i)
                    voxels.setValue(openvdb::Coord(5 + i, 6 + j, 7 + k),
                                    float(1 + i + 10 * j + 100 * k));
        return grid;
    }

    std::string write(const std::string& name, const openvdb::GridPtrVec& grids) const {
        const std::string path = (folder_ / name).string();
        openvdb::io::File(path).write(grids);
        return path;
    }

    // The message of the InputError reading `path` throws; fails when it throws none.
    static std::string refusal(const std::string& path, const std::string& grid = "",
                               size_t maxNodes = 1 << 20) {
        try {
            readVdbDensity(path, grid, maxNodes);
        } catch (const InputError& e) {
            return e.what();
        }
        ADD_FAILURE() << path << " was read";
        return "";
    }

    std::filesystem::path folder_;
};

TEST_F(VdbReader, ValuesSitAtTheVoxelCentresWithAZeroBorder) {
    const std::string path = write("block.vdb", {block()});
    const VoxelDensity voxels = readVdbDensity(path, "", 1 << 20);
    // 2 x 3 x 4 voxels and one of background on every side.
    EXPECT_EQ(voxels.nodes, glm::ivec3(4, 5, 6));
    // Centres of voxels 4 to 7, 5 to 9 and 6 to 11 at 0.1 m, offset by (1, 2, 3).
    EXPECT_NEAR(voxels.box.lo.x, 1.4f, 1e-6f);
    EXPECT_NEAR(voxels.box.lo.y, 2.5f, 1e-6f);
    EXPECT_NEAR(voxels.box.lo.z, 3.6f, 1e-6f);
    EXPECT_NEAR(voxels.box.hi.x, 1.7f, 1e-6f);
    EXPECT_NEAR(voxels.box.hi.y, 2.9f, 1e-6f);
    EXPECT_NEAR(voxels.box.hi.z, 4.1f, 1e-6f);
    const DensityGrid grid(voxels.box, voxels.nodes, voxels.values);
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 2; ++i) {
                const Vec3 centre = Vec3(1.0f, 2.0f, 3.0f) + 0.1f * Vec3(5 + i, 6 + j, 7 + k);
                EXPECT_NEAR(grid.at(centre), float(1 + i + 10 * j + 100 * k), 1e-3f);
            }
    // Halfway between the last voxel and the border: half its value.
    EXPECT_NEAR(grid.at(Vec3(1.0f, 2.0f, 3.0f) + 0.1f * Vec3(6.5f, 8.0f, 10.0f)),
                0.5f * (2 + 20 + 300), 1e-3f);
    EXPECT_EQ(grid.node(0, 2, 3), 0.0f);
    EXPECT_EQ(grid.node(3, 2, 3), 0.0f);
    EXPECT_EQ(grid.maxValue(), 2.0f + 20.0f + 300.0f);
}

// OpenVDB's own trilinear sampler (tools::BoxSampler, in world space) is the oracle of where
// the values sit and how they blend: the density grid agrees with it everywhere in and around
// the active voxels.
TEST_F(VdbReader, AgreesWithOpenVdbsOwnTrilinearSampling) {
    openvdb::FloatGrid::Ptr grid = block();
    const std::string path = write("sampled.vdb", {grid});
    const VoxelDensity voxels = readVdbDensity(path, "", 1 << 20);
    const DensityGrid density(voxels.box, voxels.nodes, voxels.values);
    const openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> sampler(
        *grid);
    std::mt19937_64 random(43);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    for (int i = 0; i < 2000; ++i) {
        // Points from half a voxel outside the bordered box to inside it.
        const openvdb::Vec3d p(1.35 + 0.45 * uniform(random), 2.45 + 0.5 * uniform(random),
                               3.55 + 0.6 * uniform(random));
        // The point's float coordinates are off by up to 2.4e-7 m near z = 4 m, and the density
        // drops by up to 322 over a voxel of 0.1 m (3220 per metre): 1e-3 between the two.
        const float expected = sampler.wsSample(p);
        EXPECT_NEAR(density.at(Vec3(float(p.x()), float(p.y()), float(p.z()))), expected,
                    2e-3f + 1e-5f * expected)
            << "at (" << p.x() << ", " << p.y() << ", " << p.z() << ")";
    }
}

TEST_F(VdbReader, FindsTheGridByNameOrAlone) {
    openvdb::FloatGrid::Ptr smoke = block();
    smoke->setName("smoke");
    const std::string single = write("single.vdb", {smoke});
    EXPECT_EQ(readVdbDensity(single, "", 1 << 20).nodes, glm::ivec3(4, 5, 6));
    EXPECT_EQ(readVdbDensity(single, "smoke", 1 << 20).nodes, glm::ivec3(4, 5, 6));

    openvdb::FloatGrid::Ptr temperature = openvdb::FloatGrid::create(0.0f);
    temperature->setName("temperature");
    temperature->tree().setValue(openvdb::Coord(0), 1.0f);
    const std::string two = write("two.vdb", {smoke, temperature});
    EXPECT_EQ(readVdbDensity(two, "smoke", 1 << 20).nodes, glm::ivec3(4, 5, 6));
    const std::string message = refusal(two);
    EXPECT_NE(message.find("two.vdb"), std::string::npos) << message;
    EXPECT_NE(message.find("none named \"density\""), std::string::npos) << message;
    EXPECT_NE(message.find("\"smoke\", \"temperature\""), std::string::npos) << message;
    EXPECT_NE(refusal(two, "fog").find("no grid \"fog\""), std::string::npos);

    openvdb::FloatGrid::Ptr density = block();
    const std::string named = write("named.vdb", {temperature, density});
    EXPECT_EQ(readVdbDensity(named, "", 1 << 20).nodes, glm::ivec3(4, 5, 6));
}

TEST_F(VdbReader, RefusesWhatIsNotADensity) {
    const auto expectRefused = [&](const std::string& path, const std::string& fault,
                                   size_t maxNodes = 1 << 20) {
        const std::string message = refusal(path, "", maxNodes);
        EXPECT_EQ(message.rfind(path, 0), 0u) << message;
        EXPECT_NE(message.find(fault), std::string::npos) << message;
    };
    expectRefused((folder_ / "missing.vdb").string(), "no such file");
    const std::string garbage = (folder_ / "garbage.vdb").string();
    std::ofstream(garbage) << "not a volume";
    expectRefused(garbage, "not a readable OpenVDB file");

    openvdb::Vec3SGrid::Ptr velocity = openvdb::Vec3SGrid::create();
    velocity->setName("density");
    velocity->tree().setValue(openvdb::Coord(0), openvdb::Vec3s(1.0f));
    expectRefused(write("vectors.vdb", {velocity}), "holds vec3s values");

    openvdb::FloatGrid::Ptr levelSet = block();
    levelSet->setGridClass(openvdb::GRID_LEVEL_SET);
    expectRefused(write("level_set.vdb", {levelSet}), "level set");

    expectRefused(write("empty.vdb", {openvdb::FloatGrid::create(0.0f)}), "no active voxel");

    openvdb::FloatGrid::Ptr background = openvdb::FloatGrid::create(0.5f);
    background->tree().setValue(openvdb::Coord(0), 1.0f);
    expectRefused(write("background.vdb", {background}), "background");

    openvdb::FloatGrid::Ptr negative = block();
    negative->tree().setValue(openvdb::Coord(6, 7, 8), -0.25f);
    expectRefused(write("negative.vdb", {negative}), "voxel (6, 7, 8) holds -0.25");
    openvdb::FloatGrid::Ptr notFinite = block();
    notFinite->tree().setValue(openvdb::Coord(5, 6, 7), std::numeric_limits<float>::quiet_NaN());
    expectRefused(write("nan.vdb", {notFinite}), "voxel (5, 6, 7)");

    openvdb::FloatGrid::Ptr rotated = block();
    openvdb::math::Transform::Ptr turn = openvdb::math::Transform::createLinearTransform(0.1);
    turn->postRotate(0.3, openvdb::math::Y_AXIS);
    rotated->setTransform(turn);
    expectRefused(write("rotated.vdb", {rotated}), "rotates, shears or mirrors");

    // 4 x 5 x 6 = 120 nodes once dense.
    expectRefused(write("large.vdb", {block()}), "120 voxels once made dense", 100);
}

}  // namespace
}  // namespace penumbra::test
