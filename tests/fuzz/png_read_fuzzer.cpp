// libFuzzer target: any bytes as a PNG file that crex reads (a compared render, a reference, a
// sequence's frames and their headers). Seeded by tools/dev.sh with PNG files crex wrote and
// small textures. Invariants: no crash, sanitizer report or unbounded allocation; a read that
// succeeds gives width x height x 3 finite values in [0, 1].
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "runtime/io/image_formats.h"
#include "tests/fuzz/input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace crex;
    const std::string path = fuzz::input_file(data, size, "fuzz.png");
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
