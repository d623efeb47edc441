// Runs the penumbra command-line program from tests, as a user would.
#pragma once

#include "core/image.h"

#include <filesystem>
#include <string>

namespace penumbra::test {

struct CliResult {
    int status = -1;     // exit status
    std::string output;  // stdout and stderr together
};

// Runs build/bin/penumbra with the given arguments (a shell-quoted string).
CliResult runPenumbra(const std::string& arguments);

// Runs `penumbra render INPUT -o OUTPUT OPTIONS`, expects (gtest) exit status 0, and returns the
// image written; the run's status and output go to `out` if given.
Image renderImage(const std::string& input, const std::string& output, const std::string& options,
                  CliResult* out = nullptr);

// A fresh, empty directory for one test's files, removed when the object goes away.
class TempDir {
  public:
    explicit TempDir(const std::string& name);
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    std::string file(const std::string& name) const { return (path_ / name).string(); }

  private:
    std::filesystem::path path_;
};

// Mean of one channel over a rectangle of pixels [x0, x1) x [y0, y1).
double regionMean(const Image& image, int channel, int x0, int y0, int x1, int y1);
// Mean luminance (Rec. 709 weights, as core/math.h's luminance()) of the whole image.
double luminanceMean(const Image& image);

}  // namespace penumbra::test
