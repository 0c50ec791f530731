// OpenEXR files through OpenEXR's own library (image_formats.h): what crex writes, and the
// float or half RGB (or one-channel) images a reference or a compared render usually is.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfChromaticitiesAttribute.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfMatrixAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStdIO.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTestFile.h>
#include <OpenEXR/openexr.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "base/render_text.h"
#include "runtime/io/image_formats.h"

namespace crex::image_formats {
namespace {

void insert_attribute(Imf::Header& header, const std::string& name, const AttributeValue& value) {
    if (const auto* s = std::get_if<std::string>(&value)) header.insert(name, Imf::StringAttribute(*s));
    else if (const auto* i = std::get_if<int>(&value)) header.insert(name, Imf::IntAttribute(*i));
    else if (const auto* f = std::get_if<float>(&value)) header.insert(name, Imf::FloatAttribute(*f));
    else if (const auto* m = std::get_if<Matrix44>(&value)) {
        Imath::M44f matrix;
        for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 4; ++c) matrix[r][c] = m->m[static_cast<size_t>(4 * r + c)];
        header.insert(name, Imf::M44fAttribute(matrix));
    } else if (const auto* x = std::get_if<Chromaticities>(&value)) {
        const auto& v = x->xy;
        header.insert(name, Imf::ChromaticitiesAttribute(Imf::Chromaticities(Imath::V2f(v[0], v[1]), Imath::V2f(v[2], v[3]),
                                                                             Imath::V2f(v[4], v[5]), Imath::V2f(v[6], v[7]))));
    }
}

// The value of a header attribute as image_io.h types them; other types as their text.
AttributeValue attribute_value(const Imf::Attribute& a) {
    if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&a)) return s->value();
    if (const auto* i = dynamic_cast<const Imf::IntAttribute*>(&a)) return i->value();
    if (const auto* f = dynamic_cast<const Imf::FloatAttribute*>(&a)) return f->value();
    if (const auto* d = dynamic_cast<const Imf::DoubleAttribute*>(&a)) return fmt::format("{:.17g}", d->value());
    if (const auto* m = dynamic_cast<const Imf::M44fAttribute*>(&a)) {
        Matrix44 out;
        for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 4; ++c) out.m[static_cast<size_t>(4 * r + c)] = m->value()[r][c];
        return out;
    }
    if (const auto* c = dynamic_cast<const Imf::ChromaticitiesAttribute*>(&a)) {
        const Imf::Chromaticities& v = c->value();
        return Chromaticities{{v.red.x, v.red.y, v.green.x, v.green.y, v.blue.x, v.blue.y, v.white.x, v.white.y}};
    }
    return std::string("(") + a.typeName() + ")";
}

bool is_float_channel(const Imf::Channel* c) {
    return c && (c->type == Imf::FLOAT || c->type == Imf::HALF) && c->xSampling == 1 && c->ySampling == 1;
}

// The file's size, or false where its layout is one left to OpenImageIO (a data window that
// is not the display window at the origin) or its size is out of bounds (`error` says so).
bool plain_window(const Imf::Header& header, const std::string& path, int& width, int& height, std::string& error) {
    const Imath::Box2i data = header.dataWindow(), display = header.displayWindow();
    if (data.min != display.min || data.max != display.max || data.min.x != 0 || data.min.y != 0) return false;
    const int64_t w = int64_t{data.max.x} + 1, h = int64_t{data.max.y} + 1;
    // More than kMaxReadPixels is refused before anything is allocated (its RGB then takes at
    // most 400 MB): a hostile 30-byte file can claim a data window of 2^31 x 2^31.
    if (w <= 0 || h <= 0 || w * h > kMaxReadPixels) {
        error = "cannot read '" + path + "': " + beyond_read_limit(w, h);
        return true;
    }
    // A channel holds at least 2 bytes a pixel (half), and no compression but DWA packs more
    // than deflate (RLE, PIZ and B44 pack less; DWA's DC values of a flat block go through zlib
    // after the DCT, so it is not bounded here): a header claiming more pixels than its file can
    // hold is refused before their memory is taken (a 400-byte file may claim 2^25, 400 MB of RGB).
    const Imf::Compression compression = header.compression();
    const bool bounded = compression != Imf::DWAA_COMPRESSION && compression != Imf::DWAB_COMPRESSION;
    std::error_code ec;
    const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
    if (bounded && !ec) {
        if (std::string why = claim_beyond_file(2.0 * static_cast<double>(w * h), bytes, w, h, kDeflatePacking); !why.empty()) {
            error = "cannot read '" + path + "': " + why;
            return true;
        }
    }
    width = static_cast<int>(w), height = static_cast<int>(h);
    return true;
}

// Reads the named channels (3, repeats allowed: one channel as grey) into interleaved RGB,
// straight into `rgb` (no buffer beside it).
void read_channels(Imf::InputFile& in, const std::array<std::string, 3>& names, int width, int height, std::vector<float>& rgb) {
    const size_t np = static_cast<size_t>(width) * static_cast<size_t>(height);
    rgb.assign(3 * np, 0.0f);
    Imf::FrameBuffer frame;
    std::array<size_t, 3> from = {0, 1, 2};  // the channel of rgb each one is read into
    for (size_t c = 0; c < 3; ++c) {
        for (size_t k = 0; k < c; ++k)
            if (names[k] == names[c]) from[c] = from[k];
        if (from[c] == c)
            frame.insert(names[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(rgb.data() + c), 3 * sizeof(float),
                                              3 * sizeof(float) * static_cast<size_t>(width)));
    }
    in.setFrameBuffer(frame);
    in.readPixels(0, height - 1);
    for (size_t c = 0; c < 3; ++c)
        if (from[c] != c)
            for (size_t p = 0; p < np; ++p) rgb[3 * p + c] = rgb[3 * p + from[c]];
}

std::string failed(const std::string& path, const std::exception& e) { return "cannot read '" + path + "': " + e.what(); }

// The sizes OpenEXR's C++ library reads the fixed-size attribute types at, whatever their
// declared size says (ImfAttribute.h's typed attributes).
const std::map<std::string, uint32_t>& fixed_sizes() {
    static const std::map<std::string, uint32_t> sizes = {
        {"box2i", 16}, {"box2f", 16}, {"chromaticities", 32}, {"compression", 1}, {"deepImageState", 1}, {"double", 8},
        {"envmap", 1}, {"float", 4}, {"int", 4}, {"keycode", 28}, {"lineOrder", 1}, {"m33f", 36}, {"m33d", 72},
        {"m44f", 64}, {"m44d", 128}, {"rational", 8}, {"tiledesc", 9}, {"timecode", 8}, {"v2i", 8}, {"v2f", 8},
        {"v2d", 16}, {"v3i", 12}, {"v3f", 12}, {"v3d", 24}};
    return sizes;
}

uint32_t le32(const unsigned char* p) { return p[0] | p[1] << 8 | p[2] << 16 | static_cast<uint32_t>(p[3]) << 24; }

// Why OpenEXR's C++ library would read a header other than its declared sizes say, else "".
// OpenEXR's C core (check_header()) checks each attribute by its declared size; the C++ library
// reads a channel list to its terminating null and a fixed-size type at its own size whatever
// was declared, and allocates a string vector's strings and a preview's pixels by what they
// claim inside. Where the two disagree the C++ library reads the rest of the header out of
// step, as attributes the core never saw: a fuzzed 347-byte file whose channel list ran past
// its size gave the C++ library a string claiming 1 GB, which it allocated (2 GB and 11 s to
// fail) after the core had found eight sound attributes. So every attribute must fit in what
// the file has left and its value must take exactly its declared size.
std::string header_out_of_step(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return "";  // OpenEXR says why
    in.seekg(0, std::ios::end);
    const uint64_t file_size = static_cast<uint64_t>(in.tellg());
    in.seekg(0);
    unsigned char head[8];
    if (!in.read(reinterpret_cast<char*>(head), 8) || le32(head) != 20000630u) return "";  // not an EXR: OpenEXR says so
    const uint32_t flags = le32(head + 4);
    const bool multipart = flags & 0x1000u;
    const size_t max_name = (flags & 0x400u) ? 255 : 31;
    // A null-terminated name of at most max_name characters; false where there is none.
    auto name_at = [&](std::string& out) {
        out.clear();
        for (char c; in.get(c);) {
            if (c == '\0') return true;
            if (out.size() == max_name) return false;
            out += c;
        }
        return false;
    };
    bool header_has_attributes = false;
    for (std::string name, type;;) {
        if (!name_at(name)) return "";  // damaged or cut: OpenEXR says how
        if (name.empty()) {              // the end of a header; a multi-part file's headers end with an empty one
            if (!multipart || !header_has_attributes) return "";
            header_has_attributes = false;
            continue;
        }
        header_has_attributes = true;
        unsigned char size_bytes[4];
        if (!name_at(type) || !in.read(reinterpret_cast<char*>(size_bytes), 4)) return "";
        const int64_t size = static_cast<int32_t>(le32(size_bytes));
        const uint64_t left = file_size - static_cast<uint64_t>(in.tellg());
        const std::string what = "its header attribute '" + printable(name) + "' (" + printable(type) + ")";
        if (size < 0 || static_cast<uint64_t>(size) > left)
            return fmt::format("{} claims {} bytes where the file has {} left (truncated?)", what, size, left);
        const auto fixed = fixed_sizes().find(type);
        if (fixed != fixed_sizes().end() && size != fixed->second)
            return fmt::format("{} claims {} bytes where its value takes {}", what, size, fixed->second);
        if (type == "chlist" || type == "stringvector" || type == "preview") {
            std::string value(static_cast<size_t>(size), '\0');
            if (!in.read(value.data(), size)) return "";
            const auto* v = reinterpret_cast<const unsigned char*>(value.data());
            const size_t n = value.size();
            size_t used = 0;  // what the C++ library reads of it
            if (type == "chlist") {  // entries (a name, 16 bytes) until an empty name
                for (size_t at = 0;;) {
                    const size_t end = value.find('\0', at);
                    if (end == std::string::npos) return what + " has no end within its size";
                    if (end == at) {
                        used = end + 1;
                        break;
                    }
                    at = end + 1 + 16;
                    if (at > n) return what + " has no end within its size";
                }
            } else if (type == "stringvector") {  // a length and its string, to the declared size
                while (used < n) {
                    if (n - used < 4) return what + " ends inside a string's length";
                    const uint64_t length = le32(v + used);
                    if (length > n - used - 4) return fmt::format("{} holds a string of {} bytes where it has {} left", what, length, n - used - 4);
                    used += 4 + length;
                }
            } else {  // preview: width, height, then 4 bytes a pixel
                if (n < 8) return what + " is shorter than a preview's width and height";
                used = 8 + 4 * static_cast<uint64_t>(le32(v)) * le32(v + 4);
            }
            if (used != n) return fmt::format("{} claims {} bytes where its value takes {}", what, size, used);
        } else {
            in.seekg(size, std::ios::cur);
        }
    }
}

// OpenEXR's C++ library takes a header attribute's size as it stands and allocates it before
// reading (a 1.4 KB file whose string attribute claimed 1.4 GB took 1.4 GB and 7.5 s to
// fail). A header whose values do not take their declared sizes is refused first
// (header_out_of_step()); then OpenEXR's C core parses it with every size checked against the
// file (it was written for untrusted input and is fuzzed upstream): a file it refuses is
// refused here, with its reason, before the C++ library opens it. Throws as OpenEXR would.
void check_header(const std::string& path) {
    if (std::string why = header_out_of_step(path); !why.empty()) throw std::runtime_error(why);
    struct Reason {
        std::string text;
    } reason;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.user_data = &reason;
    init.error_handler_fn = [](exr_const_context_t context, exr_result_t, const char* message) {
        void* user = nullptr;
        if (exr_get_user_data(context, &user) == EXR_ERR_SUCCESS && user && message) {
            auto* r = static_cast<Reason*>(user);
            if (r->text.empty()) r->text = message;  // the first, most specific one
        }
    };
    exr_context_t context = nullptr;
    const exr_result_t result = exr_start_read(&context, path.c_str(), &init);
    if (result == EXR_ERR_SUCCESS) exr_finish(&context);
    // The core passes over an attribute it finds damaged (its size beyond the file) and says so:
    // the C++ library would not, so what the core said is a refusal too.
    if (result == EXR_ERR_SUCCESS && reason.text.empty()) return;
    throw std::runtime_error(reason.text.empty() ? exr_get_default_error_message(result) : reason.text);
}

// OpenEXR's own bounds on what a header may ask for, checked as a file opens (before the
// line-offset table of a claimed 2^31 rows is allocated); kMaxReadPixels then bounds the product.
Imf::InputFile open_bounded(const std::string& path) {
    static const bool bounded = [] {
        Imf::Header::setMaxImageSize(65536, 65536);
        Imf::Header::setMaxTileSize(65536, 65536);
        return true;
    }();
    (void)bounded;
    check_header(path);
    return Imf::InputFile(path.c_str());
}

}  // namespace

std::string encode_exr(int width, int height, const std::vector<ImageLayer>& layers, const ImageMetadata& metadata,
                       std::string& error) {
    error.clear();
    try {
        const size_t np = static_cast<size_t>(width) * static_cast<size_t>(height);
        Imf::Header header(width, height);
        header.compression() = Imf::ZIP_COMPRESSION;
        for (const auto& [name, value] : metadata) insert_attribute(header, name, value);
        // One float plane a channel, non-finite values as 0 (as every image crex writes).
        std::vector<std::vector<float>> planes;
        Imf::FrameBuffer frame;
        for (const ImageLayer& layer : layers) {
            const int channels = layer.channels == 1 ? 1 : 3;
            for (int c = 0; c < channels; ++c) {
                std::string name = channels == 1 ? (layer.name.empty() ? "Y" : layer.name)
                                                 : (layer.name.empty() ? "" : layer.name + ".") + "RGB"[c];
                std::vector<float> plane(np);
                for (size_t p = 0; p < np; ++p) {
                    const float v = layer.rgb[static_cast<size_t>(channels) * p + static_cast<size_t>(c)];
                    plane[p] = std::isfinite(v) ? v : 0.0f;
                }
                planes.push_back(std::move(plane));
                header.channels().insert(name, Imf::Channel(Imf::FLOAT));
                frame.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(planes.back().data()), sizeof(float),
                                              sizeof(float) * static_cast<size_t>(width)));
            }
        }
        Imf::StdOSStream out;
        {
            Imf::OutputFile file(out, header);
            file.setFrameBuffer(frame);
            file.writePixels(height);
        }  // the line-offset table is written as the file closes
        return out.str();
    } catch (const std::exception& e) {
        error = e.what();
        return {};
    }
}

namespace {

// The three channels a reader takes as R, G, B from a file's; or, with `error` set, why the file
// has none it can take; or std::nullopt: the file is left to OpenImageIO.
using ChannelChoice = std::function<std::optional<std::array<std::string, 3>>(const Imf::ChannelList&, std::string& error)>;

std::optional<std::string> read_rgb(const std::string& path, const ChannelChoice& choose, int& width, int& height, std::vector<float>& rgb) {
    if (!Imf::isOpenExrFile(path.c_str())) return std::nullopt;
    try {
        Imf::InputFile in = open_bounded(path);
        std::string error;
        int w = 0, h = 0;
        if (!plain_window(in.header(), path, w, h, error)) return std::nullopt;
        if (!error.empty()) return error;
        const std::optional<std::array<std::string, 3>> names = choose(in.header().channels(), error);
        if (!error.empty()) return error;
        if (!names) return std::nullopt;
        read_channels(in, *names, w, h, rgb);
        width = w, height = h;
        return std::string();
    } catch (const std::exception& e) {
        return failed(path, e);
    }
}

}  // namespace

std::optional<std::string> read_exr(const std::string& path, int& width, int& height, std::vector<float>& rgb) {
    auto choose = [](const Imf::ChannelList& channels, std::string&) -> std::optional<std::array<std::string, 3>> {
        if (is_float_channel(channels.findChannel("R")) && is_float_channel(channels.findChannel("G")) &&
            is_float_channel(channels.findChannel("B")))
            return std::array<std::string, 3>{"R", "G", "B"};
        if (channels.begin() != channels.end() && ++channels.begin() == channels.end() && is_float_channel(&channels.begin().channel()))
            return std::array<std::string, 3>{channels.begin().name(), channels.begin().name(), channels.begin().name()};  // grey
        return std::nullopt;
    };
    return read_rgb(path, choose, width, height, rgb);
}

std::optional<std::string> read_exr_layer(const std::string& path, const std::string& layer, int& width, int& height,
                                          std::vector<float>& rgb) {
    auto choose = [&](const Imf::ChannelList& channels, std::string& error) -> std::optional<std::array<std::string, 3>> {
        const std::array<std::string, 3> names = {layer + ".R", layer + ".G", layer + ".B"};
        for (const std::string& n : names) {
            const Imf::Channel* c = channels.findChannel(n);
            if (!c) {
                error = "'" + path + "' has no layer '" + layer + "' (channels " + layer + ".R, .G, .B)";
                return std::nullopt;
            }
            if (!is_float_channel(c)) return std::nullopt;
        }
        return names;
    };
    return read_rgb(path, choose, width, height, rgb);
}

std::optional<std::string> read_exr_metadata(const std::string& path, int& width, int& height, ImageMetadata& metadata) {
    if (!Imf::isOpenExrFile(path.c_str())) return std::nullopt;
    try {
        Imf::InputFile in = open_bounded(path);
        const Imf::Header& header = in.header();
        const Imath::Box2i data = header.dataWindow();
        width = data.max.x - data.min.x + 1, height = data.max.y - data.min.y + 1;
        // What every OpenEXR file has (the layout, not what made the image) stays out.
        static const std::set<std::string> layout = {"channels",           "compression",       "dataWindow", "displayWindow",
                                                     "lineOrder",          "pixelAspectRatio",  "screenWindowCenter",
                                                     "screenWindowWidth",  "tiles",             "type",
                                                     "name",               "version",           "chunkCount"};
        metadata.clear();
        for (auto a = header.begin(); a != header.end(); ++a)
            if (!layout.count(a.name())) metadata.push_back({a.name(), attribute_value(a.attribute())});
        return std::string();
    } catch (const std::exception& e) {
        return failed(path, e);
    }
}

}  // namespace crex::image_formats
