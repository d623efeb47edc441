#include "core/image_io.h"

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace penumbra {
namespace fs = std::filesystem;
namespace {

constexpr const char* kSupportedExtensions = ".exr, .png, .jpg, .jpeg, .tif, .tiff";

std::string lowerExtension(const fs::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

bool isFloatFormat(const std::string& ext) {
    return ext == ".exr";
}

bool isEightBitFormat(const std::string& ext) {
    return ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".tif" || ext == ".tiff";
}

// "<dir>/<stem>.tmp-<pid><ext>": same directory, so the final rename stays on one file system
// (and is atomic there); same extension, so OpenImageIO picks the same format.
fs::path temporaryPath(const fs::path& path) {
    return path.parent_path() / (path.stem().string() + ".tmp-" + std::to_string(::getpid()) +
                                 path.extension().string());
}

// Removes the temporary file unless the write was committed.
class TemporaryFile {
  public:
    explicit TemporaryFile(fs::path path) : path_(std::move(path)) {}
    ~TemporaryFile() {
        if (!committed_) {
            std::error_code ignored;
            fs::remove(path_, ignored);
        }
    }
    TemporaryFile(const TemporaryFile&) = delete;
    TemporaryFile& operator=(const TemporaryFile&) = delete;

    const fs::path& path() const { return path_; }
    void commit() { committed_ = true; }

  private:
    fs::path path_;
    bool committed_ = false;
};

float finiteOrZero(float v, size_t& replaced) {
    if (std::isfinite(v)) {
        return v;
    }
    ++replaced;
    return 0.0f;
}

// Scene-linear 32-bit float: R, G, B, then every layer's channels as "<layer>.<channel>",
// interleaved per pixel.
OIIO::ImageSpec floatPixels(const Image& beauty, const std::vector<NamedLayer>& aovs,
                            std::vector<float>& pixels, size_t& replaced) {
    std::vector<std::string> names = {"R", "G", "B"};
    for (const NamedLayer& layer : aovs) {
        if (layer.image.width() != beauty.width() || layer.image.height() != beauty.height()) {
            throw std::invalid_argument("writeImage: AOV \"" + layer.name +
                                        "\" differs in size from the beauty");
        }
        for (const std::string& channel : layer.image.channelNames()) {
            names.push_back(layer.name + "." + channel);
        }
    }
    const size_t pixelCount = size_t(beauty.width()) * size_t(beauty.height());
    pixels.reserve(pixelCount * names.size());
    for (size_t i = 0; i < pixelCount; ++i) {
        for (size_t c = 0; c < 3; ++c) {
            pixels.push_back(finiteOrZero(beauty.pixels()[i * 3 + c], replaced));
        }
        for (const NamedLayer& layer : aovs) {
            const size_t n = size_t(layer.image.channels());
            for (size_t c = 0; c < n; ++c) {
                pixels.push_back(finiteOrZero(layer.image.pixels()[i * n + c], replaced));
            }
        }
    }
    OIIO::ImageSpec spec(beauty.width(), beauty.height(), int(names.size()), OIIO::TypeDesc::FLOAT);
    spec.channelnames = std::move(names);
    spec.attribute("compression", "zip");  // lossless for float data
    return spec;
}

// Display-referred 8-bit sRGB of the beauty: exposure, tone mapping, sRGB encoding.
OIIO::ImageSpec eightBitPixels(const Image& beauty, const ToneMapping& toneMapping,
                               std::vector<uint8_t>& pixels, size_t& replaced) {
    Image linear(beauty.width(), beauty.height(), {"R", "G", "B"});
    const std::span<float> values = linear.pixels();
    for (size_t i = 0; i < values.size(); ++i)
        values[i] = finiteOrZero(beauty.pixels()[i], replaced);
    const Image display = toneMapImage(linear, toneMapping);
    pixels.reserve(values.size());
    for (const float v : display.pixels())
        pixels.push_back(encodeSrgb8(v));
    OIIO::ImageSpec spec(beauty.width(), beauty.height(), 3, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:ColorSpace", "sRGB");
    return spec;
}

// EXR headers keep typed attributes. The 8-bit writers keep only strings (PNG as text chunks)
// and silently drop numbers, so there every value is written as text.
void addMetadata(OIIO::ImageSpec& spec, const ImageMetadata& metadata, bool typed) {
    for (const auto& [key, value] : metadata.attributes()) {
        if (const auto* s = std::get_if<std::string>(&value)) {
            spec.attribute(key, *s);
        } else if (const auto* i = std::get_if<int>(&value)) {
            if (typed) {
                spec.attribute(key, *i);
            } else {
                spec.attribute(key, std::to_string(*i));
            }
        } else {
            const float f = std::get<float>(value);
            if (typed) {
                spec.attribute(key, f);
            } else {
                char text[32];
                std::snprintf(text, sizeof text, "%.9g", double(f));  // round-trips a float
                spec.attribute(key, text);
            }
        }
    }
}

}  // namespace

void ImageMetadata::set(const std::string& key, Value value) {
    for (auto& [k, v] : attributes_) {
        if (k == key) {
            v = std::move(value);
            return;
        }
    }
    attributes_.emplace_back(key, std::move(value));
}

const ImageMetadata::Value* ImageMetadata::find(const std::string& key) const {
    for (const auto& [k, v] : attributes_) {
        if (k == key) {
            return &v;
        }
    }
    return nullptr;
}

void checkOutputPath(const std::string& path) {
    const fs::path p(path);
    const std::string ext = lowerExtension(p);
    if (p.stem().empty() || (!isFloatFormat(ext) && !isEightBitFormat(ext))) {
        throw ImageIoError(path, "unsupported image format \"" + ext +
                                     "\" (supported: " + kSupportedExtensions + ")");
    }
    if (!OIIO::ImageOutput::create(ext.substr(1))) {
        throw ImageIoError(path, "this OpenImageIO build cannot write " + ext + " files");
    }
    const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) {
        throw ImageIoError(path, "directory \"" + dir.string() + "\" does not exist");
    }
    if (::access(dir.c_str(), W_OK | X_OK) != 0) {
        throw ImageIoError(path, "directory \"" + dir.string() + "\" is not writable");
    }
}

size_t writeImage(const std::string& path, const Image& beauty, const std::vector<NamedLayer>& aovs,
                  const ImageMetadata& metadata, const ToneMapping& toneMapping) {
    checkOutputPath(path);
    if (beauty.channels() != 3) {
        throw std::invalid_argument("writeImage: beauty is not RGB");
    }
    const bool linear = isFloatFormat(lowerExtension(path));
    size_t replaced = 0;
    std::vector<float> floats;
    std::vector<uint8_t> bytes;
    OIIO::ImageSpec spec = linear ? floatPixels(beauty, aovs, floats, replaced)
                                  : eightBitPixels(beauty, toneMapping, bytes, replaced);
    addMetadata(spec, metadata, linear);

    TemporaryFile temporary(temporaryPath(path));
    {
        // Scoped so that the file is closed before it is renamed or removed.
        auto out = OIIO::ImageOutput::create(temporary.path().string());
        if (!out) {
            throw ImageIoError(path, "cannot create a writer: " + OIIO::geterror());
        }
        const void* data = linear ? static_cast<const void*>(floats.data())
                                  : static_cast<const void*>(bytes.data());
        if (!out->open(temporary.path().string(), spec) || !out->write_image(spec.format, data) ||
            !out->close()) {
            throw ImageIoError(path, "cannot write: " + out->geterror());
        }
    }
    std::error_code ec;
    fs::rename(temporary.path(), path, ec);
    if (ec) {
        throw ImageIoError(path, "cannot replace the file: " + ec.message());
    }
    temporary.commit();
    return replaced;
}

Image readImage(const std::string& path, ImageMetadata* metadata) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        throw ImageIoError(path, "cannot read image: " + OIIO::geterror());
    }
    const OIIO::ImageSpec& spec = in->spec();
    std::vector<std::string> names = spec.channelnames;
    for (int c = int(names.size()); c < spec.nchannels; ++c) {
        names.push_back("channel" + std::to_string(c));
    }
    Image image(spec.width, spec.height, std::move(names));
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels().data())) {
        throw ImageIoError(path, "cannot read image: " + in->geterror());
    }
    if (metadata) {
        for (const OIIO::ParamValue& attribute : spec.extra_attribs) {
            const std::string key = attribute.name().string();
            const OIIO::TypeDesc t = attribute.type();
            if (t == OIIO::TypeInt) {
                metadata->set(key, attribute.get_int());
            } else if (t == OIIO::TypeFloat) {
                metadata->set(key, attribute.get_float());
            } else {
                metadata->set(key, attribute.get_string());
            }
        }
    }
    in->close();
    return image;
}

}  // namespace penumbra
