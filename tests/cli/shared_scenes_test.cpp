// Every real glTF scene in ../shared/scenes (Khronos sample assets, the Cornell box as a GLB, two
// architectural interiors; scenes we did not write) renders through the command line: exit 0,
// no NaN or Inf in the image, no sample dropped. Skipped with a message when the folder is absent.
#include "core/image_io.h"
#include "tests/support/cli_runner.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace penumbra::test {
namespace {

namespace fs = std::filesystem;

const fs::path kSharedScenes = fs::path(PENUMBRA_SOURCE_DIR) / ".." / "shared" / "scenes";

std::vector<fs::path> sharedSceneFiles() {
    std::vector<fs::path> files;
    if (!fs::is_directory(kSharedScenes))
        return files;
    for (const auto& folder : fs::directory_iterator(kSharedScenes)) {
        if (!folder.is_directory())
            continue;
        for (const auto& entry : fs::directory_iterator(folder.path())) {
            const std::string extension = entry.path().extension().string();
            if (extension == ".gltf" || extension == ".glb")
                files.push_back(entry.path());
        }
    }
    std::sort(files.begin(), files.end());
    return files;
}

TEST(SharedScenes, EverySceneRendersWithFinitePixels) {
    const std::vector<fs::path> files = sharedSceneFiles();
    if (files.empty())
        GTEST_SKIP() << "no scenes in " << kSharedScenes << " (the shared folder is absent)";
    TempDir dir("shared-scenes");
    for (const fs::path& file : files) {
        SCOPED_TRACE(file.string());
        const std::string out = dir.file("out.exr");
        // Tiny and few samples: this checks robustness on real input, not convergence.
        const CliResult result = runPenumbra("render '" + file.string() + "' -o " + out +
                                             " --width 24 --height 24 --spp 2 --quiet --threads 2");
        ASSERT_EQ(result.status, 0) << result.output;
        ImageMetadata metadata;
        const Image image = readImage(out, &metadata);
        for (const float v : image.pixels())
            ASSERT_TRUE(std::isfinite(v));
        const auto* dropped = metadata.find("penumbra:path.dropped_samples");
        ASSERT_NE(dropped, nullptr);
        EXPECT_EQ(std::get<std::string>(*dropped), "0");
    }
}

}  // namespace
}  // namespace penumbra::test
