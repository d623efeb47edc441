// A pass's script parameters, each key written once: a pass lists its keys in one function
// template over a key visitor, which ParameterReader walks to read them from a [[pass]] table and
// ParameterPrinter walks to print them for the plan and the image's metadata. The default of a key
// is the value its field holds before reading. (Tungsten pairs each settings' fromJson with a
// toJson; pbrt-v4 reads with ParameterDictionary and prints by hand: here one list does both, so
// a key cannot be read under one name and printed under another, or printed with a stale
// default.)
//
//     template <typename Settings, typename Keys>   // Settings: const when printing
//     void visitKeys(Settings& s, Keys& keys) {
//         keys("epsilon", s.epsilon);
//         keys("max_iterations", s.maxIterations, 1, 1000);
//         keys.choice("iteration", s.iteration, kIterationNames, "iteration");
//         keys.orAuto("final_gather", s.finalGatherRays, kAutoFinalGather, 0, 65536);
//     }
#pragma once

#include "core/errors.h"
#include "core/stats.h"
#include "passes/pass_script.h"

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace penumbra {

// Command-line values that replace a pass parameter in every pass of a script that has it
// (docs/pass-scripts.md, "Precedence"); absent = the script's value.
struct PassOverrides {
    std::optional<int> maxDepth;  // --max-depth: `max_depth` of the path passes
};

// The largest max_depth and max_specular_depth a script takes, as --max-depth.
constexpr int kMaxDepthLimit = 1 << 20;

// The words a key with named values takes, each with its value, in the order messages list them.
template <typename E>
using NamedValues = std::vector<std::pair<std::string, E>>;

// "a, b, c"
std::string joinedNames(const std::vector<std::string>& names);

// Reads each visited key from a [[pass]] table into its field: ScriptTable's typed getters, so a
// value of the wrong type or out of range is refused at its place, and every key is recorded as
// read for ScriptTable::reportUnused().
class ParameterReader {
  public:
    explicit ParameterReader(const ScriptTable& table) : table_(table) {}

    template <typename T>
    void operator()(const char* key, T& value) {
        if constexpr (std::is_same_v<T, uint32_t>)
            value = static_cast<uint32_t>(table_.get<int64_t>(key, value, 0, UINT32_MAX));
        else
            value = table_.get<T>(key, value);
    }
    template <typename T>
    void operator()(const char* key, T& value, T minimum, T maximum) {
        value = table_.get<T>(key, value, minimum, maximum);
    }
    // A key that takes one of `names`; an unknown word is refused as "unknown <what> 'word';
    // valid: ...".
    template <typename E>
    void choice(const char* key, E& value, const NamedValues<E>& names,
                const std::string& what = "value") {
        std::string current;
        for (const auto& [name, named] : names) {
            if (named == value)
                current = name;
        }
        const std::string word = table_.get<std::string>(key, current);
        std::vector<std::string> valid;
        for (const auto& [name, named] : names) {
            if (name == word) {
                value = named;
                return;
            }
            valid.push_back(name);
        }
        throw table_.error(key,
                           "unknown " + what + " '" + word + "'; valid: " + joinedNames(valid));
    }
    // A number in [minimum, maximum], or the word "auto", which stores `automatic`.
    template <typename T>
    void orAuto(const char* key, T& value, T automatic,
                T minimum = std::numeric_limits<T>::lowest(),
                T maximum = std::numeric_limits<T>::max()) {
        orWord(key, value, "auto", automatic, minimum, maximum);
    }
    // A number in [minimum, maximum], or `word`, which stores `wordValue`.
    template <typename T>
    void orWord(const char* key, T& value, const std::string& word, T wordValue, T minimum,
                T maximum) {
        if (!table_.holdsString(key)) {
            value = table_.get<T>(key, value, minimum, maximum);
            return;
        }
        const std::string given = table_.get<std::string>(key, word);
        if (given != word) {
            throw table_.error(key, "unknown value '" + given + "'; valid: " +
                                        describeRange(minimum, maximum) + ", " + word);
        }
        value = wordValue;
    }

    // Returns make(), which builds the pass from the values read: its constructor checks them by
    // the rules every caller of the solver or map obeys and throws UsageError "PREFIXkey: what",
    // whose message this moves to the key's place in the script.
    template <typename Make>
    auto construct(const std::string& prefix, Make&& make) const {
        try {
            return make();
        } catch (const UsageError& e) {
            throw atKey(prefix, e);
        }
    }

  private:
    // "an integer in [0, 65536]"; "a number" for a real (the getter names its range).
    template <typename T>
    static std::string describeRange(T minimum, T maximum) {
        if constexpr (std::is_integral_v<T>)
            return "an integer in [" + std::to_string(minimum) + ", " + std::to_string(maximum) +
                   "]";
        else
            return "a number";
    }
    ScriptError atKey(const std::string& prefix, const UsageError& e) const;

    const ScriptTable& table_;
};

// Prints each visited key with its value as the plan and the metadata show it: numbers with four
// significant digits (integers whole), booleans as true or false, named values by their word,
// an automatic value as "auto".
class ParameterPrinter {
  public:
    template <typename T>
    void operator()(const char* key, const T& value) {
        stats_.push_back({key, format(value)});
    }
    template <typename T>
    void operator()(const char* key, const T& value, T, T) {
        stats_.push_back({key, format(value)});
    }
    template <typename E>
    void choice(const char* key, const E& value, const NamedValues<E>& names,
                const std::string& = "") {
        for (const auto& [name, named] : names) {
            if (named == value)
                stats_.push_back({key, name});
        }
    }
    template <typename T>
    void orAuto(const char* key, const T& value, T automatic, T = {}, T = {}) {
        stats_.push_back({key, value == automatic ? std::string("auto") : format(value)});
    }
    template <typename T>
    void orWord(const char* key, const T& value, const std::string& word, T wordValue, T, T) {
        stats_.push_back({key, value == wordValue ? word : format(value)});
    }

    const PassStats& stats() const { return stats_; }

  private:
    template <typename T>
    static std::string format(const T& value) {
        if constexpr (std::is_same_v<T, bool>)
            return value ? "true" : "false";
        else if constexpr (std::is_same_v<T, std::string>)
            return value;
        else if constexpr (std::is_floating_point_v<T>)
            return formatStat(value);
        else
            return std::to_string(value);
    }

    PassStats stats_;
};

}  // namespace penumbra
