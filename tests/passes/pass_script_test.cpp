// Pass scripts (passes/pass_script.h, docs/pass-scripts.md): what a script says is what
// loadPassScript() and makeScriptPipeline() make of it, and every kind of bad script is refused
// with a ScriptError at the exact line and column of the offending key or value, with that line
// quoted and a caret under the column.
#include "passes/pass_script.h"
#include "passes/pipeline.h"
#include "tests/support/cli_runner.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace penumbra::test {
namespace {

namespace fs = std::filesystem;

void writeText(const std::string& path, const std::string& text) {
    std::ofstream out(path);
    out << text;
    ASSERT_TRUE(out) << "cannot write " << path;
}

std::string firstLine(const std::string& text) {
    return text.substr(0, text.find('\n'));
}

// Scripts in a fresh folder that also holds the scene file they name (loadPassScript checks that
// it exists, not what it contains).
class PassScriptTest : public ::testing::Test {
  protected:
    void SetUp() override { writeText(dir_.file("model.gltf"), "{}"); }

    std::string write(const std::string& text) {
        const std::string path = dir_.file("script.toml");
        writeText(path, text);
        return path;
    }

    // The ScriptError of loading `text` and building its pipeline, without the leading
    // "<path>:": "line:column: key: what", then the quoted line and the caret.
    std::string error(const std::string& text) {
        const std::string path = write(text);
        try {
            makeScriptPipeline(loadPassScript(path));
        } catch (const ScriptError& e) {
            const std::string message = e.what();
            EXPECT_EQ(message.rfind(path + ":", 0), 0u) << message;
            return message.substr(path.size() + 1);
        }
        ADD_FAILURE() << "no ScriptError for\n" << text;
        return "";
    }

    TempDir dir_{"pass-script"};
};

const std::string kScene = "scene = \"model.gltf\"\n";
const std::string kPath = "[[pass]]\ntype = \"path\"\n";

TEST_F(PassScriptTest, ReadsEveryTopLevelKey) {
    fs::create_directories(dir_.file("sub"));
    fs::create_directories(dir_.file("images"));
    const std::string path = dir_.file("sub/script.toml");
    writeText(path,
              "scene = \"../model.gltf\"\n"
              "scene_index = 2\n"
              "camera = \"top\"\n"
              "width = 320\n"
              "height = 200\n"
              "spp = 16\n"
              "seed = 4294967295\n"
              "output = [\"../images/a.exr\", \"b.png\"]\n"
              "portals = [\"0,0,0,1,0,0,0,1,0\", \"auto\"]\n"
              "[[pass]]\n"
              "type = \"radiosity\"\n"
              "epsilon = 0.005\n");
    const PassScript script = loadPassScript(path);
    EXPECT_EQ(script.portals, (std::vector<std::string>{"0,0,0,1,0,0,0,1,0", "auto"}));
    EXPECT_EQ(script.file, path);
    // Paths in the script are relative to the script's folder.
    EXPECT_EQ(fs::path(script.scene), fs::path(dir_.file("model.gltf")).lexically_normal());
    ASSERT_EQ(script.outputs.size(), 2u);
    EXPECT_EQ(fs::path(script.outputs[0]), fs::path(dir_.file("images/a.exr")).lexically_normal());
    EXPECT_EQ(fs::path(script.outputs[1]), fs::path(dir_.file("sub/b.png")).lexically_normal());
    EXPECT_EQ(script.sceneIndex, 2);
    EXPECT_EQ(script.camera, "top");
    EXPECT_EQ(script.width, 320);
    EXPECT_EQ(script.height, 200);
    EXPECT_EQ(script.spp, 16);
    EXPECT_EQ(script.seed, 4294967295u);
    ASSERT_EQ(script.passes.size(), 1u);
    EXPECT_EQ(script.passes[0].type, "radiosity");
    EXPECT_EQ(script.passes[0].parameters.path(), "pass[0]");
    EXPECT_EQ(script.passes[0].parameters.location().line, 10);
    EXPECT_EQ(script.passes[0].parameters.location().column, 1);

    const Pipeline pipeline = makeScriptPipeline(script);
    EXPECT_EQ(pipeline.name(), "script.toml");
    ASSERT_EQ(pipeline.passes().size(), 1u);
    EXPECT_EQ(pipeline.passes()[0]->type(), "radiosity");
}

TEST_F(PassScriptTest, OptionalKeysStayUnsetAndParametersDefault) {
    const PassScript script = loadPassScript(write(kScene + kPath));
    EXPECT_FALSE(script.sceneIndex || script.camera || script.width || script.height ||
                 script.spp || script.seed);
    EXPECT_TRUE(script.outputs.empty());
    const ScriptTable& p = script.passes[0].parameters;
    EXPECT_EQ(p.get("max_depth", 7), 7);
    EXPECT_EQ(p.get<std::string>("solver", "x"), "x");
    EXPECT_FALSE(p.find<float>("epsilon").has_value());
    EXPECT_EQ(makeScriptPipeline(script).passes()[0]->type(), "path");
}

TEST_F(PassScriptTest, TypedGettersConvertOnlyWhatIsExact) {
    const PassScript script = loadPassScript(
        write(kScene + kPath + "a = 3\nb = 0.25\nc = \"text\"\nd = true\ne = 3000000000\n"));
    const ScriptTable& p = script.passes[0].parameters;
    EXPECT_EQ(p.get("a", 0), 3);
    EXPECT_EQ(p.get("a", 0.0), 3.0);  // an integer is a number too
    EXPECT_EQ(p.get("b", 0.0f), 0.25f);
    EXPECT_EQ(p.get<std::string>("c", ""), "text");
    EXPECT_EQ(p.get("d", false), true);
    EXPECT_EQ(p.get<int64_t>("e", 0), 3000000000);
    EXPECT_THROW(p.get("b", 0), ScriptError);  // 0.25 is no integer
    EXPECT_THROW(p.get("e", 0), ScriptError);  // past the int's range
    EXPECT_THROW(p.get("c", 0.0), ScriptError);
    EXPECT_THROW(p.get("a", false), ScriptError);
    const auto entries = p.entries();
    ASSERT_EQ(entries.size(), 6u);  // in file order, with `type`
    EXPECT_EQ(entries[0], (std::pair<std::string, std::string>{"type", "\"path\""}));
    EXPECT_EQ(entries[2], (std::pair<std::string, std::string>{"b", "0.25"}));
}

TEST_F(PassScriptTest, UnknownPassKeyAtTheKeyWithTheValidOnes) {
    const std::string message =
        error(kScene + "[[pass]]\ntype = \"radiosity\"\nepsilon = 0.1\n  epsiln = 0.1\n");
    EXPECT_EQ(firstLine(message),
              "5:3: pass[0].epsiln: unknown key; valid keys here: type, solver, caustics, "
              "specular_transfer, transfer_photons, epsilon, "
              "patch_edge_length, min_element_area, contact_lines, shadow_lines, convergence, "
              "visibility_samples, "
              "max_iterations, max_refinements, iteration, cluster_min_patches, "
              "subdivision_threshold, final_gather, direct_at_corners, indirect_at_corners");
    // The offending line, then a caret under its column.
    EXPECT_NE(message.find("\n      epsiln = 0.1\n      ^"), std::string::npos) << message;
}

TEST_F(PassScriptTest, UnknownTopLevelKey) {
    EXPECT_EQ(firstLine(error(kScene + "widht = 64\n" + kPath)),
              "2:1: widht: unknown key; valid keys here: scene, scene_index, camera, width, "
              "height, spp, seed, output, environment, environment_scale, "
              "environment_rotation, environment_illuminance, sky, sky_illuminance, "
              "ground_reflectance, site, time, north, "
              "sun_direct_normal, portals, pipeline, pass, luminaire, medium");
    // A depth belongs to the path pass, not to the script.
    EXPECT_EQ(firstLine(error(kScene + "max_depth = 3\n" + kPath)).substr(0, 27),
              "2:1: max_depth: unknown key");
}

TEST_F(PassScriptTest, WrongTypes) {
    const std::string message =
        error(kScene + "[[pass]]\ntype = \"radiosity\"\nepsilon = \"high\"\n");
    EXPECT_EQ(firstLine(message), "4:11: pass[0].epsilon: expected a number, got \"high\"");
    EXPECT_NE(message.find("\n    epsilon = \"high\"\n              ^"), std::string::npos)
        << message;
    EXPECT_EQ(firstLine(error(kScene + kPath + "max_depth = 2.5\n")),
              "4:13: pass[0].max_depth: expected an integer, got 2.5");
    EXPECT_EQ(firstLine(error(kScene + "width = \"wide\"\n" + kPath)),
              "2:9: width: expected an integer, got \"wide\"");
    EXPECT_EQ(firstLine(error("scene = 3\n" + kPath)), "1:9: scene: expected a string, got 3");
    EXPECT_EQ(firstLine(error(kScene + "[[pass]]\ntype = 1\n")),
              "3:8: pass[0].type: expected a string, got 1");
}

TEST_F(PassScriptTest, OutOfRange) {
    const std::string radiosity = kScene + "[[pass]]\ntype = \"radiosity\"\n";
    // Radiosity values are checked by validateRadiositySettings, reported at the key.
    EXPECT_EQ(firstLine(error(radiosity + "epsilon = 2\n")),
              "4:11: pass[0].epsilon: expected a number in (0, 1), got 2");
    EXPECT_EQ(firstLine(error(radiosity + "visibility_samples = 5000\n")),
              "4:22: pass[0].visibility_samples: expected an integer in [1, 4096], got 5000");
    EXPECT_EQ(firstLine(error(radiosity + "patch_edge_length = -1.5\n")),
              "4:21: pass[0].patch_edge_length: expected a length >= 0, got -1.5");
    EXPECT_EQ(firstLine(error(radiosity + "convergence = nan\n")),
              "4:15: pass[0].convergence: expected a number in (0, 1), got nan");
    EXPECT_EQ(firstLine(error(radiosity + "solver = \"multigrid\"\n")).substr(0, 45),
              "4:10: pass[0].solver: unknown solver 'multigr");
    EXPECT_EQ(firstLine(error(radiosity + "iteration = \"sor\"\n")),
              "4:13: pass[0].iteration: unknown iteration 'sor'; valid: gauss-seidel, jacobi");
    EXPECT_EQ(firstLine(error(kScene + kPath + "max_depth = -2\n")),
              "4:13: pass[0].max_depth: expected an integer in [-1, 1048576], got -2");
    EXPECT_EQ(firstLine(error(kScene + "spp = 0\n" + kPath)),
              "2:7: spp: expected an integer >= 1, got 0");
    EXPECT_EQ(firstLine(error(kScene + "width = 3000000000\n" + kPath)),
              "2:9: width: expected an integer in [1, 2147483647], got 3000000000");
    EXPECT_EQ(firstLine(error(kScene + "seed = -1\n" + kPath)),
              "2:8: seed: expected an integer in [0, 4294967295], got -1");
    EXPECT_EQ(firstLine(error(kScene + "environment_scale = 0\n" + kPath)),
              "2:21: environment_scale: expected a number > 0, got 0");
    EXPECT_EQ(firstLine(error(kScene + "ground_reflectance = 1.5\n" + kPath)),
              "2:22: ground_reflectance: expected a number in [0, 1], got 1.5");
    EXPECT_EQ(firstLine(error(kScene + "environment_rotation = \"east\"\n" + kPath)).substr(0, 38),
              "2:24: environment_rotation: expected a");
    EXPECT_EQ(firstLine(error(kScene + "time = \"noon\"\n" + kPath)).substr(0, 22),
              "2:8: time: time \"noon\"");
    EXPECT_EQ(firstLine(error(kScene + "portals = [\"0,0,0,1,0,0,0,1,0\", \"1,2,3\"]\n" + kPath))
                  .substr(0, 37),
              "2:33: portals: portal \"1,2,3\": expect");
}

// The [[medium]] table: each coefficient a number for all channels or one per channel, the
// phase function's g, the box, the density file; every bad value refused at its place.
TEST_F(PassScriptTest, MediumTable) {
    const PassScript script = loadPassScript(write(kScene + kPath +
                                                   "[[medium]]\n"
                                                   "sigma_a = 0.01\n"
                                                   "sigma_s = [0.1, 0.2, 0.3]\n"
                                                   "g = 0.6\n"
                                                   "box = [-1, 0, -1, 1, 3, 2]\n"));
    ASSERT_TRUE(script.medium.has_value());
    EXPECT_EQ(script.medium->sigmaA, (std::array<float, 3>{0.01f, 0.01f, 0.01f}));
    EXPECT_EQ(script.medium->sigmaS, (std::array<float, 3>{0.1f, 0.2f, 0.3f}));
    EXPECT_EQ(script.medium->g, 0.6f);
    EXPECT_EQ(script.medium->box, (std::array<double, 6>{-1, 0, -1, 1, 3, 2}));
    // Only sigma_s: no absorption, isotropic, the scene's bounds.
    const PassScript fog = loadPassScript(write(kScene + kPath + "[[medium]]\nsigma_s = 0.05\n"));
    ASSERT_TRUE(fog.medium.has_value());
    EXPECT_EQ(fog.medium->sigmaA, (std::array<float, 3>{0.0f, 0.0f, 0.0f}));
    EXPECT_EQ(fog.medium->g, 0.0f);
    EXPECT_FALSE(fog.medium->box.has_value());
    EXPECT_FALSE(fog.medium->densityFile.has_value());
    EXPECT_FALSE(loadPassScript(write(kScene + kPath)).medium.has_value());
    // A density file, relative to the script, and its grid's name (read later, by the loader).
    writeText(dir_.file("smoke.vdb"), "");
    const PassScript smoke = loadPassScript(
        write(kScene + kPath +
              "[[medium]]\nsigma_s = 3\ndensity = \"smoke.vdb\"\ndensity_grid = \"d\"\n"));
    ASSERT_TRUE(smoke.medium.has_value());
    EXPECT_EQ(fs::path(*smoke.medium->densityFile), fs::path(dir_.file("smoke.vdb")));
    EXPECT_EQ(smoke.medium->densityGrid, "d");

    const std::string medium = kScene + kPath + "[[medium]]\n";
    EXPECT_EQ(firstLine(error(medium + "g = 0.5\n")),
              "4:1: medium[0].sigma_s: missing: a medium needs sigma_a or sigma_s (per metre)");
    EXPECT_EQ(firstLine(error(medium + "sigma_s = 1\ng = 1\n")),
              "6:5: medium[0].g: expected a number in (-1, 1), got 1");
    EXPECT_EQ(firstLine(error(medium + "sigma_s = -0.1\n")),
              "5:11: medium[0].sigma_s: expected a number >= 0 (per metre) or an array of three");
    EXPECT_EQ(firstLine(error(medium + "sigma_a = [0.1, 0.2]\n")),
              "5:11: medium[0].sigma_a: expected an array of 3 numbers, got [0.1, 0.2]");
    EXPECT_EQ(firstLine(error(medium + "sigma_s = 1\nbox = [0, 0, 0, 1, -1, 1]\n")),
              "6:7: medium[0].box: expected [x0, y0, z0, x1, y1, z1] with x0 < x1, y0 < y1 and "
              "z0 < z1");
    EXPECT_EQ(firstLine(error(medium + "sigma_s = 1\ndensty = 2\n")).substr(0, 39),
              "6:1: medium[0].densty: unknown key; val");
    EXPECT_EQ(firstLine(error(medium + "sigma_s = 1\ndensity = 2\n")).substr(0, 40),
              "6:11: medium[0].density: expected a stri");
    EXPECT_EQ(firstLine(error(medium + "sigma_s = 1\n[[medium]]\nsigma_s = 2\n")),
              "6:1: medium[1]: a second [[medium]]: penumbra renders one medium for now");
}

TEST_F(PassScriptTest, PassTypes) {
    EXPECT_EQ(firstLine(error(kScene + "[[pass]]\ntype = \"photon\"\n")),
              "3:8: pass[0].type: unknown pass type 'photon'; valid: radiosity, path, "
              "distribution, whitted, caustics, composite");
    EXPECT_EQ(firstLine(error(kScene + "\n[[pass]]\nepsilon = 0.1\n")),
              "3:1: pass[0].type: missing; valid pass types: radiosity, path, distribution, "
              "whitted, caustics, composite");
}

// The planner's checks (passes/planner.h) reach the script's author at the offending table.
TEST_F(PassScriptTest, PipelinesThatCountAPathTwiceOrLackAProduct) {
    EXPECT_EQ(firstLine(error(kScene + kPath + "\n" + kPath)),
              "5:1: pass[1]: pass 2 (path) and pass 1 (path) both count the light paths L E, L D "
              "E, L S E, ... (path: L(D|S|V)*E; path: L(D|S|V)*E): each path must be counted once");
    // The radiosity view counts L D* E, which a path pass that does not reuse it counts too.
    EXPECT_EQ(firstLine(error(kScene + "[[pass]]\ntype = \"radiosity\"\n\n" + kPath)).substr(0, 71),
              "5:1: pass[1]: pass 2 (path) and pass 1 (radiosity) both count the light");
    EXPECT_EQ(firstLine(error(kScene + kPath + "radiosity = true\n")),
              "2:1: pass[0]: pass 1 (path) reuses the radiosity product, which no earlier pass "
              "makes: put a pass of type 'radiosity' before it");
    EXPECT_EQ(firstLine(error(kScene + "[[pass]]\ntype = \"composite\"\n\n" + kPath)),
              "5:1: pass[1]: a pass after the composite pass: the composite must be the last pass");
    // The "a script that counts caustics twice".
    EXPECT_EQ(firstLine(error(kScene + "[[pass]]\ntype = \"radiosity\"\n\n" + kPath +
                              "radiosity = true\ncaustics = \"include\"\n\n[[pass]]\ntype = "
                              "\"caustics\"\n"))
                  .substr(0, 99),
              "10:1: pass[2]: pass 3 (caustics) and pass 2 (path) both count the light paths L S D "
              "E, L S D S E, L");
    const std::string caustics = kScene + "[[pass]]\ntype = \"caustics\"\n";
    EXPECT_EQ(firstLine(error(caustics + "method = \"sppm\"\n")),
              "4:10: pass[0].method: unknown method 'sppm'; valid: photon_map, progressive");
    // A key of the other method is unknown to this one.
    EXPECT_EQ(firstLine(error(caustics + "method = \"progressive\"\nk = 5\n")).substr(0, 35),
              "5:1: pass[0].k: unknown key; valid ");
    EXPECT_EQ(firstLine(error(caustics + "method = \"progressive\"\nalpha = 1.5\n")).substr(0, 30),
              "5:9: pass[0].alpha: expected a");
    EXPECT_EQ(firstLine(error(kScene + kPath + "caustics = \"some\"\n")),
              "4:12: pass[0].caustics: unknown value 'some'; valid: auto, include, exclude");
    // Whitted's ambient: a number or "radiosity", which needs a radiosity pass before it.
    const std::string whitted = "[[pass]]\ntype = \"whitted\"\n";
    EXPECT_EQ(firstLine(error(kScene + whitted + "ambient = \"sky\"\n")),
              "4:11: pass[0].ambient: unknown value 'sky'; valid: a number, radiosity");
    EXPECT_EQ(firstLine(error(kScene + whitted + "ambient = \"radiosity\"\n")),
              "2:1: pass[0]: pass 1 (whitted) reuses the radiosity product, which no earlier pass "
              "makes: put a pass of type 'radiosity' before it");
    EXPECT_EQ(firstLine(error(kScene + whitted + "ambient = -1\n")).substr(0, 30),
              "4:11: pass[0].ambient: expecte");
    // The final gather: an integer in [0, 65536] or "auto".
    const std::string radiosity = "[[pass]]\ntype = \"radiosity\"\n";
    EXPECT_EQ(firstLine(error(kScene + radiosity + "final_gather = \"on\"\n")),
              "4:16: pass[0].final_gather: unknown value 'on'; valid: an integer in [0, 65536], "
              "auto");
    EXPECT_EQ(firstLine(error(kScene + radiosity + "final_gather = -1\n")).substr(0, 35),
              "4:16: pass[0].final_gather: expecte");
}

TEST_F(PassScriptTest, MissingPasses) {
    EXPECT_EQ(firstLine(error(kScene)).substr(0, 45),
              "1:1: pass: missing: a script needs at least o");
    EXPECT_EQ(firstLine(error(kScene + "[pass]\ntype = \"path\"\n")),
              "2:1: pass: expected [[pass]] tables (an array of tables), got a table");
    // A built-in pipeline in their place, but not with them; its name must be a string.
    EXPECT_EQ(firstLine(error(kScene + "pipeline = \"hybrid\"\n" + kPath)),
              "2:12: pipeline: give either a built-in `pipeline` or [[pass]] tables, not both");
    EXPECT_EQ(firstLine(error(kScene + "pipeline = 3\n")).substr(0, 32),
              "2:12: pipeline: expected a strin");
}

// A built-in pipeline by name: the preset's passes, checked by name when the pipeline is made.
TEST_F(PassScriptTest, ABuiltInPipeline) {
    const PassScript script = loadPassScript(write(kScene + "pipeline = \"hybrid\"\n"));
    EXPECT_TRUE(script.passes.empty());
    const Pipeline pipeline = makeScriptPipeline(script);
    EXPECT_EQ(pipeline.name(), "hybrid");
    ASSERT_EQ(pipeline.passes().size(), 3u);
    EXPECT_EQ(pipeline.passes()[2]->type(), "path");
    EXPECT_EQ(firstLine(error(kScene + "pipeline = \"hybird\"\n")).substr(0, 59),
              "2:12: pipeline: unknown pipeline 'hybird'; valid: reference");
}

TEST_F(PassScriptTest, MissingOrBadScene) {
    EXPECT_EQ(firstLine(error("# no scene\nwidth = 8\n" + kPath)).substr(0, 24),
              "1:1: scene: missing: the");
    const std::string missing = error("scene = \"nowhere/box.gltf\"\n" + kPath);
    EXPECT_EQ(firstLine(missing),
              "1:9: scene: file not found: " +
                  (fs::path(dir_.file("nowhere/box.gltf")).lexically_normal()).string());
    EXPECT_EQ(firstLine(error("scene = \"model.obj\"\n" + kPath)),
              "1:9: scene: expected a .gltf or .glb file, got \"model.obj\"");
    EXPECT_EQ(firstLine(error(kScene + "environment = \"sky/none.exr\"\n" + kPath)),
              "2:15: environment: file not found: " +
                  (fs::path(dir_.file("sky/none.exr")).lexically_normal()).string());
}

TEST_F(PassScriptTest, MissingScriptFile) {
    const std::string path = dir_.file("absent.toml");
    try {
        loadPassScript(path);
        ADD_FAILURE() << "no error";
    } catch (const UsageError& e) {
        EXPECT_EQ(std::string(e.what()), path + ": pass script not found");
    }
}

TEST_F(PassScriptTest, TomlSyntaxErrorsAtTheirPlace) {
    const std::string message = error(kScene + "width = = 3\n" + kPath);
    EXPECT_EQ(firstLine(message).substr(0, 23), "2:9: TOML syntax error:");
    EXPECT_NE(message.find("\n    width = = 3\n            ^"), std::string::npos) << message;
    // A key given twice is a TOML error, at the second's value.
    EXPECT_EQ(firstLine(error(kScene + "spp = 1\nspp = 2\n" + kPath)),
              "3:7: TOML syntax error: Error while parsing key-value pair: cannot redefine "
              "existing integer 'spp'");
    EXPECT_EQ(firstLine(error(kScene + "camera = \"unterminated\n" + kPath)).substr(0, 24),
              "2:23: TOML syntax error:");
}

TEST_F(PassScriptTest, BadOutputs) {
    EXPECT_EQ(firstLine(error(kScene + "output = [\"a.exr\", \"b.png\", \"a.exr\"]\n" + kPath)),
              "2:29: output: \"a.exr\" is given twice (first at line 2)");
    EXPECT_EQ(firstLine(error(kScene + "output = [\"x.exr\", \"./x.exr\"]\n" + kPath)),
              "2:20: output: \"./x.exr\" is given twice (first at line 2)");
    const std::string format = firstLine(error(kScene + "output = \"image.xyz\"\n" + kPath));
    EXPECT_EQ(format.rfind("2:10: output: " + dir_.file("image.xyz") + ": ", 0), 0u) << format;
    EXPECT_NE(format.find("unsupported image format \".xyz\""), std::string::npos) << format;
    EXPECT_NE(
        firstLine(error(kScene + "output = \"no/dir/a.exr\"\n" + kPath)).find("does not exist"),
        std::string::npos);
    EXPECT_EQ(firstLine(error(kScene + "output = []\n" + kPath)),
              "2:10: output: expected a string or an array of strings, got []");
    EXPECT_EQ(firstLine(error(kScene + "output = [\"a.exr\", 2]\n" + kPath)),
              "2:20: output: expected a string, got 2");
}

TEST_F(PassScriptTest, UnknownKernelListsTheKernels) {
    EXPECT_EQ(firstLine(error(kScene + "[[pass]]\ntype = \"caustics\"\nkernel = \"box\"\n")),
              "4:10: pass[0].kernel: unknown kernel 'box'; valid: cone, epanechnikov, gaussian");
}

TEST_F(PassScriptTest, BadDepthIsRefusedEvenWhenTheCommandLineReplacesIt) {
    // The table is read either way: the override does not hide a mistake in the script.
    const PassScript script = loadPassScript(write(kScene + kPath + "max_depth = 99999999\n"));
    EXPECT_THROW(makeScriptPipeline(script, PassOverrides{.maxDepth = 3}), ScriptError);
}

// Every key a pass prints (the plan, the image's metadata) is one its script reads, under the
// same name and with a value that reads back as itself: a script written from a pass's printed
// parameters makes a pass that prints the same ones. Each type is tried with its defaults and
// with values set, in each of its variants.
TEST_F(PassScriptTest, PrintedParametersReadBackAsThemselves) {
    const auto lastPassParameters = [&](const std::string& passes) {
        const Pipeline pipeline = makeScriptPipeline(loadPassScript(write(kScene + passes)));
        return pipeline.passes().back()->parameters();
    };
    // A printed value as TOML: numbers and booleans as they are, words quoted; the radiosity
    // pass's explanation of its caustics key (in brackets) is not part of the value.
    const auto asToml = [](std::string value) {
        value = value.substr(0, value.find(" ("));
        if (value == "true" || value == "false")
            return value;
        char* end = nullptr;
        std::strtod(value.c_str(), &end);
        return *end == '\0' && !value.empty() ? value : "\"" + value + "\"";
    };
    const std::string solution = "[[pass]]\ntype = \"radiosity\"\n";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"", "type = \"radiosity\"\n"},
        {"",
         "type = \"radiosity\"\nepsilon = 0.02\nfinal_gather = 64\niteration = \"jacobi\"\n"
         "patch_edge_length = 0.5\ncaustics = \"exclude\"\n"},
        {"", "type = \"radiosity\"\nsolver = \"progressive\"\nthreshold = 0.01\nambient = false\n"},
        {"", "type = \"path\"\n"},
        {solution, "type = \"path\"\nmax_depth = 7\nradiosity = true\ncaustics = \"include\"\n"},
        {solution, "type = \"distribution\"\nmax_specular_depth = 3\n"},
        {"", "type = \"whitted\"\nambient = 0.25\n"},
        {solution, "type = \"whitted\"\nambient = \"radiosity\"\n"},
        {"", "type = \"caustics\"\n"},
        {"",
         "type = \"caustics\"\nphotons = 5000\nk = 20\nmax_radius = 0.1\n"
         "kernel = \"gaussian\"\nseed = 9\nview_spp = 4\n"},
        {"", "type = \"caustics\"\nmethod = \"progressive\"\niterations = 3\nalpha = 0.5\n"},
        {"", "type = \"composite\"\n"},
    };
    for (const auto& [before, pass] : cases) {
        const PassStats printed = lastPassParameters(before + "[[pass]]\n" + pass);
        // The type line, then what the pass printed.
        std::string written = before + "[[pass]]\n" + pass.substr(0, pass.find('\n') + 1);
        for (const auto& [key, value] : printed)
            written += key + " = " + asToml(value) + "\n";
        PassStats reprinted;
        EXPECT_NO_THROW(reprinted = lastPassParameters(written)) << written;
        EXPECT_EQ(reprinted, printed) << written;
    }
}

}  // namespace
}  // namespace penumbra::test
