// PNG through libpng (image_formats.h). Written as 8-bit in memory: image_io.cpp writes the
// bytes atomically, so a full disk or a file-size limit is a failed write() it sees, not a
// truncated file a writer did not report. Read from memory too, every colour type and depth.
#include <png.h>

#include <array>
#include <cmath>
#include <csetjmp>
#include <cstdint>
#include <cstring>
#include <cstdio>
#include <memory>

#include "base/input_file.h"
#include "base/render_text.h"
#include "runtime/io/image_formats.h"

namespace crex::image_formats {
namespace {

struct PngSink {
    std::string bytes;
    char error[256] = {};
};

void append(png_structp png, png_bytep data, png_size_t n) {
    static_cast<PngSink*>(png_get_io_ptr(png))->bytes.append(reinterpret_cast<const char*>(data), n);
}
void flush(png_structp) {}
// `T`: what holds the message (PngSink, PngSource).
template <class T>
[[noreturn]] void on_error(png_structp png, png_const_charp message) {
    auto* holder = static_cast<T*>(png_get_error_ptr(png));
    std::snprintf(holder->error, sizeof(holder->error), "%s", message);
    png_longjmp(png, 1);
}
void on_warning(png_structp, png_const_charp) {}

// The encoding itself, apart from every C++ object that owns memory: libpng reports errors
// by longjmp, which must not cross a destructor. `rows` point into the caller's pixels.
bool encode(PngSink& sink, png_uint_32 width, png_uint_32 height, int colour_type, png_bytep* rows, png_text* text, int texts) {
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &sink, on_error<PngSink>, on_warning);
    if (!png) return false;
    png_infop info = png_create_info_struct(png);
    if (!info || setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return false;
    }
    png_set_write_fn(png, &sink, append, flush);
    // zlib level 3, not libpng's 6: a noisy 320x240 frame takes 7.6 ms instead of 22 and is
    // 7 % larger (75.6 KB against 70.4), which matters for a sequence's PNG every frame
    // (Blender's default PNG compression is as light, 15 %).
    png_set_compression_level(png, 3);
    png_set_IHDR(png, info, width, height, 8, colour_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);  // the values are sRGB-encoded
    if (texts > 0) png_set_text(png, info, text, texts);
    png_set_rows(png, info, rows);
    png_write_png(png, info, PNG_TRANSFORM_IDENTITY, nullptr);
    png_destroy_write_struct(&png, &info);
    return true;
}

// Reading. As for writing, every libpng call that can fail runs in a function whose frame holds
// no C++ object with a destructor, so that libpng's longjmp skips none.
struct PngSource {
    const unsigned char* data = nullptr;
    size_t size = 0, at = 0;
    char error[256] = {};
};

void take(png_structp png, png_bytep out, png_size_t n) {
    auto* source = static_cast<PngSource*>(png_get_io_ptr(png));
    if (n > source->size - source->at) png_error(png, "the file ends inside the image (truncated?)");
    std::memcpy(out, source->data + source->at, n);
    source->at += n;
}

// What the file's pixels become after the transforms below: 1 (grey), 2 (grey, alpha), 3 (RGB)
// or 4 (RGBA) channels of 8 or 16 bits.
struct PngLayout {
    png_uint_32 width = 0, height = 0;
    int channels = 0, bit_depth = 0;
    size_t row_bytes = 0;
    // How stored values become linear light: 0 for the sRGB curve, else the power they are
    // raised to (1 / the file's gAMA).
    double decode_power = 0;
};

// The transfer a file's values were stored with. An sRGB or ICC chunk, or none at all, is
// sRGB (as the PNG specification asks a decoder to assume for an untagged file, and as every
// crex PNG says). A gAMA chunk alone is a pure power: its value near 1/2.2 is the sRGB curve
// that writers tag so, 1 is linear light (16-bit data images, some HDR tools' previews).
double decode_power_of(png_structp png, png_infop info) {
    if (png_get_valid(png, info, PNG_INFO_sRGB) || png_get_valid(png, info, PNG_INFO_iCCP)) return 0;
    png_fixed_point gamma = 0;
    if (!png_get_gAMA_fixed(png, info, &gamma) || gamma <= 0) return 0;
    if (gamma > 43000 && gamma < 48000) return 0;  // 1/2.2 +- 5 %: written for the sRGB curve
    return 100000.0 / static_cast<double>(gamma);
}

// The header, and the transforms that give every colour type as PngLayout: palettes and grey
// below 8 bits expanded, a tRNS chunk as alpha, interlaced passes put together. Bounded before
// anything is allocated: 65536 pixels a side, kMaxReadPixels in all, 8 MiB for an ancillary
// chunk (a compressed text chunk cannot inflate past it).
bool open_png(png_structp png, png_infop info, PngLayout& layout) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_set_user_limits(png, 65536, 65536);
    png_set_chunk_malloc_max(png, 8u << 20);
    png_read_info(png, info);
    const png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
    if (static_cast<uint64_t>(w) * h > static_cast<uint64_t>(kMaxReadPixels)) png_error(png, "the image has more pixels than crex reads");
    layout.decode_power = decode_power_of(png, info);
    png_set_expand(png);
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    layout.width = w, layout.height = h;
    layout.channels = png_get_channels(png, info);
    layout.bit_depth = png_get_bit_depth(png, info);
    layout.row_bytes = png_get_rowbytes(png, info);
    return true;
}

bool read_rows(png_structp png, png_bytepp rows) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_read_image(png, rows);
    return true;
}

// A PNG file's bytes and libpng's read and info structs over them, destroyed together.
struct PngFile {
    std::string bytes;
    PngSource source;
    png_structp png = nullptr;
    png_infop info = nullptr;
    PngLayout layout;
    std::string error;  // why it cannot be read, "" where it can
    explicit PngFile(std::string file_bytes) : bytes(std::move(file_bytes)) {
        source.data = reinterpret_cast<const unsigned char*>(bytes.data());
        source.size = bytes.size();
        png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &source, on_error<PngSource>, on_warning);
        if (png) info = png_create_info_struct(png);
        if (png && info) png_set_read_fn(png, &source, take);
    }
    ~PngFile() { png_destroy_read_struct(&png, &info, nullptr); }
    PngFile(const PngFile&) = delete;
    PngFile& operator=(const PngFile&) = delete;
    std::string why(const std::string& path) const {
        return "cannot read '" + path + "': " + (source.error[0] ? source.error : "libpng could not decode it");
    }
};

// The file's bytes where it is a PNG (its signature), else nullopt (a file that cannot be read
// too: the plugin then says why).
std::optional<std::string> png_bytes(const std::string& path) {
    std::string error;
    std::optional<std::string> bytes = read_input_file(path, error, kMaxDataInputBytes);
    if (!bytes || bytes->size() < 8 || png_sig_cmp(reinterpret_cast<png_const_bytep>(bytes->data()), 0, 8) != 0) return std::nullopt;
    return bytes;
}

// Why the file cannot be read before libpng sees it, else "". libpng allocates an ancillary
// chunk's claimed length before reading it (its own limit is only a warning when reading: a
// 213-byte file whose tEXt claimed 1.5 GB took 1.5 GB and 8 s to fail), so every chunk must fit
// in what the file has left. And a size beyond what crex reads is said in pixels, where libpng's
// own limit (kept as a second guard in open_png) says only "Invalid IHDR data".
std::string unreadable(const std::string& path, const std::string& bytes) {
    auto word = [&](size_t at) {
        uint64_t v = 0;
        for (size_t k = 0; k < 4; ++k) v = v << 8 | static_cast<unsigned char>(bytes[at + k]);
        return v;
    };
    for (size_t at = 8; at + 8 <= bytes.size();) {  // length, type, data, CRC
        const uint64_t length = word(at), left = bytes.size() - at - 8;
        if (length + 4 > left)
            return "cannot read '" + path + "': its chunk '" + printable(bytes.substr(at + 4, 4)) + "' claims " + std::to_string(length) +
                   " bytes where the file has " + std::to_string(left) + " left (truncated?)";
        if (bytes.compare(at + 4, 4, "IEND") == 0) break;
        at += 12 + length;
    }
    if (bytes.size() < 24 || bytes.compare(12, 4, "IHDR") != 0) return "";  // libpng says what is wrong
    const uint64_t w = word(16), h = word(20);
    if (w <= 65536 && h <= 65536 && w * h <= static_cast<uint64_t>(kMaxReadPixels)) return "";
    return "cannot read '" + path + "': an image of " + std::to_string(w) + " x " + std::to_string(h) +
           " pixels is beyond what crex reads (" + std::to_string(kMaxReadPixels) + " pixels, 65536 a side)";
}

// `path` opened up to its pixels (PngFile::error says why it cannot be), or nullptr where it
// is not a PNG.
std::unique_ptr<PngFile> open_file(const std::string& path) {
    std::optional<std::string> bytes = png_bytes(path);
    if (!bytes) return nullptr;
    auto file = std::make_unique<PngFile>(std::move(*bytes));
    file->error = unreadable(path, file->bytes);
    if (file->error.empty() && (!file->png || !file->info || !open_png(file->png, file->info, file->layout))) file->error = file->why(path);
    return file;
}

}  // namespace

std::optional<std::string> read_png(const std::string& path, int& width, int& height, std::vector<float>& rgb) {
    const std::unique_ptr<PngFile> file = open_file(path);
    if (!file) return std::nullopt;
    if (!file->error.empty()) return file->error;
    const PngLayout& layout = file->layout;
    const size_t file_size = file->bytes.size();
    // A header claiming more pixels than its deflated file can hold is refused before the
    // pixels' memory is taken (a 100-byte file may claim 2^25).
    if (std::string why = claim_beyond_file(static_cast<double>(layout.row_bytes + 1) * layout.height, file_size, layout.width,
                                            layout.height, kDeflatePacking);
        !why.empty())
        return "cannot read '" + path + "': " + why;
    std::vector<unsigned char> pixels(layout.row_bytes * layout.height);
    std::vector<png_bytep> rows(layout.height);
    for (size_t y = 0; y < rows.size(); ++y) rows[y] = pixels.data() + y * layout.row_bytes;
    if (!read_rows(file->png, rows.data())) return file->why(path);
    // Stored values to linear light (decode_power_of()); alpha composites over black (as
    // OpenImageIO gave them, associated); grey to all three channels.
    const size_t n = static_cast<size_t>(layout.width) * layout.height, nc = static_cast<size_t>(layout.channels);
    const bool wide = layout.bit_depth == 16, alpha = nc == 2 || nc == 4;
    const double power = layout.decode_power;
    auto decode = [power](double v) { return power > 0 ? std::pow(v, power) : srgb_decode(v); };
    std::array<double, 256> linear_of_byte{};  // a power a value was 0.2 s a 1080p frame
    if (!wide)
        for (size_t v = 0; v < linear_of_byte.size(); ++v) linear_of_byte[v] = decode(static_cast<double>(v) / 255.0);
    auto value = [&](size_t k) { return wide ? static_cast<double>(pixels[2 * k] << 8 | pixels[2 * k + 1]) / 65535.0 : pixels[k] / 255.0; };
    auto linear = [&](size_t k) { return wide ? decode(value(k)) : linear_of_byte[pixels[k]]; };
    rgb.assign(3 * n, 0.0f);
    for (size_t p = 0; p < n; ++p) {
        const double a = alpha ? value(p * nc + nc - 1) : 1.0;
        for (size_t c = 0; c < 3; ++c) rgb[3 * p + c] = static_cast<float>(linear(p * nc + (nc < 3 ? 0 : c)) * a);
    }
    width = static_cast<int>(layout.width), height = static_cast<int>(layout.height);
    return std::string();
}

std::optional<std::string> read_png_metadata(const std::string& path, int& width, int& height, ImageMetadata& metadata) {
    const std::unique_ptr<PngFile> file = open_file(path);
    if (!file) return std::nullopt;
    if (!file->error.empty()) return file->error;
    // The text chunks before the pixels (where crex and most writers put them), as strings.
    metadata.clear();
    png_textp text = nullptr;
    const int texts = png_get_text(file->png, file->info, &text, nullptr);
    for (int i = 0; i < texts; ++i)
        if (text[i].key && text[i].text)  // tEXt and zTXt give their length in text_length, iTXt in itxt_length
            metadata.push_back({text[i].key, std::string(text[i].text, text[i].text_length ? text[i].text_length : text[i].itxt_length)});
    width = static_cast<int>(file->layout.width), height = static_cast<int>(file->layout.height);
    return std::string();
}

std::string encode_png(int width, int height, const std::vector<ImageLayer>& layers, const ImageMetadata& metadata,
                       std::string& error) {
    error.clear();
    const ImageLayer& layer = layers.front();
    const size_t nc = layer.channels == 1 ? 1 : 3;
    std::vector<unsigned char> bytes = eight_bit_pixels(layer, static_cast<size_t>(width) * static_cast<size_t>(height));
    std::vector<png_bytep> rows(static_cast<size_t>(height));
    for (size_t y = 0; y < rows.size(); ++y) rows[y] = bytes.data() + y * static_cast<size_t>(width) * nc;
    // String attributes as tEXt chunks (what made the image); PNG has no typed numbers.
    std::vector<png_text> text;
    for (const ImageAttribute& a : metadata)
        if (const auto* s = std::get_if<std::string>(&a.value); s && !a.name.empty() && a.name.size() < 80) {
            png_text t{};
            t.compression = PNG_TEXT_COMPRESSION_NONE;
            t.key = const_cast<char*>(a.name.c_str());
            t.text = const_cast<char*>(s->c_str());
            t.text_length = s->size();
            text.push_back(t);
        }
    PngSink sink;
    if (!encode(sink, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), nc == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB,
                rows.data(), text.data(), static_cast<int>(text.size()))) {
        error = sink.error[0] ? sink.error : "libpng could not encode the image";
        return {};
    }
    return std::move(sink.bytes);
}

}  // namespace crex::image_formats
