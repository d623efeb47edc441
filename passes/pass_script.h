// Pass scripts: `penumbra render script.toml` (docs/pass-scripts.md). A script names a glTF scene,
// the view and image settings, and an ordered list of [[pass]] tables, each with its `type` and
// that pass's parameters:
//
//     scene = "cornell-box.gltf"     # relative to the script
//     width = 256
//     [[pass]]
//     type = "radiosity"
//     epsilon = 0.005
//
// Loading is two-stage, like the scene's: loadPassScript() turns the file into a PassScript that
// remembers where every value came from; the registry (passes/registry.cpp,
// makeScriptPipeline) then builds the passes from their tables, reading each parameter through
// ScriptTable's typed getters. Every key no getter asked for is an error at its place.
//
// Every error is a ScriptError "file:line:column: key.path: what", followed by the offending line
// and a caret under the column. Lines and columns are 1-based (columns count Unicode code points,
// as toml++ does). This file and pass_script.cpp are the only ones that see toml++.
#pragma once

#include "core/errors.h"

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace penumbra {

// A place in a script, 1-based.
struct PassScript;

struct ScriptLocation {
    int line = 1, column = 1;
};

// One table of a script (the top level or a [[pass]]) behind typed, recording getters, after
// pbrt-v4's ParameterDictionary: get<T>(key, default) returns the default when the key is absent,
// refuses a value of the wrong type at the value's place, and records the key as read;
// reportUnused() then refuses every key nobody read, listing the keys that were read (which, as
// every getter records its key even when absent, are the valid ones).
//
// T is bool, int, int64_t, float, double or std::string. A float or double accepts a TOML integer
// too (epsilon = 1 is the number 1); an int or int64_t accepts only an integer that fits.
// Copies share the table and the record of what was read.
class ScriptTable {
  public:
    // Key path of the table in messages: "" for the top level, "pass[0]" for the first pass.
    const std::string& path() const;
    // The script's file name, as given to loadPassScript().
    const std::string& file() const;
    // Where the table starts (the `[[pass]]` header; 1:1 for the top level).
    ScriptLocation location() const;
    bool has(const std::string& key) const;
    // Whether the key holds a string, for keys that take a string or a number; does not count
    // as reading the key.
    bool holdsString(const std::string& key) const;
    // Whether the key holds an array, for keys that take a number or an array; does not count as
    // reading the key.
    bool holdsArray(const std::string& key) const;
    // Where the key's value is; the table's location when the key is absent.
    ScriptLocation location(const std::string& key) const;

    template <typename T>
    std::optional<T> find(const std::string& key) const;
    template <typename T>
    T get(const std::string& key, T fallback) const {
        return find<T>(key).value_or(fallback);
    }
    // As get(), and refuses a value outside [minimum, maximum] ("expected an integer >= 1, got
    // 0"; a bound at the type's limit is left out of the message).
    template <typename T>
    T get(const std::string& key, T fallback, T minimum, T maximum) const;
    // An array of exactly `count` finite numbers; nothing when absent.
    std::optional<std::vector<double>> numbers(const std::string& key, size_t count) const;
    // A string or an array of strings, each with its location; empty when absent.
    std::vector<std::pair<std::string, ScriptLocation>> strings(const std::string& key) const;

    // The keys present, in file order, each with its value as written in TOML (for `info`).
    std::vector<std::pair<std::string, std::string>> entries() const;

    // An error at the key's value ("file:line:col: path.key: message" plus the line and a caret),
    // or at the table when the key is absent; key "" names the table itself.
    ScriptError error(const std::string& key, const std::string& message) const;
    ScriptError error(ScriptLocation where, const std::string& key,
                      const std::string& message) const;
    // Throws a ScriptError at the first key (in file order) that no getter asked for.
    void reportUnused() const;

    struct Impl;
    explicit ScriptTable(std::shared_ptr<Impl> impl) : impl_(std::move(impl)) {}

  private:
    friend PassScript loadPassScript(const std::string& path);
    std::shared_ptr<Impl> impl_;
};

// One [[luminaire]] table: a measured luminaire (core/photometric_files.h) placed by the script.
struct ScriptLuminaire {
    std::string file;                           // the IES or LDT file, resolved, existing
    std::array<double, 3> position{};           // metres, the glTF file's world frame
    std::array<double, 3> aim{0.0, -1.0, 0.0};  // the nadir's direction (default straight down)
    std::optional<std::array<double, 3>> c0;    // towards the C0 plane; default: across the aim
    float multiplier = 1.0f;
    std::array<float, 3> color{1.0f, 1.0f, 1.0f};
};

// The [[medium]] table: a homogeneous participating medium (core/medium.h) placed by the script.
struct ScriptMedium {
    std::array<float, 3> sigmaA{}, sigmaS{};  // per metre, per channel
    std::array<float, 3> emission{};          // cd/m², per channel; zero where sigmaA is
    float g = 0.0f;                           // in (-1, 1)
    // [x0, y0, z0, x1, y1, z1], metres, the glTF file's world frame, lo < hi on every axis;
    // nothing: the scene's bounding box.
    std::optional<std::array<double, 6>> box;
    // An OpenVDB file whose float grid scales sigma_a and sigma_s (resolved against the script's
    // folder; it exists), and the grid's name (empty: the file's only grid, or "density").
    std::optional<std::string> densityFile;
    std::string densityGrid;
};

// One [[pass]] table: its type and its parameters (`type` already read).
struct ScriptPass {
    std::string type;
    ScriptTable parameters;
};

// A pass script as read, before any pass is built. The optional values are absent when the
// script does not give them; the command line's options override them (docs/pass-scripts.md).
struct PassScript {
    std::string file;               // the script's path, as given
    std::string scene;              // the glTF file, resolved relative to the script's folder
    std::optional<int> sceneIndex;  // glTF `scenes` index
    std::optional<std::string> camera;
    std::optional<int> width, height, spp;
    std::optional<uint32_t> seed;
    std::vector<std::string> outputs;  // resolved relative to the script's folder; may be empty
    // The environment light (cli/scene_input.h, EnvironmentInput): an image file resolved
    // relative to the script's folder, a scale > 0 and a rotation about +Y in degrees.
    std::optional<std::string> environment;
    std::optional<float> environmentScale, environmentRotation, environmentIlluminance;
    // A sky in place of the environment (core/sky.h): its model, its unobstructed horizontal
    // illuminance (lux) and the ground's reflectance.
    std::optional<std::string> sky;
    std::optional<float> skyIlluminance, groundReflectance;
    // The sun (cli/scene_input.h): the site "LAT,LON" and the local time with its UTC offset
    // (checked by core/solar_position.h's parsers), the angle of true north from -Z (degrees,
    // counter-clockwise seen from above) and the direct normal illuminance (lux, >= 0).
    std::optional<std::string> site, time;
    std::optional<float> north, sunDirectNormal;
    // Portals, each "X0,Y0,Z0,X1,Y1,Z1,X2,Y2,Z2" as --portal takes it (core/portals.h), checked.
    std::vector<std::string> portals;
    std::vector<ScriptLuminaire> luminaires;  // [[luminaire]] tables, in order
    std::optional<ScriptMedium> medium;       // the [[medium]] table (at most one for now)
    // The passes, in order: [[pass]] tables, or a built-in pipeline by name (`pipeline`), one of
    // the two (passes/pipeline.h, makeScriptPipeline).
    std::vector<ScriptPass> passes;
    std::optional<std::string> pipeline;
    ScriptTable topLevel;  // for errors about top-level values found later
};

// Reads and checks a pass script: TOML syntax, the top-level keys (types, ranges, that the scene
// file exists and is .gltf or .glb, that outputs have a supported extension, an existing folder
// and no duplicates), that it has [[pass]] tables or a `pipeline` string, not both, and that
// every [[pass]] has a string `type`. Pass parameters and the pipeline's name are read later, by
// makeScriptPipeline(). Throws ScriptError at the offending place; UsageError when the file
// cannot be read.
PassScript loadPassScript(const std::string& path);

}  // namespace penumbra
