// Image files, through OpenImageIO (the only module that includes it).
//
// The file extension picks the format:
//   .exr                      32-bit float, scene-linear: the beauty as R, G, B and every AOV
//                             layer as channels "<layer>.<channel>" ("albedo.R", "depth.Z"),
//                             with the metadata as header attributes;
//   .png .jpg .jpeg .tif .tiff  8-bit sRGB of the beauty alone, after exposure and tone mapping
//                             (core/tonemap.h); AOV layers are not written to these.
#pragma once

#include "core/errors.h"
#include "core/image.h"
#include "core/tonemap.h"

#include <cstddef>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace penumbra {

// An image file that cannot be written or read; the message starts with the path.
class ImageIoError : public InputError {
  public:
    ImageIoError(const std::string& path, const std::string& what)
        : InputError(path + ": " + what) {}
};

// An AOV layer to write next to the beauty; the image's channel names become the suffixes.
struct NamedLayer {
    std::string name;
    Image image;
};

// Attributes stored in the file header: typed in EXR; as text in PNG (tEXt chunks), and
// wherever else the format allows (TIFF and JPEG keep few or none). Keys are used as given, e.g.
// "penumbra:spp", "penumbra:seconds", "penumbra:pipeline", "penumbra:seed", "penumbra:version".
class ImageMetadata {
  public:
    using Value = std::variant<std::string, int, float>;

    // Adds the attribute, or replaces the value of an existing one with that key.
    void set(const std::string& key, Value value);
    // The value stored under `key`, or nullptr.
    const Value* find(const std::string& key) const;
    // In insertion order.
    const std::vector<std::pair<std::string, Value>>& attributes() const { return attributes_; }

  private:
    std::vector<std::pair<std::string, Value>> attributes_;
};

// Throws ImageIoError unless `path` has a supported extension (case-insensitive) and its
// directory exists and is writable. The command line calls it before rendering so that a bad
// output path fails in a second, not after an hour.
void checkOutputPath(const std::string& path);

// Writes the beauty (channels R, G, B) and, for EXR, the AOV layers (same size as the beauty)
// with `metadata` to `path`. The file is first written to "<stem>.tmp-<pid><ext>" in the same
// directory and renamed over `path` only when complete: on any failure the temporary is removed,
// `path` is left as it was, and ImageIoError is thrown. Non-finite values are written as 0;
// returns how many were replaced (0 when the tracer did its job).
size_t writeImage(const std::string& path, const Image& beauty, const std::vector<NamedLayer>& aovs,
                  const ImageMetadata& metadata, const ToneMapping& toneMapping);

// Reads the first subimage of any format OpenImageIO reads, as float (8-bit formats scaled to
// [0, 1], not linearised), with the file's channel names, and, if `metadata` is not null, its
// string, int and float attributes (others as strings). Throws ImageIoError when unreadable.
Image readImage(const std::string& path, ImageMetadata* metadata = nullptr);

}  // namespace penumbra
