// Reading pass scripts with toml++ (the only file that includes it: CONTRIBUTING.md, "Layering").
//
// Top-level keys of a script (docs/pass-scripts.md has the full table):
//   key          type                      default            meaning
//   scene        string                    required           glTF file, relative to the script
//   scene_index  int >= 0                  the file's scene   glTF `scenes` index
//   camera       string                    the first camera   glTF camera by name
//   width        int >= 1                  from the camera    image width, pixels
//   height       int >= 1                  from the camera    image height, pixels
//   spp          int >= 1                  64                 samples per pixel
//   seed         int in [0, 2^32 - 1]      0                  random seed
//   output       string or array of them   none (-o)          images, relative to the script
//   environment  string                    the scene's        environment image, relative to it
//   environment_scale     float > 0        1                  multiplies its radiance
//   environment_rotation  float            0                  degrees about +Y
//   environment_illuminance  float > 0     none               lux on an upward plane: the scale
//   sky          string                    none               a sky model (core/sky.h)
//   sky_illuminance       float > 0        10000              lux, horizontal, unobstructed
//   ground_reflectance    float in [0, 1]  0.2                the ground below the horizon
//   site         string "LAT,LON"          none               where the sun is seen from
//   time         string (ISO 8601)         none               local time with its UTC offset
//   north        float                     0                  true north from -Z, degrees
//   sun_direct_normal     float >= 0       none               the sun's E_n, lux
//   portals      string or array of them   "auto"             windows, "X0,Y0,Z0,...,Z2" each,
//                                                             "auto": found, "none": no portal
//   luminaire    array of tables           none               measured luminaires: file,
//                                                             position, aim, c0, multiplier,
//                                                             color (docs/pass-scripts.md)
//   medium       array of one table        none               a participating medium: sigma_a,
//                                                             sigma_s, g, emission, box,
//                                                             density (.vdb), density_grid
//   pass         array of tables           required           the passes, in order
#include "passes/pass_script.h"

#include "core/image_io.h"
#include "core/portals.h"
#include "core/solar_position.h"

#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <type_traits>

namespace penumbra {

namespace fs = std::filesystem;

namespace {

// The script's name and text, to quote the offending line in messages.
struct ScriptSource {
    std::string file;
    std::vector<std::string> lines;
};

ScriptLocation locationOf(const toml::source_region& region) {
    return {static_cast<int>(std::max<toml::source_index>(region.begin.line, 1)),
            static_cast<int>(std::max<toml::source_index>(region.begin.column, 1))};
}

bool before(const ScriptLocation& a, const ScriptLocation& b) {
    return a.line != b.line ? a.line < b.line : a.column < b.column;
}

// A line of spaces (tabs kept, so that the caret lines up under tabs too) ending in a caret
// under code point `column` (1-based) of `text`.
std::string caretLine(const std::string& text, int column) {
    std::string caret;
    int codePoint = 1;
    for (const char c : text) {
        if (codePoint >= column)
            break;
        // Continuation bytes of UTF-8 (10xxxxxx) belong to the code point before them.
        if ((static_cast<unsigned char>(c) & 0xC0) == 0x80)
            continue;
        caret += c == '\t' ? '\t' : ' ';
        ++codePoint;
    }
    caret.append(static_cast<size_t>(std::max(column - codePoint, 0)), ' ');
    return caret + "^";
}

ScriptError errorAt(const ScriptSource& source, ScriptLocation at, const std::string& keyPath,
                    const std::string& message) {
    std::string what = (keyPath.empty() ? "" : keyPath + ": ") + message;
    if (at.line >= 1 && static_cast<size_t>(at.line) <= source.lines.size()) {
        const std::string& text = source.lines[static_cast<size_t>(at.line) - 1];
        what += "\n    " + text + "\n    " + caretLine(text, at.column);
    }
    return ScriptError(source.file, at.line, at.column, what);
}

// A value for messages, as TOML would write it: strings in double quotes, numbers in their
// shortest round-trip form (0.05, not toml++'s 0.050000000000000003), arrays element by element.
std::string describe(const toml::node& node) {
    if (node.is_table())
        return "a table";
    if (const auto* array = node.as_array()) {
        std::string text;
        for (const toml::node& element : *array)
            text += (text.empty() ? "" : ", ") + describe(element);
        return "[" + text + "]";
    }
    if (const auto* string = node.as_string()) {
        std::string text;
        for (const char c : string->get())
            text += c == '"' || c == '\\' ? std::string("\\") + c : std::string(1, c);
        return "\"" + text + "\"";
    }
    if (const auto* floating = node.as_floating_point()) {
        char buffer[32];
        const auto end = std::to_chars(buffer, buffer + sizeof buffer, floating->get()).ptr;
        return std::string(buffer, end);
    }
    std::ostringstream out;
    node.visit([&out](const auto& value) {
        if constexpr (toml::is_value<decltype(value)>)
            out << value;
    });
    return out.str();
}

template <typename T>
std::string noun() {
    if constexpr (std::is_same_v<T, bool>)
        return "a boolean (true or false)";
    else if constexpr (std::is_integral_v<T>)
        return "an integer";
    else if constexpr (std::is_floating_point_v<T>)
        return "a number";
    else
        return "a string";
}

template <typename T>
std::string number(T value) {
    std::ostringstream out;
    out << value;
    return out.str();
}

// " in [a, b]", " >= a" or " <= b": a bound at the type's limit is no bound to the user, unless
// `value` breaks it.
template <typename T, typename V>
std::string rangeText(T minimum, T maximum, V value) {
    const bool low = minimum > std::numeric_limits<T>::lowest() || value < minimum;
    const bool high = maximum < std::numeric_limits<T>::max() || value > maximum;
    if (low && high)
        return " in [" + number(minimum) + ", " + number(maximum) + "]";
    return low ? " >= " + number(minimum) : high ? " <= " + number(maximum) : "";
}

std::string joined(const std::vector<std::string>& items) {
    std::string text;
    for (const std::string& item : items)
        text += (text.empty() ? "" : ", ") + item;
    return text;
}

}  // namespace

struct ScriptTable::Impl {
    std::shared_ptr<const ScriptSource> source;
    std::shared_ptr<const toml::table> root;  // keeps the document `table` points into alive
    const toml::table* table = nullptr;
    std::string path;
    ScriptLocation where;
    mutable std::vector<std::string> read;  // keys asked for, in order, without repeats

    std::string keyPath(const std::string& key) const {
        return path.empty() ? key : key.empty() ? path : path + "." + key;
    }
    // The key's node, or null; records the key as read either way.
    const toml::node* lookup(const std::string& key) const {
        if (std::find(read.begin(), read.end(), key) == read.end())
            read.push_back(key);
        return table->get(key);
    }
};

const std::string& ScriptTable::path() const {
    return impl_->path;
}

const std::string& ScriptTable::file() const {
    return impl_->source->file;
}

ScriptLocation ScriptTable::location() const {
    return impl_->where;
}

bool ScriptTable::has(const std::string& key) const {
    return impl_->table->contains(key);
}

bool ScriptTable::holdsString(const std::string& key) const {
    const toml::node* node = impl_->table->get(key);
    return node && node->is_string();
}

bool ScriptTable::holdsArray(const std::string& key) const {
    const toml::node* node = impl_->table->get(key);
    return node && node->is_array();
}

ScriptLocation ScriptTable::location(const std::string& key) const {
    const toml::node* node = impl_->table->get(key);
    return node ? locationOf(node->source()) : impl_->where;
}

ScriptError ScriptTable::error(const std::string& key, const std::string& message) const {
    return error(location(key), key, message);
}

ScriptError ScriptTable::error(ScriptLocation where, const std::string& key,
                               const std::string& message) const {
    return errorAt(*impl_->source, where, impl_->keyPath(key), message);
}

template <typename T>
std::optional<T> ScriptTable::find(const std::string& key) const {
    const toml::node* node = impl_->lookup(key);
    if (!node)
        return std::nullopt;
    if constexpr (std::is_same_v<T, bool>) {
        if (const auto* v = node->as_boolean())
            return v->get();
    } else if constexpr (std::is_integral_v<T>) {
        if (const auto* v = node->as_integer()) {
            const int64_t x = v->get();
            if (x < std::numeric_limits<T>::lowest() || x > std::numeric_limits<T>::max()) {
                throw error(key, "expected an integer" +
                                     rangeText(std::numeric_limits<T>::lowest(),
                                               std::numeric_limits<T>::max(), x) +
                                     ", got " + describe(*node));
            }
            return static_cast<T>(x);
        }
    } else if constexpr (std::is_floating_point_v<T>) {
        if (const auto* v = node->as_floating_point())
            return static_cast<T>(v->get());
        if (const auto* v = node->as_integer())
            return static_cast<T>(v->get());
    } else {
        if (const auto* v = node->as_string())
            return v->get();
    }
    throw error(key, "expected " + noun<T>() + ", got " + describe(*node));
}

template <typename T>
T ScriptTable::get(const std::string& key, T fallback, T minimum, T maximum) const {
    // Integers are read as int64_t, so that a value past the type's limits fails with the range
    // asked for rather than with the type's.
    using Read = std::conditional_t<std::is_integral_v<T>, int64_t, T>;
    const std::optional<Read> value = find<Read>(key);
    if (!value)
        return fallback;
    // Written so that NaN fails too.
    if (!(*value >= static_cast<Read>(minimum) && *value <= static_cast<Read>(maximum))) {
        throw error(key, "expected " + noun<T>() + rangeText(minimum, maximum, *value) + ", got " +
                             describe(*impl_->table->get(key)));
    }
    return static_cast<T>(*value);
}

template std::optional<bool> ScriptTable::find<bool>(const std::string&) const;
template std::optional<int> ScriptTable::find<int>(const std::string&) const;
template std::optional<int64_t> ScriptTable::find<int64_t>(const std::string&) const;
template std::optional<float> ScriptTable::find<float>(const std::string&) const;
template std::optional<double> ScriptTable::find<double>(const std::string&) const;
template std::optional<std::string> ScriptTable::find<std::string>(const std::string&) const;
template int ScriptTable::get<int>(const std::string&, int, int, int) const;
template int64_t ScriptTable::get<int64_t>(const std::string&, int64_t, int64_t, int64_t) const;
template float ScriptTable::get<float>(const std::string&, float, float, float) const;
template double ScriptTable::get<double>(const std::string&, double, double, double) const;

std::optional<std::vector<double>> ScriptTable::numbers(const std::string& key,
                                                        size_t count) const {
    const toml::node* node = impl_->lookup(key);
    if (!node)
        return std::nullopt;
    const toml::array* array = node->as_array();
    const std::string expected = "expected an array of " + std::to_string(count) + " numbers";
    if (!array || array->size() != count)
        throw error(key, expected + ", got " + describe(*node));
    std::vector<double> values;
    for (const toml::node& element : *array) {
        std::optional<double> value;
        if (const auto* v = element.as_floating_point())
            value = v->get();
        else if (const auto* v = element.as_integer())
            value = double(v->get());
        if (!value || !std::isfinite(*value))
            throw error(key, expected + ", got " + describe(*node));
        values.push_back(*value);
    }
    return values;
}

std::vector<std::pair<std::string, ScriptLocation>> ScriptTable::strings(
    const std::string& key) const {
    std::vector<std::pair<std::string, ScriptLocation>> result;
    const toml::node* node = impl_->lookup(key);
    if (!node)
        return result;
    if (const auto* v = node->as_string()) {
        result.emplace_back(v->get(), locationOf(node->source()));
        return result;
    }
    const toml::array* array = node->as_array();
    if (!array || array->empty())
        throw error(key, "expected a string or an array of strings, got " + describe(*node));
    for (const toml::node& element : *array) {
        const ScriptLocation where = locationOf(element.source());
        const auto* v = element.as_string();
        if (!v)
            throw error(where, key, "expected a string, got " + describe(element));
        result.emplace_back(v->get(), where);
    }
    return result;
}

std::vector<std::pair<std::string, std::string>> ScriptTable::entries() const {
    std::vector<std::pair<ScriptLocation, std::pair<std::string, std::string>>> found;
    for (const auto& [key, node] : *impl_->table) {
        found.push_back({locationOf(key.source()), {std::string(key.str()), describe(node)}});
    }
    std::sort(found.begin(), found.end(),
              [](const auto& a, const auto& b) { return before(a.first, b.first); });
    std::vector<std::pair<std::string, std::string>> result;
    for (auto& entry : found)
        result.push_back(std::move(entry.second));
    return result;
}

void ScriptTable::reportUnused() const {
    const toml::key* first = nullptr;
    for (const auto& [key, node] : *impl_->table) {
        const std::string name(key.str());
        if (std::find(impl_->read.begin(), impl_->read.end(), name) != impl_->read.end())
            continue;
        if (!first || before(locationOf(key.source()), locationOf(first->source())))
            first = &key;
    }
    if (first) {
        throw error(locationOf(first->source()), std::string(first->str()),
                    "unknown key; valid keys here: " + joined(impl_->read));
    }
}

namespace {

std::shared_ptr<const ScriptSource> readSource(const std::string& path, std::string& text) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec))
        throw UsageError(path + ": pass script not found");
    std::ifstream in(path, std::ios::binary);
    std::ostringstream content;
    content << in.rdbuf();
    if (!in)
        throw UsageError(path + ": cannot read the pass script");
    text = content.str();
    auto source = std::make_shared<ScriptSource>();
    source->file = path;
    std::istringstream lines(text);
    std::string line;
    while (std::getline(lines, line)) {
        if (!line.empty() && line.back() == '\r')
            line.pop_back();
        source->lines.push_back(line);
    }
    return source;
}

// A path the script gives, relative to the script's folder unless absolute.
std::string resolve(const std::string& script, const std::string& path) {
    return (fs::path(script).parent_path() / path).lexically_normal().string();
}

std::string readScene(const ScriptTable& top) {
    const std::optional<std::string> scene = top.find<std::string>("scene");
    if (!scene) {
        throw top.error("scene",
                        "missing: the glTF file to render, relative to the script, e.g. "
                        "scene = \"model.gltf\"");
    }
    const std::string path = resolve(top.file(), *scene);
    const std::string extension = fs::path(path).extension().string();
    if (extension != ".gltf" && extension != ".glb")
        throw top.error("scene", "expected a .gltf or .glb file, got \"" + *scene + "\"");
    std::error_code ec;
    if (!fs::is_regular_file(path, ec))
        throw top.error("scene", "file not found: " + path);
    return path;
}

// The environment image, resolved against the script's folder; it must exist.
std::optional<std::string> readEnvironmentFile(const ScriptTable& top) {
    const std::optional<std::string> given = top.find<std::string>("environment");
    if (!given)
        return std::nullopt;
    const std::string path = resolve(top.file(), *given);
    std::error_code ec;
    if (!fs::is_regular_file(path, ec))
        throw top.error("environment", "file not found: " + path);
    return path;
}

// A number that must be finite and > 0.
// A string that `parse` accepts (it throws std::invalid_argument with its reason otherwise),
// refused at its place in the script.
template <typename Parse>
std::optional<std::string> readChecked(const ScriptTable& top, const std::string& key,
                                       const Parse& parse) {
    const std::optional<std::string> text = top.find<std::string>(key);
    if (text) {
        try {
            parse(*text);
        } catch (const std::invalid_argument& e) {
            throw top.error(key, e.what());
        }
    }
    return text;
}

std::array<double, 3> toArray3(const std::vector<double>& v) {
    return {v[0], v[1], v[2]};
}

// One [[luminaire]] table: file and position required, the rest checked against their defaults.
ScriptLuminaire readLuminaire(const ScriptTable& t) {
    ScriptLuminaire luminaire;
    const std::optional<std::string> file = t.find<std::string>("file");
    if (!file)
        throw t.error("file", "missing: the luminaire's IES or LDT file");
    luminaire.file = resolve(t.file(), *file);
    std::error_code ec;
    if (!fs::is_regular_file(luminaire.file, ec))
        throw t.error("file", "file not found: " + luminaire.file);
    const std::optional<std::vector<double>> position = t.numbers("position", 3);
    if (!position)
        throw t.error("position", "missing: [x, y, z] in metres");
    luminaire.position = toArray3(*position);
    if (const std::optional<std::vector<double>> aim = t.numbers("aim", 3)) {
        if (!((*aim)[0] != 0.0 || (*aim)[1] != 0.0 || (*aim)[2] != 0.0))
            throw t.error("aim", "expected a direction, got [0, 0, 0]");
        luminaire.aim = toArray3(*aim);
    }
    if (const std::optional<std::vector<double>> c0 = t.numbers("c0", 3)) {
        const glm::dvec3 a(luminaire.aim[0], luminaire.aim[1], luminaire.aim[2]);
        const glm::dvec3 c((*c0)[0], (*c0)[1], (*c0)[2]);
        if (!(glm::length(glm::cross(a, c)) > 1e-6 * glm::length(a) * glm::length(c)))
            throw t.error("c0", "expected a direction across the aim, not along it");
        luminaire.c0 = toArray3(*c0);
    }
    luminaire.multiplier =
        t.get<float>("multiplier", 1.0f, 0.0f, std::numeric_limits<float>::max());
    if (const std::optional<std::vector<double>> color = t.numbers("color", 3)) {
        for (size_t i = 0; i < 3; ++i) {
            if (!((*color)[i] >= 0.0 && (*color)[i] <= 1.0))
                throw t.error("color", "expected three numbers in [0, 1]");
            luminaire.color[i] = float((*color)[i]);
        }
    }
    return luminaire;
}

// A medium's value per channel (in `unit`): a number for all three or an array of three, each
// finite and >= 0; zero when absent.
std::array<float, 3> readChannels(const ScriptTable& t, const std::string& key,
                                  const std::string& unit) {
    std::array<float, 3> values{};
    if (t.holdsArray(key)) {
        const std::vector<double> given = *t.numbers(key, 3);
        for (size_t i = 0; i < 3; ++i)
            values[i] = float(given[i]);
    } else {
        values.fill(t.get<float>(key, 0.0f));
    }
    for (const float value : values) {
        if (!(value >= 0.0f && std::isfinite(value)))
            throw t.error(key, "expected a number >= 0 (" + unit + ") or an array of three");
    }
    return values;
}

// The [[medium]] table: sigma_a and sigma_s (at least one of them not zero), g, emission, the
// box and the density file.
ScriptMedium readMedium(const ScriptTable& t) {
    ScriptMedium medium;
    medium.sigmaA = readChannels(t, "sigma_a", "per metre");
    medium.sigmaS = readChannels(t, "sigma_s", "per metre");
    // Emission is tied to absorption (core/medium.h): none where a channel absorbs nothing.
    medium.emission = readChannels(t, "emission", "cd/m²");
    for (size_t c = 0; c < 3; ++c) {
        if (medium.emission[c] > 0.0f && medium.sigmaA[c] == 0.0f)
            throw t.error("emission",
                          "a medium emits sigma_a x emission per metre: give sigma_a > 0 in "
                          "every channel that emits");
    }
    if (!t.has("sigma_a") && !t.has("sigma_s"))
        throw t.error("sigma_s", "missing: a medium needs sigma_a or sigma_s (per metre)");
    medium.g = t.get<float>("g", 0.0f);
    if (!(medium.g > -1.0f && medium.g < 1.0f))
        throw t.error("g", "expected a number in (-1, 1), got " + number(medium.g));
    if (const std::optional<std::vector<double>> box = t.numbers("box", 6)) {
        for (size_t axis = 0; axis < 3; ++axis) {
            if (!((*box)[axis] < (*box)[axis + 3]))
                throw t.error("box",
                              "expected [x0, y0, z0, x1, y1, z1] with x0 < x1, y0 < y1 "
                              "and z0 < z1");
        }
        medium.box =
            std::array<double, 6>{(*box)[0], (*box)[1], (*box)[2], (*box)[3], (*box)[4], (*box)[5]};
    }
    if (const std::optional<std::string> file = t.find<std::string>("density")) {
        const std::string path = resolve(t.file(), *file);
        if (std::filesystem::path(path).extension() != ".vdb")
            throw t.error("density", "expected an OpenVDB file (.vdb), got \"" + *file + "\"");
        if (!std::filesystem::is_regular_file(path))
            throw t.error("density", "file not found: " + path);
        medium.densityFile = path;
        medium.densityGrid = t.get<std::string>("density_grid", "");
    } else if (t.has("density_grid")) {
        throw t.error("density_grid", "names a grid of the density file, and there is none");
    }
    return medium;
}

// The portals, each checked at its place ("auto": the scene's openings, found when it is loaded;
// "none": no portal, not even found ones).
std::vector<std::string> readPortals(const ScriptTable& top) {
    std::vector<std::string> portals;
    for (const auto& [text, where] : top.strings("portals")) {
        try {
            if (text != "auto" && text != "none")
                parsePortalCorners(text);
        } catch (const std::invalid_argument& e) {
            throw top.error(where, "portals", e.what());
        }
        portals.push_back(text);
    }
    return portals;
}

std::optional<float> readPositive(const ScriptTable& top, const std::string& key) {
    const std::optional<float> value = top.find<float>(key);
    if (value && !(std::isfinite(*value) && *value > 0.0f))
        throw top.error(key, "expected a number > 0, got " + number(*value));
    return value;
}

// Outputs resolved against the script's folder, each checked as `-o` is (checkOutputPath).
std::vector<std::string> readOutputs(const ScriptTable& top) {
    std::vector<std::string> outputs;
    std::vector<ScriptLocation> places;
    for (const auto& [given, where] : top.strings("output")) {
        const std::string path = resolve(top.file(), given);
        for (size_t i = 0; i < outputs.size(); ++i) {
            if (outputs[i] == path) {
                throw top.error(where, "output",
                                "\"" + given + "\" is given twice (first at line " +
                                    std::to_string(places[i].line) + ")");
            }
        }
        try {
            checkOutputPath(path);
        } catch (const InputError& e) {
            throw top.error(where, "output", e.what());
        }
        outputs.push_back(path);
        places.push_back(where);
    }
    return outputs;
}

template <typename T>
std::optional<T> optionalIn(const ScriptTable& table, const std::string& key, T minimum,
                            T maximum) {
    if (!table.has(key)) {
        table.find<T>(key);  // records the key as read, so reportUnused() lists it
        return std::nullopt;
    }
    return table.get<T>(key, minimum, minimum, maximum);
}

}  // namespace

PassScript loadPassScript(const std::string& path) {
    std::string text;
    const std::shared_ptr<const ScriptSource> source = readSource(path, text);
    std::shared_ptr<toml::table> root;
    try {
        root = std::make_shared<toml::table>(toml::parse(text, path));
    } catch (const toml::parse_error& e) {
        throw errorAt(*source, locationOf(e.source()), "",
                      "TOML syntax error: " + std::string(e.description()));
    }

    const auto tableAt = [&](const toml::table* table, std::string keyPath, ScriptLocation where) {
        auto impl = std::make_shared<ScriptTable::Impl>();
        impl->source = source;
        impl->root = root;
        impl->table = table;
        impl->path = std::move(keyPath);
        impl->where = where;
        return ScriptTable(std::move(impl));
    };
    const ScriptTable top = tableAt(root.get(), "", ScriptLocation{});

    constexpr int kIntMax = std::numeric_limits<int>::max();
    PassScript script{
        .file = path,
        .scene = readScene(top),
        .sceneIndex = optionalIn(top, "scene_index", 0, kIntMax),
        .camera = top.find<std::string>("camera"),
        .width = optionalIn(top, "width", 1, kIntMax),
        .height = optionalIn(top, "height", 1, kIntMax),
        .spp = optionalIn(top, "spp", 1, kIntMax),
        .seed = optionalIn<int64_t>(top, "seed", 0, std::numeric_limits<uint32_t>::max()),
        .outputs = readOutputs(top),
        .environment = readEnvironmentFile(top),
        .environmentScale = readPositive(top, "environment_scale"),
        .environmentRotation = top.find<float>("environment_rotation"),
        .environmentIlluminance = readPositive(top, "environment_illuminance"),
        .sky = top.find<std::string>("sky"),
        .skyIlluminance = readPositive(top, "sky_illuminance"),
        .groundReflectance = optionalIn(top, "ground_reflectance", 0.0f, 1.0f),
        .site = readChecked(top, "site", parseSite),
        .time = readChecked(top, "time", parseIsoLocalTime),
        .north = top.find<float>("north"),
        .sunDirectNormal =
            optionalIn(top, "sun_direct_normal", 0.0f, std::numeric_limits<float>::max()),
        .portals = readPortals(top),
        .luminaires = {},
        .medium = {},
        .passes = {},
        .pipeline = top.find<std::string>("pipeline"),
        .topLevel = top};

    // [[pass]]: an array of tables, each a pass; its parameters are read by the registry. Or a
    // built-in pipeline, whose name the registry checks.
    const toml::node* passes = top.impl_->lookup("pass");
    if (passes && script.pipeline) {
        throw top.error("pipeline",
                        "give either a built-in `pipeline` or [[pass]] tables, not both");
    }
    if (!passes && !script.pipeline) {
        throw top.error("pass",
                        "missing: a script needs at least one [[pass]] table with its type, e.g. "
                        "[[pass]] type = \"path\", or a built-in pipeline, e.g. "
                        "pipeline = \"hybrid\"");
    }
    const toml::array* array = passes ? passes->as_array() : nullptr;
    if (passes && (!array || !array->is_array_of_tables())) {
        throw top.error("pass",
                        "expected [[pass]] tables (an array of tables), got " + describe(*passes));
    }
    for (size_t i = 0; array && i < array->size(); ++i) {
        const toml::table& table = *array->get(i)->as_table();
        ScriptTable parameters =
            tableAt(&table, "pass[" + std::to_string(i) + "]", locationOf(table.source()));
        script.passes.push_back(
            {parameters.find<std::string>("type").value_or(""), std::move(parameters)});
    }
    // [[luminaire]]: measured luminaires placed by the script.
    if (const toml::node* luminaires = top.impl_->lookup("luminaire")) {
        const toml::array* list = luminaires->as_array();
        if (!list || !list->is_array_of_tables()) {
            throw top.error(
                "luminaire",
                "expected [[luminaire]] tables (an array of tables), got " + describe(*luminaires));
        }
        for (size_t i = 0; i < list->size(); ++i) {
            const toml::table& table = *list->get(i)->as_table();
            const ScriptTable t =
                tableAt(&table, "luminaire[" + std::to_string(i) + "]", locationOf(table.source()));
            script.luminaires.push_back(readLuminaire(t));
            t.reportUnused();
        }
    }
    // [[medium]]: a participating medium, one for now.
    if (const toml::node* media = top.impl_->lookup("medium")) {
        const toml::array* list = media->as_array();
        if (!list || !list->is_array_of_tables()) {
            throw top.error("medium", "expected a [[medium]] table (an array of tables), got " +
                                          describe(*media));
        }
        for (size_t i = 0; i < list->size(); ++i) {
            const toml::table& table = *list->get(i)->as_table();
            const ScriptTable t =
                tableAt(&table, "medium[" + std::to_string(i) + "]", locationOf(table.source()));
            if (i > 0) {
                throw t.error(t.location(), "",
                              "a second [[medium]]: penumbra renders one medium for now");
            }
            script.medium = readMedium(t);
            t.reportUnused();
        }
    }
    top.reportUnused();
    return script;
}

}  // namespace penumbra
