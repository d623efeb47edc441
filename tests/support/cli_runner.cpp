#include "tests/support/cli_runner.h"

#include "core/image_io.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <sys/wait.h>
#include <cstdio>

namespace penumbra::test {

CliResult runPenumbra(const std::string& arguments) {
    const std::string command =
        std::string(PENUMBRA_BINARY_DIR) + "/bin/penumbra " + arguments + " 2>&1";
    CliResult result;
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe)
        return result;
    char buffer[4096];
    size_t n;
    while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0)
        result.output.append(buffer, n);
    const int status = pclose(pipe);
    result.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return result;
}

TempDir::TempDir(const std::string& name)
    : path_(std::filesystem::temp_directory_path() /
            ("penumbra-" + name + "-" + std::to_string(getpid()))) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
}

TempDir::~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
}

double regionMean(const Image& image, int channel, int x0, int y0, int x1, int y1) {
    double sum = 0.0;
    for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x)
            sum += image.at(x, y, channel);
    }
    return sum / (static_cast<double>(x1 - x0) * (y1 - y0));
}

Image renderImage(const std::string& input, const std::string& output, const std::string& options,
                  CliResult* out) {
    const CliResult result = runPenumbra("render " + input + " -o " + output + " " + options);
    EXPECT_EQ(result.status, 0) << result.output;
    if (out)
        *out = result;
    return readImage(output);
}

double luminanceMean(const Image& image) {
    const int w = image.width(), h = image.height();
    return 0.2126 * regionMean(image, 0, 0, 0, w, h) + 0.7152 * regionMean(image, 1, 0, 0, w, h) +
           0.0722 * regionMean(image, 2, 0, 0, w, h);
}

}  // namespace penumbra::test
