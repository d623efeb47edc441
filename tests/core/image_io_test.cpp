// Image files: EXR round trip with AOV layers and metadata, tone-mapped 8-bit values, atomic
// writes that leave nothing behind on failure, non-finite values, and refused paths.
#include "core/image_io.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

namespace penumbra {
namespace {
namespace fs = std::filesystem;

// Each test writes into a fresh directory of its own, removed afterwards.
class ImageIoTest : public testing::Test {
  protected:
    void SetUp() override {
        const testing::TestInfo* info = testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() /
               ("penumbra-image-io-" + std::to_string(::getpid()) + "-" + info->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override {
        fs::permissions(dir_, fs::perms::owner_all, fs::perm_options::add);
        fs::remove_all(dir_);
    }

    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    std::vector<std::string> listing() const {
        std::vector<std::string> names;
        for (const auto& entry : fs::directory_iterator(dir_)) {
            names.push_back(entry.path().filename().string());
        }
        std::sort(names.begin(), names.end());
        return names;
    }

    fs::path dir_;
};

Image gradient(int width, int height, std::vector<std::string> channels, float scale) {
    Image image(width, height, std::move(channels));
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            for (int c = 0; c < image.channels(); ++c) {
                image.at(x, y, c) = scale * float(1 + x + 10 * y + 100 * c);
            }
        }
    }
    return image;
}

Image uniformRgb(const std::vector<float>& values) {
    Image image(int(values.size()), 1, {"R", "G", "B"});
    for (size_t x = 0; x < values.size(); ++x) {
        for (int c = 0; c < 3; ++c) {
            image.at(int(x), 0, c) = values[x];
        }
    }
    return image;
}

TEST_F(ImageIoTest, ExrRoundTripKeepsLayersAndMetadata) {
    const Image beauty = gradient(5, 3, {"R", "G", "B"}, 0.25f);
    const std::vector<NamedLayer> aovs = {
        {"albedo", gradient(5, 3, {"R", "G", "B"}, 0.001f)},
        {"normal", gradient(5, 3, {"X", "Y", "Z"}, -0.5f)},
        {"depth", gradient(5, 3, {"Z"}, 3.0f)},
    };
    ImageMetadata metadata;
    metadata.set("penumbra:spp", 64);
    metadata.set("penumbra:seconds", 12.5f);
    metadata.set("penumbra:pipeline", std::string("radiosity+raytrace"));
    metadata.set("penumbra:seed", 7);
    metadata.set("penumbra:version", std::string("0.1.0"));
    metadata.set("penumbra:scene", std::string("box.gltf"));
    metadata.set("penumbra:spp", 128);  // replaces the first value

    const std::string file = path("out.exr");
    EXPECT_EQ(writeImage(file, beauty, aovs, metadata, ToneMapping{}), 0u);
    EXPECT_EQ(listing(), std::vector<std::string>{"out.exr"});

    ImageMetadata read;
    const Image image = readImage(file, &read);
    ASSERT_EQ(image.width(), 5);
    ASSERT_EQ(image.height(), 3);
    ASSERT_EQ(image.channels(), 3 + 3 + 3 + 1);
    auto check = [&](const Image& expected, const std::string& prefix) {
        for (int c = 0; c < expected.channels(); ++c) {
            const int channel = image.channelIndex(prefix + expected.channelNames()[size_t(c)]);
            ASSERT_GE(channel, 0) << prefix << expected.channelNames()[size_t(c)];
            for (int y = 0; y < 3; ++y) {
                for (int x = 0; x < 5; ++x) {
                    EXPECT_EQ(image.at(x, y, channel), expected.at(x, y, c));
                }
            }
        }
    };
    check(beauty, "");
    for (const NamedLayer& layer : aovs) {
        check(layer.image, layer.name + ".");
    }

    ASSERT_NE(read.find("penumbra:spp"), nullptr);
    EXPECT_EQ(std::get<int>(*read.find("penumbra:spp")), 128);
    EXPECT_EQ(std::get<float>(*read.find("penumbra:seconds")), 12.5f);
    EXPECT_EQ(std::get<std::string>(*read.find("penumbra:pipeline")), "radiosity+raytrace");
    EXPECT_EQ(std::get<int>(*read.find("penumbra:seed")), 7);
    EXPECT_EQ(std::get<std::string>(*read.find("penumbra:version")), "0.1.0");
    EXPECT_EQ(std::get<std::string>(*read.find("penumbra:scene")), "box.gltf");
}

TEST(ToneMapping, OperatorsAndSrgbEncodingGiveKnownCodeValues) {
    // Code values from the formulas evaluated in double precision, none near a rounding tie.
    EXPECT_EQ(encodeSrgb8(0.0f), 0);
    EXPECT_EQ(encodeSrgb8(0.001f), 3);  // linear segment: 12.92 * 0.001 * 255 = 3.29
    EXPECT_EQ(encodeSrgb8(0.18f), 118);
    EXPECT_EQ(encodeSrgb8(0.5f), 188);
    EXPECT_EQ(encodeSrgb8(1.0f), 255);
    EXPECT_EQ(encodeSrgb8(2.0f), 255);

    const ToneMapping reinhard{0.0f, ToneMapOperator::Reinhard};
    EXPECT_FLOAT_EQ(reinhard.apply(Color(1.0f, 3.0f, 0.0f)).x, 0.5f);
    EXPECT_FLOAT_EQ(reinhard.apply(Color(1.0f, 3.0f, 0.0f)).y, 0.75f);
    const ToneMapping aces{0.0f, ToneMapOperator::Aces};
    // (2.51 + 0.03) / (2.43 + 0.59 + 0.14)
    EXPECT_NEAR(aces.apply(Color(1.0f)).x, 2.54f / 3.16f, 1e-6f);
    EXPECT_EQ(aces.apply(Color(100.0f)).x, 1.0f);
    const ToneMapping brighter{1.0f, ToneMapOperator::Clamp};
    EXPECT_FLOAT_EQ(brighter.apply(Color(0.25f)).x, 0.5f);
    EXPECT_EQ(ToneMapping{}.apply(Color(-1.0f)).x, 0.0f);
}

// Ward 1994: at the display's own adaptation (L_wa = Ld_max / 2 = 50 cd/m²) the scale factor is
// 1 and cd/m² map to display luminance one to one (25 cd/m² shows at 0.25 of 100); in a dim world
// (L_wa = 1 cd/m²) m = [(1.219 + 50^0.4) / (1.219 + 1)]^2.5 = (6.0008 / 2.219)^2.5 = 12.03 by
// hand, so 1 cd/m² shows at 0.1203. The adaptation of an image of Y = 1 and Y = 100 is their
// geometric mean, 10.
TEST(ToneMapping, WardScalesByTheAdaptationLuminance) {
    ToneMapping ward{0.0f, ToneMapOperator::Ward};
    EXPECT_NEAR(ward.apply(Color(25.0f)).x, 0.25f, 1e-6f);
    ward.adaptationLuminance = 1.0f;
    EXPECT_NEAR(ward.apply(Color(1.0f)).x, 0.1203f, 2e-4f);
    EXPECT_EQ(ward.apply(Color(1000.0f)).x, 1.0f);
    Image image(2, 1, {"R", "G", "B"});
    for (int c = 0; c < 3; ++c) {
        image.at(0, 0, c) = 1.0f;
        image.at(1, 0, c) = 100.0f;
    }
    EXPECT_NEAR(wardAdaptationLuminance(image), 10.0f, 1e-3f);
}

// Automatic exposure puts the log-average luminance at middle grey: an image of Y = 2 and Y = 8
// has log-average 4, so 4 cd/m² shows at 0.18 under clamp: EV = log2(0.045).
TEST(ToneMapping, AutomaticExposureShowsTheLogAverageAtMiddleGrey) {
    Image image(2, 1, {"R", "G", "B"});
    for (int c = 0; c < 3; ++c) {
        image.at(0, 0, c) = 2.0f;
        image.at(1, 0, c) = 8.0f;
    }
    const float ev = automaticExposure(image);
    EXPECT_NEAR(ev, std::log2(0.045f), 1e-3f);
    const ToneMapping automatic{ev, ToneMapOperator::Clamp};
    EXPECT_NEAR(automatic.apply(Color(4.0f)).x, 0.18f, 1e-4f);
}

TEST(ToneMapping, ParsesNamesAndListsThemOnError) {
    EXPECT_EQ(parseToneMapOperator("clamp"), ToneMapOperator::Clamp);
    EXPECT_EQ(parseToneMapOperator("reinhard"), ToneMapOperator::Reinhard);
    EXPECT_EQ(parseToneMapOperator("aces"), ToneMapOperator::Aces);
    EXPECT_EQ(parseToneMapOperator("ward"), ToneMapOperator::Ward);
    EXPECT_EQ(parseToneMapOperator("histogram"), ToneMapOperator::Histogram);
    EXPECT_EQ(parseToneMapOperator("human"), ToneMapOperator::Human);
    try {
        parseToneMapOperator("filmic");
        FAIL() << "expected UsageError";
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("clamp, reinhard, aces, ward, histogram, human"),
                  std::string::npos);
    }
}

// The whole-image operators (Ward Larson et al. 1997): a ramp of six decades, 0.01 to 10^4 cd/m²
// evenly in log luminance, more than 8-bit sRGB shows at one exposure (clamp shows every pixel
// from 1 cd/m² up as white); the histogram adjustment shows the ramp rising across the whole
// picture, each eighth brighter than the last, its top white.
TEST(ToneMapping, HistogramAdjustmentShowsEveryDecade) {
    Image scene(64, 4, {"R", "G", "B"});
    const auto luminanceAt = [](int x) { return std::pow(10.0f, -2.0f + 6.0f * float(x) / 63.0f); };
    for (int y = 0; y < scene.height(); ++y)
        for (int x = 0; x < scene.width(); ++x)
            for (int c = 0; c < 3; ++c)
                scene.at(x, y, c) = luminanceAt(x);
    for (const ToneMapOperator op : {ToneMapOperator::Histogram, ToneMapOperator::Human}) {
        SCOPED_TRACE(std::string(toneMapOperatorName(op)));
        const Image display = toneMapImage(scene, ToneMapping{0.0f, op});
        for (int x = 15; x < 64; x += 8)
            EXPECT_LT(encodeSrgb8(display.at(x - 8, 2, 1)), encodeSrgb8(display.at(x, 2, 1))) << x;
        EXPECT_EQ(encodeSrgb8(display.at(63, 2, 1)), 255);
    }
    // Clamp, for comparison: a third of the ramp at white.
    EXPECT_EQ(toneMapImage(scene, ToneMapping{}).at(43, 2, 1), 1.0f);
}

TEST_F(ImageIoTest, PngHoldsToneMappedSrgbCodeValues) {
    struct Case {
        ToneMapping toneMapping;
        std::vector<float> linear;
        std::vector<int> codes;
    };
    const Case cases[] = {
        {{0.0f, ToneMapOperator::Clamp}, {0.0f, 0.18f, 0.5f, 1.0f, 4.0f}, {0, 118, 188, 255, 255}},
        {{1.0f, ToneMapOperator::Clamp}, {0.09f, 0.25f}, {118, 188}},
        {{0.0f, ToneMapOperator::Reinhard}, {1.0f, 3.0f}, {188, 225}},
        {{0.0f, ToneMapOperator::Aces}, {0.18f, 1.0f, 10.0f}, {141, 232, 255}},
    };
    for (const Case& test : cases) {
        const std::string file = path("tone.png");
        writeImage(file, uniformRgb(test.linear), {}, ImageMetadata{}, test.toneMapping);
        const Image image = readImage(file);
        ASSERT_EQ(image.width(), int(test.linear.size()));
        ASSERT_EQ(image.channels(), 3);
        for (size_t x = 0; x < test.codes.size(); ++x) {
            for (int c = 0; c < 3; ++c) {
                EXPECT_EQ(std::lround(image.at(int(x), 0, c) * 255.0f), test.codes[x])
                    << toneMapOperatorName(test.toneMapping.op) << " value " << test.linear[x];
            }
        }
    }
}

TEST_F(ImageIoTest, PngKeepsMetadataAsText) {
    ImageMetadata metadata;
    metadata.set("penumbra:spp", 16);
    metadata.set("penumbra:seconds", 1.25f);
    metadata.set("penumbra:pipeline", std::string("raytrace"));
    writeImage(path("meta.png"), uniformRgb({0.5f}), {}, metadata, ToneMapping{});
    ImageMetadata read;
    readImage(path("meta.png"), &read);
    ASSERT_NE(read.find("penumbra:spp"), nullptr);
    EXPECT_EQ(std::get<std::string>(*read.find("penumbra:spp")), "16");
    EXPECT_EQ(std::get<std::string>(*read.find("penumbra:seconds")), "1.25");
    EXPECT_EQ(std::get<std::string>(*read.find("penumbra:pipeline")), "raytrace");
}

TEST_F(ImageIoTest, NonFiniteValuesAreWrittenAsZeroAndCounted) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    Image beauty = uniformRgb({1.0f, 2.0f});
    beauty.at(0, 0, 1) = nan;
    beauty.at(1, 0, 2) = -inf;
    Image depth(2, 1, {"Z"});
    depth.at(1, 0, 0) = inf;
    const std::string file = path("nan.exr");
    EXPECT_EQ(writeImage(file, beauty, {{"depth", depth}}, ImageMetadata{}, ToneMapping{}), 3u);
    const Image image = readImage(file);
    EXPECT_EQ(image.at(0, 0, image.channelIndex("G")), 0.0f);
    EXPECT_EQ(image.at(0, 0, image.channelIndex("R")), 1.0f);
    EXPECT_EQ(image.at(1, 0, image.channelIndex("B")), 0.0f);
    EXPECT_EQ(image.at(1, 0, image.channelIndex("depth.Z")), 0.0f);
    // In an 8-bit file too, before tone mapping.
    EXPECT_EQ(writeImage(path("nan.png"), beauty, {}, ImageMetadata{}, ToneMapping{}), 2u);
    EXPECT_EQ(std::lround(readImage(path("nan.png")).at(0, 0, 1) * 255.0f), 0);
}

TEST_F(ImageIoTest, FailedRenameRemovesTheTemporaryAndKeepsTheTarget) {
    // The target is a directory: the image is written in full to the temporary file, and the
    // rename over the target fails.
    fs::create_directory(path("taken.exr"));
    EXPECT_THROW(
        writeImage(path("taken.exr"), uniformRgb({1.0f}), {}, ImageMetadata{}, ToneMapping{}),
        ImageIoError);
    EXPECT_EQ(listing(), std::vector<std::string>{"taken.exr"});
    EXPECT_TRUE(fs::is_directory(path("taken.exr")));
}

TEST_F(ImageIoTest, MissingDirectoryIsNamedAndLeavesNoFile) {
    const std::string missing = path("missing/out.exr");
    try {
        writeImage(missing, uniformRgb({1.0f}), {}, ImageMetadata{}, ToneMapping{});
        FAIL() << "expected ImageIoError";
    } catch (const ImageIoError& e) {
        EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(listing().empty());
}

TEST_F(ImageIoTest, UnwritableDirectoryLeavesNoFile) {
    fs::create_directory(path("locked"));
    fs::permissions(path("locked"), fs::perms::owner_read | fs::perms::owner_exec);
    if (::access(path("locked").c_str(), W_OK) == 0) {
        GTEST_SKIP() << "running with privileges that ignore directory permissions (root)";
    }
    try {
        writeImage(path("locked/out.png"), uniformRgb({1.0f}), {}, ImageMetadata{}, ToneMapping{});
        FAIL() << "expected ImageIoError";
    } catch (const ImageIoError& e) {
        EXPECT_NE(std::string(e.what()).find("not writable"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(fs::is_empty(path("locked")));
}

TEST_F(ImageIoTest, UnknownExtensionIsRefusedBeforeWriting) {
    for (const char* name : {"out.bmp", "out", "out.exr.txt"}) {
        try {
            checkOutputPath(path(name));
            FAIL() << "expected ImageIoError for " << name;
        } catch (const ImageIoError& e) {
            const std::string message = e.what();
            EXPECT_NE(message.find(path(name)), std::string::npos) << message;
            EXPECT_NE(message.find(".exr, .png"), std::string::npos) << message;
        }
    }
    EXPECT_THROW(
        writeImage(path("out.bmp"), uniformRgb({1.0f}), {}, ImageMetadata{}, ToneMapping{}),
        ImageIoError);
    EXPECT_TRUE(listing().empty());
    // Accepted: supported extensions in any case, in an existing writable directory.
    EXPECT_NO_THROW(checkOutputPath(path("a.EXR")));
    EXPECT_NO_THROW(checkOutputPath(path("a.png")));
    EXPECT_NO_THROW(checkOutputPath(path("a.jpg")));
    EXPECT_NO_THROW(checkOutputPath(path("a.tif")));
}

TEST_F(ImageIoTest, UnreadableFilesThrowNamingTheFile) {
    const std::string missing = path("nothing.exr");
    try {
        readImage(missing);
        FAIL() << "expected ImageIoError";
    } catch (const ImageIoError& e) {
        EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
    }
    std::ofstream(path("text.png")) << "not an image";
    EXPECT_THROW(readImage(path("text.png")), ImageIoError);
}

}  // namespace
}  // namespace penumbra
