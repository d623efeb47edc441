// Numerical stress (issue 5, item 9): scenes built to break renderers, rendered through the
// command line with the `reference` and the `radiosity` pipelines at a tiny size. Each must exit
// 0 with every pixel finite and no sample dropped as NaN or infinite, and its energy must agree
// with a closed form or with the same scene without the stress where there is one. What is
// already covered elsewhere is not repeated: the Cornell box translated by 1e5 m, scaled to
// millimetres and rotated (robustness_test.cpp), and the radiosity solver alone on slivers, tiny
// faces and far placements (radiosity_robustness_test.cpp).
#include "core/image_io.h"
#include "tests/support/cli_runner.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/radiosity_scenes.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

namespace penumbra::test {
namespace {

using nlohmann::json;

const std::string kReference = "reference", kRadiosity = "radiosity";

// Orthographic camera looking straight down (-Y): rotation of -90 degrees about +X. Image right
// is +X and image up is -Z.
const Vec4 kLookDown{-std::sqrt(0.5f), 0.0f, 0.0f, std::sqrt(0.5f)};

// --- glTF beyond what GltfBuilder writes ------------------------------------------------------

void useExtension(json& gltf, const std::string& name) {
    json& used = gltf["extensionsUsed"];
    if (std::find(used.begin(), used.end(), name) == used.end())
        used.push_back(name);
}

// Turns `material` into clear, non-absorbing glass: KHR_materials_transmission 1 with
// KHR_materials_ior, a solid (KHR_materials_volume thicknessFactor > 0) or a thin wall
// (thicknessFactor 0, the extension's default).
void makeGlass(json& gltf, int material, float ior, float roughness, bool solid) {
    json& m = gltf["materials"][material];
    m["pbrMetallicRoughness"] = {
        {"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0}, {"roughnessFactor", roughness}};
    m["extensions"] = {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
                       {"KHR_materials_ior", {{"ior", ior}}},
                       {"KHR_materials_volume", {{"thicknessFactor", solid ? 1.0 : 0.0}}}};
    for (const char* name :
         {"KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume"})
        useExtension(gltf, name);
}

// Gives mesh `mesh` (in GltfBuilder's order) the vertex normals `normals`, stored in their own
// buffer file next to the scene.
void setNormals(json& gltf, int mesh, const std::vector<Vec3>& normals, const TempDir& dir) {
    const std::string name = "normals" + std::to_string(mesh) + ".bin";
    const size_t bytes = normals.size() * sizeof(Vec3);
    std::ofstream(dir.file(name), std::ios::binary)
        .write(reinterpret_cast<const char*>(normals.data()), static_cast<std::streamsize>(bytes));
    gltf["buffers"].push_back({{"byteLength", bytes}, {"uri", name}});
    gltf["bufferViews"].push_back(
        {{"buffer", gltf["buffers"].size() - 1}, {"byteLength", bytes}, {"target", 34962}});
    gltf["accessors"].push_back({{"bufferView", gltf["bufferViews"].size() - 1},
                                 {"componentType", 5126},
                                 {"count", normals.size()},
                                 {"type", "VEC3"}});
    gltf["meshes"][mesh]["primitives"][0]["attributes"]["NORMAL"] = gltf["accessors"].size() - 1;
}

// A UV sphere, every triangle counter-clockwise seen from outside.
void addSphere(GltfBuilder& scene, const Vec3& centre, float radius, int material) {
    constexpr int kRings = 12, kSegments = 24;
    std::vector<Vec3> p;
    for (int i = 0; i <= kRings; ++i) {
        const float theta = kPi * static_cast<float>(i) / kRings;
        for (int j = 0; j < kSegments; ++j) {
            const float phi = 2.0f * kPi * static_cast<float>(j) / kSegments;
            p.push_back(centre + radius * Vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                                               std::sin(theta) * std::sin(phi)));
        }
    }
    std::vector<uint32_t> indices;
    const auto add = [&](uint32_t a, uint32_t b, uint32_t c) {
        // Orient outwards whatever the parametrisation's handedness; the poles' zero-area
        // triangles are not emitted.
        const Vec3 n = glm::cross(p[b] - p[a], p[c] - p[a]);
        if (glm::length(n) < 1e-9f * radius * radius)
            return;
        if (glm::dot(n, p[a] + p[b] + p[c] - 3.0f * centre) < 0.0f)
            std::swap(b, c);
        indices.insert(indices.end(), {a, b, c});
    };
    for (int i = 0; i < kRings; ++i) {
        for (int j = 0; j < kSegments; ++j) {
            const uint32_t a = i * kSegments + j, b = i * kSegments + (j + 1) % kSegments;
            add(a, b, a + kSegments);
            add(b, b + kSegments, a + kSegments);
        }
    }
    scene.addMesh(p, indices, material);
}

// --- Rendering and the checks every scene gets ----------------------------------------------

struct RenderOptions {
    std::string pipeline = kReference;
    int size = 32;
    int spp = 16;
    // Parameters of the radiosity pass (TOML lines): rendered through a pass script
    // (docs/pass-scripts.md) instead of --pipeline.
    std::string radiosityParameters = {};
};

// Renders the glTF `gltf` through build/bin/penumbra and checks what every stress render must
// satisfy: exit status 0, every pixel finite and no sample dropped as NaN or infinite (the
// tracers drop such samples before the film and count them in `penumbra:*.dropped_samples`; the
// EXR writer would turn a non-finite pixel into 0, so both are checked).
Image render(const json& gltf, const TempDir& dir, const std::string& name, RenderOptions options) {
    // scripts/stress --long: twice the size, four times the samples. Every check below scales:
    // its tolerance comes from the image's own noise or holds for any size.
    if (std::getenv("PENUMBRA_STRESS_LONG")) {
        options.size *= 2;
        options.spp *= 4;
    }
    const std::string scene = dir.file(name + ".gltf"),
                      image = dir.file(name + "-" + options.pipeline + ".exr");
    std::ofstream(scene) << gltf.dump();
    std::string input = scene + " --pipeline " + options.pipeline;
    if (!options.radiosityParameters.empty()) {
        input = dir.file(name + ".toml");
        std::ofstream(input) << "scene = \"" << name << ".gltf\"\n[[pass]]\ntype = \"radiosity\"\n"
                             << options.radiosityParameters << "\n";
    }
    const CliResult result =
        runPenumbra("render " + input + " -o " + image + " --width " +
                    std::to_string(options.size) + " --height " + std::to_string(options.size) +
                    " --spp " + std::to_string(options.spp) + " --seed 3 --threads 2 --quiet");
    EXPECT_EQ(result.status, 0) << name << ": " << result.output;
    if (result.status != 0)
        return Image(options.size, options.size, {"R", "G", "B"});
    // For a look at a failure: PENUMBRA_STRESS_KEEP=DIR keeps every scene and image there.
    if (const char* keep = std::getenv("PENUMBRA_STRESS_KEEP")) {
        for (const std::string& file : {scene, image})
            std::filesystem::copy_file(
                file, std::filesystem::path(keep) / std::filesystem::path(file).filename(),
                std::filesystem::copy_options::overwrite_existing);
    }
    ImageMetadata metadata;
    Image out = readImage(image, &metadata);
    bool reportsDrops = false;
    for (const auto& [key, value] : metadata.attributes()) {
        if (!key.ends_with(".dropped_samples"))
            continue;
        reportsDrops = true;
        EXPECT_EQ(std::get<std::string>(value), "0")
            << name << " (" << options.pipeline << "): " << key;
    }
    EXPECT_TRUE(reportsDrops) << name << ": no dropped_samples in the EXR metadata";
    size_t nonFinite = 0;
    for (const float v : out.pixels())
        nonFinite += std::isfinite(v) ? 0 : 1;
    EXPECT_EQ(nonFinite, 0u) << name << " (" << options.pipeline << ")";
    return out;
}

Image render(const GltfBuilder& scene, const TempDir& dir, const std::string& name,
             const RenderOptions& options) {
    return render(json::parse(scene.json()), dir, name, options);
}

double luminance(const Image& image, int x, int y) {
    return 0.2126 * image.at(x, y, 0) + 0.7152 * image.at(x, y, 1) + 0.0722 * image.at(x, y, 2);
}

// Mean and standard error of the luminance over the pixels (x, y) of `image` where `use(x, y)`.
struct Estimate {
    double mean = 0.0, standardError = 0.0;
    int pixels = 0;
};

Estimate estimateOf(const Image& image, const std::function<double(int, int)>& value,
                    const std::function<bool(int, int)>& use) {
    double sum = 0.0, sumSquares = 0.0;
    int n = 0;
    for (int y = 0; y < image.height(); ++y) {
        for (int x = 0; x < image.width(); ++x) {
            if (!use(x, y))
                continue;
            const double v = value(x, y);
            sum += v;
            sumSquares += v * v;
            ++n;
        }
    }
    if (n < 2)
        return {n ? sum : 0.0, 0.0, n};
    const double mean = sum / n;
    const double variance = std::max(0.0, (sumSquares - n * mean * mean) / (n - 1));
    return {mean, std::sqrt(variance / n), n};
}

Estimate estimate(const Image& image, const std::function<bool(int, int)>& use) {
    return estimateOf(
        image, [&](int x, int y) { return luminance(image, x, y); }, use);
}

Estimate estimateChannel(const Image& image, int channel,
                         const std::function<bool(int, int)>& use) {
    return estimateOf(
        image, [&](int x, int y) { return image.at(x, y, channel); }, use);
}

bool everyPixel(int, int) {
    return true;
}

// Compares two renders of scenes that must look the same, block by block, on the pixels where
// `use` holds: the mean of the luminance differences over each 8 x 8 block must be within
// 1.5 x 4.5 of its standard error, plus `relative` of the block's level for what noise does not
// cover (a deterministic solver's own error, float rounding). The pixels' errors are independent,
// so the standard error is the spread of the block's differences over sqrt(n); pairing the pixels
// cancels the image's own structure. z = 4.5 is a two-sided level of 7e-6 per block, below 1e-3
// over the 16 to 64 blocks of an image; the factor 1.5 is the regression suite's allowance for
// path-tracing noise's skewed tail, which makes a block's own spread too small where rare paths
// carry the light (docs/testing.md). Returns the number of blocks that fail, printing them when
// `print`.
int differingBlocks(const Image& image, const Image& expected, double relative,
                    const std::string& name, const std::function<bool(int, int)>& use = everyPixel,
                    bool print = true) {
    if (image.width() != expected.width() || image.height() != expected.height())
        return -1;
    constexpr int kBlock = 8;
    constexpr double kZ = 4.5 * 1.5;
    Image difference(image.width(), image.height(), {"Y"});
    for (int y = 0; y < image.height(); ++y) {
        for (int x = 0; x < image.width(); ++x)
            difference.at(x, y, 0) =
                static_cast<float>(luminance(image, x, y) - luminance(expected, x, y));
    }
    const double level = estimate(expected, use).mean;
    double largestZ = 0.0;
    int failures = 0;
    for (int by = 0; by < image.height() / kBlock; ++by) {
        for (int bx = 0; bx < image.width() / kBlock; ++bx) {
            const auto inBlock = [&](int x, int y) {
                return x / kBlock == bx && y / kBlock == by && use(x, y);
            };
            const Estimate d = estimateChannel(difference, 0, inBlock);
            if (d.pixels < 2)
                continue;
            const double blockLevel = estimate(expected, inBlock).mean;
            const double allowance = relative * std::max(blockLevel, 1e-3 * level);
            if (std::abs(d.mean) > kZ * d.standardError + allowance) {
                ++failures;
                if (print) {
                    std::cout << name << ": block " << bx << "," << by << ": "
                              << blockLevel + d.mean << " vs " << blockLevel << ", standard error "
                              << d.standardError << "\n";
                }
            }
            if (d.standardError > 0.0)
                largestZ = std::max(largestZ, std::abs(d.mean) / d.standardError);
        }
    }
    const double mean = estimate(image, use).mean;
    std::cout << name << ": mean " << mean << " vs " << level << " ("
              << 100.0 * (mean / level - 1.0) << " %), largest block z " << largestZ << ", "
              << failures << " blocks differ\n";
    return failures;
}

void expectSameImage(const Image& image, const Image& expected, double relative,
                     const std::string& name,
                     const std::function<bool(int, int)>& use = everyPixel) {
    EXPECT_EQ(differingBlocks(image, expected, relative, name, use), 0) << name;
}

// --- Closed forms ----------------------------------------------------------------------------

// Form factor from a differential area to a parallel rectangle a x b at distance c, the area
// element facing it below one corner (Howell's catalogue, configuration B-3).
double cornerFormFactor(double a, double b, double c) {
    const double x = a / c, y = b / c;
    const double sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
    return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2 * M_PI);
}

// Form factor from a differential area at (x, z), facing up, to the parallel rectangle [x0, x1] x
// [z0, z1] at height c above it facing down: B-3 for the four rectangles spanned by the point's
// foot and each corner, added and subtracted (form-factor algebra; Siegel and Howell, "Thermal
// Radiation Heat Transfer", 4.3).
double rectangleFormFactor(double x, double z, double x0, double x1, double z0, double z1,
                           double c) {
    const auto g = [c](double a, double b) {
        return std::copysign(1.0, a) * std::copysign(1.0, b) *
               cornerFormFactor(std::abs(a), std::abs(b), c);
    };
    return g(x1 - x, z1 - z) - g(x0 - x, z1 - z) - g(x1 - x, z0 - z) + g(x0 - x, z0 - z);
}

// Radiance of a Lambertian floor of reflectance rho at horizontal distance r from the foot of a
// point light of I candela at height h: rho / pi * E with E = I cos(theta) / d^2 = I h / d^3.
double pointLitFloor(double rho, double I, double h, double r) {
    return rho / kPi * I * h / std::pow(h * h + r * r, 1.5);
}

// The world point (x, z) seen by pixel (px, py) of a size x size orthographic top view with
// half-extent `half` centred on the origin (image right = +X, image up = -Z).
Vec2 topViewPoint(int px, int py, int size, float half) {
    return {-half + (px + 0.5f) * 2.0f * half / size, -half + (py + 0.5f) * 2.0f * half / size};
}

// The closed form f(x, z) of a floor seen in a top view, as an image (luminance = f): each pixel
// the mean of f over a 4 x 4 grid inside it, the box filter's integral for these smooth f.
Image topViewImage(int size, float half, const std::function<double(Vec2)>& f) {
    Image image(size, size, {"R", "G", "B"});
    for (int py = 0; py < size; ++py) {
        for (int px = 0; px < size; ++px) {
            double sum = 0.0;
            for (int j = 0; j < 4; ++j) {
                for (int i = 0; i < 4; ++i) {
                    const Vec2 p = topViewPoint(px, py, size, half) +
                                   (Vec2(i, j) + 0.5f - 2.0f) * (0.5f * half / size);
                    sum += f(p);
                }
            }
            for (int c = 0; c < 3; ++c)
                image.at(px, py, c) = static_cast<float>(sum / 16.0);
        }
    }
    return image;
}

// Largest |image / expected - 1| of the luminance over all pixels.
double largestRelativeError(const Image& image, const Image& expected) {
    double largest = 0.0;
    for (int y = 0; y < image.height(); ++y) {
        for (int x = 0; x < image.width(); ++x) {
            const double e = luminance(expected, x, y);
            largest = std::max(largest, std::abs(luminance(image, x, y) / e - 1.0));
        }
    }
    return largest;
}

// A floor [-2, 2]^2 of reflectance 0.5 lit by a 100 cd point light 1 m above its centre, seen from
// above over [-1, 1]^2, and its closed form. Radiance varies by up to 9 % across a pixel of the
// 32 x 32 view, whose few stratified samples leave about 1 % per pixel (the reference's check
// is 2 %); radiosity interpolates over elements refined where the irradiance varies (5 %).
struct PointLitFloor {
    static constexpr float kRho = 0.5f, kIntensity = 100.0f, kHeight = 1.0f, kHalf = 1.0f;

    static void build(GltfBuilder& scene) {
        const int floor = scene.addMaterial({.baseColor = Color(kRho)});
        scene.addQuad({-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}, floor);
        scene.addLight({.type = "point", .intensity = kIntensity, .position = {0, kHeight, 0}});
        scene.setOrthographicCamera({0, 5, 0}, kLookDown, kHalf, kHalf);
    }
    static Image expected(int size) {
        return topViewImage(size, kHalf, [](Vec2 p) {
            return pointLitFloor(kRho, kIntensity, kHeight, glm::length(p));
        });
    }
    static double tolerance(const std::string& pipeline) {
        return pipeline == kReference ? 0.02 : 0.05;
    }
};

// The closed box [-1, 1]^3 whose walls emit Le = 1 from the inside and reflect rho.
GltfBuilder furnace(float rho) {
    GltfBuilder scene;
    const int wall = scene.addMaterial({.baseColor = Color(rho), .emissive = Color(1.0f)});
    addClosedBox(scene, wall, wall);
    return scene;
}

// --- The scenes ------------------------------------------------------------------------------

// A closed box whose walls emit Le = 1 and reflect rho = 0.99: L = Le / (1 - rho) = 100
// everywhere (the radiosity equation of a uniform enclosure). Paths average 100 bounces, so a
// tracer whose Russian roulette or depth limit loses energy, or whose weights grow without bound,
// shows it here; the radiosity solver's form-factor errors are amplified 1 / (1 - rho) = 100 times.
TEST(Stress, FurnaceOfAlbedo099) {
    constexpr float kRho = 0.99f;
    constexpr double kExpected = 1.0 / (1.0 - kRho);
    GltfBuilder scene = furnace(kRho);
    scene.setPerspectiveCamera({0, 0, 0.5f}, {0, 0, 0, 1}, 1.2f);
    TempDir dir("stress-furnace099");
    const Image traced = render(scene, dir, "furnace", {.size = 16, .spp = 16});
    const Estimate t = estimate(traced, everyPixel);
    std::cout << "reference: " << t.mean << " +- " << t.standardError << " (expected " << kExpected
              << ")\n";
    // 4096 paths of a geometric number of bounces (mean 100) have a relative standard deviation
    // of about 1, so the mean is within 5 standard errors and the standard error is near 1.6 %.
    // The spread is checked too: with a roulette that lets weights grow (the variance infinite),
    // the standard error was 24 % and the mean 89.
    EXPECT_NEAR(t.mean, kExpected, 5.0 * t.standardError);
    EXPECT_LT(t.standardError, 0.03 * kExpected);

    // Radiosity at its default settings (epsilon 0.01, elements down to 1/16384 of the area) is
    // not made for rho = 0.99: measured +9.9 %. Finite and within 15 %, and, with the settings of
    // the solver's own rho = 0.99 furnace test (radiosity_furnace_test.cpp: elements of 1/64 of a
    // patch, epsilon 5e-4), within the 1 % that test holds it to.
    const Image coarse =
        render(scene, dir, "furnace", {.pipeline = kRadiosity, .size = 16, .spp = 1});
    const double coarseMean = estimate(coarse, everyPixel).mean;
    const Image fine =
        render(scene, dir, "furnace",
               {.pipeline = kRadiosity,
                .size = 16,
                .spp = 1,
                .radiosityParameters = "epsilon = 5e-4\nmin_element_area = 0.0078125"});
    const double fineMean = estimate(fine, everyPixel).mean;
    std::cout << "radiosity: " << coarseMean << " at the defaults, " << fineMean
              << " at fine settings (expected " << kExpected << ")\n";
    EXPECT_NEAR(coarseMean, kExpected, 0.15 * kExpected);
    EXPECT_NEAR(fineMean, kExpected, 0.01 * kExpected);
}

// Light arriving 0.1 degree above the horizon on a large floor, seen from 1 cm above it looking
// at the horizon: the shadow rays run along the floor and the camera rays hit it at grazing
// angles, where a poor ray offset self-shadows. A directional light has no noise: every floor
// pixel is rho / pi E sin(elevation) (Lambert).
TEST(Stress, GrazingLight) {
    constexpr float kRho = 0.5f, kIlluminance = 1000.0f, kElevation = 0.1f * kPi / 180.0f;
    GltfBuilder scene;
    const int floor = scene.addMaterial({.baseColor = Color(kRho)});
    constexpr float half = 100.0f;
    scene.addQuad({-half, 0, -half}, {-half, 0, half}, {half, 0, half}, {half, 0, -half}, floor);
    // The light shines down its -Z: rotate -Z to (0, -sin e, -cos e), i.e. by -e about +X.
    scene.addLight({.type = "directional",
                    .intensity = kIlluminance,
                    .rotation = {std::sin(-kElevation / 2), 0, 0, std::cos(-kElevation / 2)}});
    scene.setPerspectiveCamera({0, 0.01f, 0}, {0, 0, 0, 1}, 0.2f);
    const double expected = kRho / kPi * kIlluminance * std::sin(kElevation);
    TempDir dir("stress-grazing");
    for (const std::string& pipeline : {kReference, kRadiosity}) {
        const Image image = render(scene, dir, "grazing", {.pipeline = pipeline, .spp = 4});
        // The bottom quarter of the rows sees the floor 10 to 20 cm away, 0.05 to 0.1 rad below
        // the horizon; the top quarter sees the empty sky.
        const int h = image.height();
        const Estimate floorRows = estimate(image, [h](int, int y) { return y >= 3 * h / 4; });
        const Estimate sky = estimate(image, [h](int, int y) { return y < h / 4; });
        std::cout << pipeline << ": floor " << floorRows.mean << " (expected " << expected
                  << "), sky " << sky.mean << "\n";
        EXPECT_NEAR(floorRows.mean, expected, 0.01 * expected) << pipeline;
        EXPECT_LE(floorRows.standardError, 0.002 * expected) << pipeline;
        EXPECT_EQ(sky.mean, 0.0) << pipeline;
    }
}

// Emitters of 1e6 and 1e-6 cd/m^2 in one scene (twelve decades): the bright one, 0.3 m square at
// 1 m over a floor, double-sided so the camera above sees it; the dim one lies on the floor. The
// floor must carry rho Le F of the bright one, the dim one its own 1e-6, the bright one 1e6.
TEST(Stress, EmittersTwelveDecadesApart) {
    constexpr float kRho = 0.5f, kBright = 1e6f, kDim = 1e-6f, kHalf = 2.0f;
    constexpr float s = 0.15f, bx = -1.0f, dx = 1.0f, d = 0.4f;
    GltfBuilder scene;
    const int floor = scene.addMaterial({.baseColor = Color(kRho)});
    scene.addQuad({-5, 0, -5}, {-5, 0, 5}, {5, 0, 5}, {5, 0, -5}, floor);
    const int bright = scene.addMaterial({.baseColor = Color(0.0f),
                                          .emissive = Color(1.0f),
                                          .emissiveStrength = kBright,
                                          .doubleSided = true});
    scene.addQuad({bx - s, 1, -s}, {bx + s, 1, -s}, {bx + s, 1, s}, {bx - s, 1, s}, bright);
    const int dim = scene.addMaterial(
        {.baseColor = Color(0.0f), .emissive = Color(1.0f), .emissiveStrength = kDim});
    scene.addQuad({dx - d, 1e-3f, -d}, {dx - d, 1e-3f, d}, {dx + d, 1e-3f, d}, {dx + d, 1e-3f, -d},
                  dim);
    scene.setOrthographicCamera({0, 5, 0}, kLookDown, kHalf, kHalf);
    TempDir dir("stress-decades");
    for (const std::string& pipeline : {kReference, kRadiosity}) {
        const Image image = render(scene, dir, "decades", {.pipeline = pipeline, .spp = 16});
        const int size = image.width();
        const Image floorExpected = topViewImage(size, kHalf, [&](Vec2 p) {
            return kRho * kBright * rectangleFormFactor(p.x, p.y, bx - s, bx + s, -s, s, 1.0);
        });
        // Where a pixel lies wholly inside or wholly outside a square of half side h centred
        // on (cx, 0) (a pixel is 0.125 m at 32 x 32).
        const float pixel = 2.0f * kHalf / size;
        const auto inside = [pixel](Vec2 p, float cx, float h) {
            return std::abs(p.x - cx) < h - pixel / 2 && std::abs(p.y) < h - pixel / 2;
        };
        const auto outside = [pixel](Vec2 p, float cx, float h) {
            return std::abs(p.x - cx) > h + pixel / 2 || std::abs(p.y) > h + pixel / 2;
        };
        const auto onFloor = [&](int x, int y) {
            const Vec2 p = topViewPoint(x, y, size, kHalf);
            return outside(p, dx, d) && outside(p, bx, s);
        };
        int dimPixels = 0, brightPixels = 0;
        for (int y = 0; y < size; ++y) {
            for (int x = 0; x < size; ++x) {
                const Vec2 p = topViewPoint(x, y, size, kHalf);
                const double L = luminance(image, x, y);
                if (inside(p, dx, d)) {
                    EXPECT_NEAR(L, kDim, 1e-4 * kDim) << pipeline << ": dim emitter";
                    ++dimPixels;
                } else if (inside(p, bx, s)) {
                    EXPECT_NEAR(L, kBright, 1e-4 * kBright) << pipeline << ": bright emitter";
                    ++brightPixels;
                }
            }
        }
        EXPECT_GE(dimPixels, 36);  // 6 x 6 and 2 x 2 at 32 x 32
        EXPECT_GE(brightPixels, 4);
        if (pipeline == kReference) {
            // 16 samples of a light that subtends a few degrees: noise only.
            expectSameImage(image, floorExpected, 2e-3, "reference, floor", onFloor);
        } else {
            // The solver refines links to epsilon times the scene's mean radiance, here ~1000
            // cd/m^2 (the 1e6 emitter), so where the floor is 30 cd/m^2 its elements are off by
            // up to 30 %, and shadow-bleeding interpolation darkens the floor around the dim
            // emitter. The floor's mean over the view must still hold the energy.
            const double mean = estimate(image, onFloor).mean,
                         expected = estimate(floorExpected, onFloor).mean;
            std::cout << "radiosity, floor: mean " << mean << " vs " << expected << "\n";
            EXPECT_NEAR(mean, expected, 0.05 * expected);
        }
    }
}

// A point light over a floor of two triangles with 1e4 m edges, with 200 triangles of 1e-7 m
// edges standing on it where the camera looks. The tiny ones cover 1e-14 of a pixel and must
// leave the image that of the bare floor: rho / pi I h / d^3, without noise.
TEST(Stress, TinyTrianglesOnAHugeFloor) {
    constexpr float kRho = PointLitFloor::kRho, kIntensity = PointLitFloor::kIntensity;
    constexpr float kHeight = PointLitFloor::kHeight, kHuge = 5000.0f;  // edges of 1e4 m
    GltfBuilder scene;
    const int floor = scene.addMaterial({.baseColor = Color(kRho)});
    scene.addQuad({-kHuge, 0, -kHuge}, {-kHuge, 0, kHuge}, {kHuge, 0, kHuge}, {kHuge, 0, -kHuge},
                  floor);
    std::vector<Vec3> tiny;
    std::vector<uint32_t> indices;
    constexpr float e = 1e-7f;
    for (int i = 0; i < 200; ++i) {
        const Vec3 base(-0.9f + 0.09f * static_cast<float>(i % 20), 1e-7f,
                        -0.9f + 0.18f * static_cast<float>(i / 20));
        const uint32_t k = static_cast<uint32_t>(tiny.size());
        tiny.insert(tiny.end(), {base, base + Vec3(e, 0, 0), base + Vec3(0, e, 0)});
        indices.insert(indices.end(), {k, k + 1, k + 2});
    }
    scene.addMesh(tiny, indices, floor);
    scene.addLight({.type = "point", .intensity = kIntensity, .position = {0, kHeight, 0}});
    scene.setOrthographicCamera({0, 5, 0}, kLookDown, PointLitFloor::kHalf, PointLitFloor::kHalf);
    TempDir dir("stress-tiny-huge");
    const Image image = render(scene, dir, "tiny-huge", {.spp = 4});
    const double largest = largestRelativeError(image, PointLitFloor::expected(image.width()));
    std::cout << "reference: largest relative error " << largest << "\n";
    EXPECT_LT(largest, PointLitFloor::tolerance(kReference));

    // Radiosity: finite pixels (checked by render()) over the whole floor; its energy is the
    // next test's.
    scene.setOrthographicCamera({0, 5, 0}, kLookDown, kHuge, kHuge);
    render(scene, dir, "tiny-huge-whole", {.pipeline = kRadiosity, .spp = 1});
}

// Radiosity at its defaults meshes a 1e8 m^2 floor into elements of 6100 m^2 (78 m wide), and a
// point light 1 m above it lights a pool about a metre wide. The element means used to miss the
// pool (the floor kept 15 % of the light's energy, then the means took the exact solid angle and
// Gouraud shading spread it over 78 m); the radiosity view now shows the direct light evaluated
// at the corners of elements refined after the solve down to 1/32 of their distance to the light
// (radiosity/shown_direct.h), so a view of the pool must match the closed form as on a small floor
// (PointLitFloor, 5 %), with the whole floor meshed by the scene's size.
TEST(Stress, RadiosityShowsAPointLightsPoolOnAHugeFloor) {
    constexpr float kRho = PointLitFloor::kRho, kIntensity = PointLitFloor::kIntensity;
    constexpr float kHeight = PointLitFloor::kHeight, kHuge = 5000.0f;
    GltfBuilder scene;
    const int floor = scene.addMaterial({.baseColor = Color(kRho)});
    scene.addQuad({-kHuge, 0, -kHuge}, {-kHuge, 0, kHuge}, {kHuge, 0, kHuge}, {kHuge, 0, -kHuge},
                  floor);
    scene.addLight({.type = "point", .intensity = kIntensity, .position = {0, kHeight, 0}});
    scene.setOrthographicCamera({0, 5, 0}, kLookDown, PointLitFloor::kHalf, PointLitFloor::kHalf);
    TempDir dir("stress-huge-floor");
    const Image pool = render(scene, dir, "huge-floor", {.pipeline = kRadiosity, .spp = 4});
    const double largest = largestRelativeError(pool, PointLitFloor::expected(pool.width()));
    std::cout << "radiosity: the pool on a huge floor, largest relative error " << largest << "\n";
    EXPECT_LT(largest, PointLitFloor::tolerance(kRadiosity));
}

// Vertex normals that disagree with the winding: all flipped on one floor, and on another half
// up and half down, so that they interpolate through zero along its middle. The winding says
// which side is the front; the shading normal is turned to it, so both floors must look like a
// floor without normals: the point light's closed form.
TEST(Stress, NormalsAgainstTheWinding) {
    const Vec3 up(0, 1, 0), down(0, -1, 0);
    const std::vector<std::pair<std::string, std::vector<Vec3>>> cases = {
        {"flipped", {down, down, down, down}}, {"opposed", {up, up, down, down}}};
    for (const auto& [name, normals] : cases) {
        GltfBuilder scene;
        PointLitFloor::build(scene);
        TempDir dir("stress-normals-" + name);
        json gltf = json::parse(scene.json());
        setNormals(gltf, 0, normals, dir);
        for (const std::string& pipeline : {kReference, kRadiosity}) {
            const Image image = render(gltf, dir, name, {.pipeline = pipeline, .spp = 4});
            const double largest =
                largestRelativeError(image, PointLitFloor::expected(image.width()));
            std::cout << name << ", " << pipeline << ": largest relative error " << largest << "\n";
            EXPECT_LT(largest, PointLitFloor::tolerance(pipeline)) << name << ", " << pipeline;
        }
    }
}

// Emissive triangles of zero area: a repeated vertex and three collinear points (the loader drops
// them), and one with 1e-20 m edges, whose area underflows to 0 in float after loading. With a
// point light they must add nothing and take nothing from the light sampler; alone, the scene
// must render black, not NaN (a light sampler with zero total power).
TEST(Stress, ZeroAreaLights) {
    const auto build = [](bool withPointLight) {
        GltfBuilder scene;
        if (withPointLight) {
            PointLitFloor::build(scene);
        } else {
            scene.addQuad({-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2},
                          scene.addMaterial({.baseColor = Color(PointLitFloor::kRho)}));
            scene.setOrthographicCamera({0, 5, 0}, kLookDown, 1.0f, 1.0f);
        }
        const int emitter = scene.addMaterial(
            {.baseColor = Color(0.0f), .emissive = Color(1.0f), .emissiveStrength = 1e6f});
        // The 1e-20 m triangle sits on x = z = 0, which the rebasing on the scene's centre
        // leaves exact.
        constexpr float e = 1e-20f;
        scene.addMesh({{0.1f, 0.5f, 0.1f},
                       {0.2f, 0.5f, 0.1f},
                       {0.3f, 0.5f, 0.1f},
                       {0.1f, 0.5f, 0.2f},
                       {0, 0.5f, 0},
                       {0, 0.5f, e},
                       {e, 0.5f, 0}},
                      {0, 1, 2, 0, 3, 3, 4, 5, 6}, emitter);
        return scene;
    };
    TempDir dir("stress-zero-area");
    for (const std::string& pipeline : {kReference, kRadiosity}) {
        const Image lit = render(build(true), dir, "lit", {.pipeline = pipeline, .spp = 4});
        const double largest = largestRelativeError(lit, PointLitFloor::expected(lit.width()));
        std::cout << pipeline << ": largest relative error " << largest << "\n";
        EXPECT_LT(largest, PointLitFloor::tolerance(pipeline)) << pipeline;
        const Image dark = render(build(false), dir, "dark", {.pipeline = pipeline, .spp = 4});
        EXPECT_EQ(estimate(dark, everyPixel).mean, 0.0) << pipeline;
    }
}

// Glass inside a furnace: lossless glass does not change a uniform radiance field, since every
// path that enters a solid leaves it again and the 1 / eta^2 radiance scaling of each refraction
// (Veach 1997, 5.2) cancels with the scaling of its exit. So every pixel, through the glass or not,
// must be Le / (1 - rho) = 2: solid IOR 3.0 glass (total internal reflection beyond 19.5
// degrees), rough index-matched (IOR 1.0) glass, whose generalised half vector wo + wi vanishes
// in the straight-through direction, and nested glass: an IOR 1.5 sphere inside an IOR 3.0 one.
TEST(Stress, GlassInAFurnace) {
    constexpr float kRho = 0.5f;
    constexpr double kExpected = 1.0 / (1.0 - kRho);
    GltfBuilder scene = furnace(kRho);
    const int ior3 = scene.addMaterial({}), ior15 = scene.addMaterial({}),
              rough1 = scene.addMaterial({});
    addSphere(scene, {-0.45f, 0.35f, -0.3f}, 0.35f, ior3);
    addSphere(scene, {0.45f, 0.35f, -0.3f}, 0.35f, rough1);
    addSphere(scene, {0.0f, -0.45f, -0.3f}, 0.4f, ior3);
    addSphere(scene, {0.0f, -0.45f, -0.3f}, 0.25f, ior15);
    scene.setPerspectiveCamera({0, 0, 0.9f}, {0, 0, 0, 1}, 1.2f);
    json gltf = json::parse(scene.json());
    makeGlass(gltf, ior3, 3.0f, 0.0f, true);
    makeGlass(gltf, ior15, 1.5f, 0.0f, true);
    makeGlass(gltf, rough1, 1.0f, 0.5f, true);
    TempDir dir("stress-glass-furnace");
    const Image image = render(gltf, dir, "glass", {.size = 32, .spp = 16});
    Image uniform(image.width(), image.height(), {"R", "G", "B"});
    std::fill(uniform.pixels().begin(), uniform.pixels().end(), static_cast<float>(kExpected));
    expectSameImage(image, uniform, 0.0, "glass in a furnace");
    const Estimate all = estimate(image, everyPixel);
    EXPECT_NEAR(all.mean, kExpected, 5.0 * all.standardError + 1e-3 * kExpected);
    // Radiosity holds solid glass as opaque and black (it carries L D* E only): the walls that
    // see it are darker, never brighter, and nothing may turn NaN.
    const Image radiosity = render(gltf, dir, "glass", {.pipeline = kRadiosity, .spp = 4});
    for (const float v : radiosity.pixels())
        EXPECT_LE(v, 1.01 * kExpected);
}

// A room with a two-tone floor under a ceiling light, and an IOR 1.0 sphere over the tones'
// border: index-matched glass bends nothing and reflects nothing, so the image must equal the
// room's without it (a mirror or a refraction would move the border). Solid and thin-walled,
// smooth and rough; radiosity sees thin glass only (below).
TEST(Stress, IndexMatchedGlassIsInvisible) {
    const auto room = [](bool withSphere) {
        GltfBuilder scene;
        const int walls = scene.addMaterial({.baseColor = Color(0.6f)});
        const int bright = scene.addMaterial({.baseColor = Color(0.9f)});
        const int dark = scene.addMaterial({.baseColor = Color(0.1f)});
        addClosedBox(scene, walls, dark);
        scene.addQuad({0, -0.999f, -1}, {0, -0.999f, 1}, {1, -0.999f, 1}, {1, -0.999f, -1}, bright);
        // A large light: where the sphere blocks the shadow rays (solid glass is opaque to
        // them) the light still arrives by BSDF samples through the glass, often enough to keep
        // the noise's tail light.
        addCeilingLight(scene, 0.9f, 0.999f, 2.0f);
        if (withSphere)
            addSphere(scene, {0.0f, -0.5f, 0.0f}, 0.45f, scene.addMaterial({}));
        scene.setPerspectiveCamera({0, 0, 0.99f}, {0, 0, 0, 1}, 1.4f);
        return scene;
    };
    TempDir dir("stress-ior1");
    const Image without = render(room(false), dir, "without", {.spp = 32});
    const GltfBuilder withSphere = room(true);
    const int sphere = 4;  // materials: walls, bright, dark, light, sphere
    struct Case {
        std::string name;
        float roughness;
        bool solid;
    };
    for (const Case& c :
         {Case{"solid", 0.0f, true}, Case{"rough", 0.5f, true}, Case{"thin", 0.0f, false}}) {
        json gltf = json::parse(withSphere.json());
        makeGlass(gltf, sphere, 1.0f, c.roughness, c.solid);
        expectSameImage(render(gltf, dir, c.name, {.spp = 32}), without, 1e-3,
                        "IOR 1.0, " + c.name);
    }
    // The comparison sees a sphere that refracts: IOR 1.5 must fail it.
    json refracting = json::parse(withSphere.json());
    makeGlass(refracting, sphere, 1.5f, 0.0f, true);
    EXPECT_GT(differingBlocks(render(refracting, dir, "ior15", {.spp = 32}), without, 1e-3,
                              "IOR 1.5 (must differ)", everyPixel, false),
              0);

    // Radiosity keeps the light that thin glass lets straight through and drops what it
    // reflects: glTF's Schlick Fresnel, f0 + (1 - f0)(1 - cos)^5, reflects even at f0 = 0 (IOR
    // 1.0), 1/21 of the light on average over a projected sphere and all of it at its rim. So
    // the sphere shows as a faint ring: within 10 % of the room without it per block.
    json thin = json::parse(withSphere.json());
    makeGlass(thin, sphere, 1.0f, 0.0f, false);
    const RenderOptions radiosity{.pipeline = kRadiosity, .spp = 4};
    expectSameImage(render(thin, dir, "thin", radiosity),
                    render(room(false), dir, "without", radiosity), 0.1, "radiosity, thin IOR 1.0");
}

// A lit room 1e5 m from the origin with a small object left at the origin: the loader's rebasing
// on the geometry's centre cannot help, so the room's vertices sit at 5e4 m in float (a spacing
// of 4 mm) and every hit point carries millimetres of rounding. The image must still be the
// room's at the origin: no leaks at its edges, no self-shadowing from the ray offsets.
TEST(Stress, CoordinatesAt1e5Metres) {
    const auto room = [](const Vec3& at, bool marker) {
        GltfBuilder scene;
        const int walls = scene.addMaterial({.baseColor = Color(0.6f)});
        const int floor = scene.addMaterial({.baseColor = Color(0.3f)});
        addClosedBox(scene, walls, floor);
        addFloorBlock(scene, walls);
        // 5 cm below the ceiling: at 5e4 m float cannot tell 1 mm from nothing (measured: a
        // light 1 mm below the ceiling fights it for the pixels, and the room is 24 % darker).
        addCeilingLight(scene, 0.3f, 0.95f, 10.0f);
        scene.setPerspectiveCamera({0, 0, 0.99f}, {0, 0, 0, 1}, 1.4f);
        if (marker) {
            // 1 cm square at the origin, outside the room and seen by nothing.
            scene.addQuad({-1e5f, -1e5f, -1e5f}, {-1e5f + 0.01f, -1e5f, -1e5f},
                          {-1e5f + 0.01f, -1e5f + 0.01f, -1e5f}, {-1e5f, -1e5f + 0.01f, -1e5f},
                          walls);
        }
        scene.setRootTransform(at, 1.0f);
        return scene;
    };
    TempDir dir("stress-far");
    const Vec3 far(1e5f, 1e5f, 1e5f);
    for (const std::string& pipeline : {kReference, kRadiosity}) {
        const RenderOptions options{.pipeline = pipeline, .spp = pipeline == kReference ? 32 : 4};
        const Image origin = render(room(Vec3(0.0f), false), dir, "origin", options);
        // On the 4 mm grid every vertex moves by up to 2 mm: the 0.6 m light's area by up to
        // 1.3 %, so the reference may differ by 2 % beyond its noise (measured +1.2 %). The
        // radiosity meshes of the two rooms refine differently; at the defaults an element is
        // within about 3.5 % (radiosity_robustness_test.cpp), so two meshes within 7 %.
        expectSameImage(render(room(far, true), dir, "far", options), origin,
                        pipeline == kReference ? 0.02 : 0.07, pipeline + " at 1e5 m");
    }
}

}  // namespace
}  // namespace penumbra::test
