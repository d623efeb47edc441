// The penumbra subcommands. Each registers its options on the command-line parser and returns a
// function that runs it after parsing; errors are thrown (core/errors.h) and turned into exit
// statuses by main().
#pragma once

#include <CLI/CLI.hpp>

#include <cstdlib>
#include <functional>
#include <string>

namespace penumbra::cli {

using Command = std::function<void()>;
// A command whose outcome is an exit status of its own: 0, or 1 for a failed check (`penumbra
// diff --fail-above`), which is neither bad input nor an internal error.
using StatusCommand = std::function<int()>;

// Accepts numbers >= minimum. CLI11's PositiveNumber refuses "--spp 0" with "Value 0 not in range
// 0.000000 to 1797693134862315708...", which names the wrong bound; this says "--spp: 0 is less
// than 1". Non-numbers pass through to CLI11's own conversion error.
inline CLI::Validator atLeast(int minimum) {
    const std::string bound = std::to_string(minimum);
    return CLI::Validator(
        [minimum, bound](std::string& text) -> std::string {
            char* end = nullptr;
            const double value = std::strtod(text.c_str(), &end);
            if (end == text.c_str() || *end != '\0' || !(value < minimum))
                return "";
            return text + " is less than " + bound;
        },
        minimum == 0   ? "NONNEGATIVE"
        : minimum == 1 ? "POSITIVE"
                       : ">=" + bound);
}

// The --pipeline option of render and plan: a built-in preset by name, listed in the help.
void addPipelineOption(CLI::App& command, std::string& pipeline);

Command addRenderCommand(CLI::App& app);
Command addInfoCommand(CLI::App& app);
Command addBakeCommand(CLI::App& app);
Command addPlanCommand(CLI::App& app);
Command addIlluminanceCommand(CLI::App& app);
Command addFalseColourCommand(CLI::App& app);
StatusCommand addDiffCommand(CLI::App& app);
StatusCommand addBenchCommand(CLI::App& app);

}  // namespace penumbra::cli
