// libFuzzer target: any bytes as an OpenEXR file that crex reads (a reference, a compared
// render, a partial image to resume, a sequence's frames). Seeded by tools/dev.sh with EXR
// files crex wrote. Invariants: no crash, sanitizer report or unbounded allocation; a read
// that succeeds gives width x height x 3 values.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "runtime/io/image_formats.h"
#include "tests/fuzz/input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace crex;
    const std::string path = fuzz::input_file(data, size, "fuzz.exr");
    int w = 0, h = 0;
    std::vector<float> rgb;
    if (auto e = image_formats::read_exr(path, w, h, rgb); e && e->empty() && rgb.size() != size_t(w) * size_t(h) * 3) std::abort();
    if (auto e = image_formats::read_exr_layer(path, "D", w, h, rgb); e && e->empty() && rgb.size() != size_t(w) * size_t(h) * 3)
        std::abort();
    ImageMetadata metadata;
    (void)image_formats::read_exr_metadata(path, w, h, metadata);
    return 0;
}
