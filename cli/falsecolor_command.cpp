// `penumbra falsecolor IMAGE -o OUT`: a rendered image's luminance (cd/m²) or illuminance (lux,
// its `illuminance` layer) in false colour with a legend, as Radiance's falsecolor shows a
// picture, for a lighting designer to read values off a render.
#include "cli/commands.h"
#include "core/errors.h"
#include "core/heatmap.h"
#include "core/image_io.h"
#include "core/image_luminance.h"
#include "core/tonemap.h"

#include <iostream>
#include <memory>

namespace penumbra::cli {

namespace {

struct FalseColourOptions {
    std::string input, output;
    std::string quantity = "luminance";
    std::string scale = "log";
    FalseColourSettings settings;
    bool quiet = false;
};

// The values to show, one channel: the beauty's luminance, or the illuminance layer's.
Image quantityOf(const Image& image, const FalseColourOptions& options) {
    if (options.quantity == "luminance") {
        if (image.channelIndex("R") < 0 || image.channelIndex("G") < 0 ||
            image.channelIndex("B") < 0) {
            throw InputError(options.input + ": no R, G and B channels to take the luminance of");
        }
        return luminanceImage(image);
    }
    if (image.channelIndex("illuminance.R") < 0) {
        throw InputError(options.input +
                         ": no illuminance layer (illuminance.R, .G, .B); render it with "
                         "`penumbra render ... --aov illuminance`");
    }
    return luminanceImage(image, "illuminance.");
}

void falseColour(FalseColourOptions& options) {
    checkOutputPath(options.output);
    if (options.quantity != "luminance" && options.quantity != "illuminance") {
        throw UsageError("--quantity " + options.quantity +
                         ": expected luminance (cd/m²) or illuminance (lux)");
    }
    if (options.scale != "log" && options.scale != "linear")
        throw UsageError("--scale " + options.scale + ": expected log or linear");
    FalseColourSettings& settings = options.settings;
    settings.scale = options.scale == "log" ? FalseColourScale::Log : FalseColourScale::Linear;
    const std::string unit = options.quantity == "luminance" ? "cd/m²" : "lux";
    settings.title = options.quantity + ", " + unit + " (" + options.scale + " scale)";

    const Image values = quantityOf(readImage(options.input), options);
    FalseColourLegend legend;
    Image picture;
    try {
        picture = renderFalseColour(values, settings, legend);
    } catch (const std::invalid_argument& e) {
        throw UsageError(std::string("falsecolor: ") + e.what());
    }
    ImageMetadata metadata;
    metadata.set("penumbra:falsecolor",
                 options.quantity + " (" + unit + "), " + options.scale + " scale, viridis");
    metadata.set("penumbra:falsecolor_low", float(legend.low));
    metadata.set("penumbra:falsecolor_high", float(legend.high));
    metadata.set("penumbra:source", options.input);
    writeImage(options.output, picture, {}, metadata, ToneMapping{});
    if (!options.quiet) {
        std::cerr << "penumbra: wrote " << options.output << ": " << options.quantity << " "
                  << legend.low << " to " << legend.high << " " << unit;
        if (legend.nonFinite > 0)
            std::cerr << ", " << legend.nonFinite << " non-finite pixels in magenta";
        if (!legend.labelled)
            std::cerr << " (no font found: the legend has no numbers)";
        std::cerr << "\n";
    }
}

}  // namespace

Command addFalseColourCommand(CLI::App& app) {
    auto* command = app.add_subcommand(
        "falsecolor",
        "Show a rendered image's luminance (cd/m²) or illuminance (lux) in false colour with a "
        "legend");
    auto options = std::make_shared<FalseColourOptions>();
    command->add_option("image", options->input, "The rendered image (.exr, linear cd/m²)")
        ->required();
    command->add_option("-o,--output", options->output, "The picture (.png, .exr, ...)")
        ->required();
    command
        ->add_option("--quantity", options->quantity,
                     "luminance (the image's Rec. 709 Y, cd/m²) or illuminance (its "
                     "`illuminance` layer, lux)")
        ->capture_default_str();
    command->add_option("--scale", options->scale, "log or linear")->capture_default_str();
    command
        ->add_option("--max", options->settings.maximum,
                     "Top of the scale (default: the largest value for log; a round number at "
                     "the 99th percentile for linear)")
        ->check(CLI::PositiveNumber);
    command
        ->add_option("--decades", options->settings.decades,
                     "Log scale: the decades below --max it spans")
        ->check(CLI::Range(1, 30))
        ->capture_default_str();
    command
        ->add_option("--divisions", options->settings.divisions, "Labelled steps along the legend")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    command->add_flag("-q,--quiet", options->quiet, "Print nothing but errors");
    return [options] { falseColour(*options); };
}

}  // namespace penumbra::cli
