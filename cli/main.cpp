// penumbra: command-line entry point. Exit status 0 on success, 2 on bad input or usage,
// 1 on an internal failure or a failed `penumbra diff` check (CONTRIBUTING.md, "Errors and exit
// codes").
#include "cli/commands.h"
#include "core/errors.h"
#include "core/version.h"

#include <CLI/CLI.hpp>

#include <exception>
#include <iostream>

int main(int argc, char** argv) {
    CLI::App app{
        "penumbra: a hybrid multipass global illumination renderer for glTF 2.0 scenes, "
        "in photometric units"};
    app.set_version_flag("--version", std::string("penumbra ") + penumbra::kVersion);
    app.require_subcommand(1);

    penumbra::cli::Command render = penumbra::cli::addRenderCommand(app);
    penumbra::cli::Command info = penumbra::cli::addInfoCommand(app);
    penumbra::cli::Command bake = penumbra::cli::addBakeCommand(app);
    penumbra::cli::Command plan = penumbra::cli::addPlanCommand(app);
    penumbra::cli::Command illuminance = penumbra::cli::addIlluminanceCommand(app);
    penumbra::cli::Command falsecolor = penumbra::cli::addFalseColourCommand(app);
    penumbra::cli::StatusCommand diff = penumbra::cli::addDiffCommand(app);
    penumbra::cli::StatusCommand bench = penumbra::cli::addBenchCommand(app);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // Help and version requests are "errors" with status 0 in CLI11.
        return app.exit(e) == 0 ? 0 : 2;
    }

    try {
        if (app.got_subcommand("render"))
            render();
        if (app.got_subcommand("info"))
            info();
        if (app.got_subcommand("bake"))
            bake();
        if (app.got_subcommand("plan"))
            plan();
        if (app.got_subcommand("illuminance"))
            illuminance();
        if (app.got_subcommand("falsecolor"))
            falsecolor();
        if (app.got_subcommand("diff"))
            return diff();
        if (app.got_subcommand("bench"))
            return bench();
    } catch (const penumbra::InputError& e) {
        std::cerr << "penumbra: error: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "penumbra: internal error: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
