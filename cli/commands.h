// The penumbra subcommands. Each registers its options on the command-line parser and returns a
// function that runs it after parsing; errors are thrown (core/errors.h) and turned into exit
// statuses by main().
#pragma once

#include <CLI/CLI.hpp>

#include <functional>

namespace penumbra::cli {

using Command = std::function<void()>;

Command addRenderCommand(CLI::App& app);
Command addInfoCommand(CLI::App& app);

}  // namespace penumbra::cli
