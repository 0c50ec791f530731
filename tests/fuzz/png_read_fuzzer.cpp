// libFuzzer target: any bytes as a PNG file that crex reads (a compared render, a reference, a
// sequence's frames and their headers). Seeded by tools/dev.sh with PNG files crex wrote and
// small textures. Invariants: no crash, sanitizer report or unbounded allocation; a read that
// succeeds gives width x height x 3 finite values in [0, 1].
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "runtime/io/image_formats.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace crex;
    static const std::string path = "/tmp/crex_png_fuzz_" + std::to_string(::getpid()) + ".png";
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    }
    int w = 0, h = 0;
    std::vector<float> rgb;
    if (auto e = image_formats::read_png(path, w, h, rgb); e && e->empty()) {
        if (rgb.size() != size_t(w) * size_t(h) * 3) std::abort();
        for (float v : rgb)
            if (!(v >= 0 && v <= 1)) std::abort();
    }
    ImageMetadata metadata;
    (void)image_formats::read_png_metadata(path, w, h, metadata);
    return 0;
}
