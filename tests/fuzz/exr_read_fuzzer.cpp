// libFuzzer target: any bytes as an OpenEXR file that crex reads (a reference, a compared
// render, a partial image to resume, a sequence's frames). Seeded by tools/dev.sh with EXR
// files crex wrote. Invariants: no crash, sanitizer report or unbounded allocation; a read
// that succeeds gives width x height x 3 values.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "runtime/io/image_formats.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace crex;
    static const std::string path = "/tmp/crex_exr_fuzz_" + std::to_string(::getpid()) + ".exr";
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    }
    int w = 0, h = 0;
    std::vector<float> rgb;
    if (auto e = image_formats::read_exr(path, w, h, rgb); e && e->empty() && rgb.size() != size_t(w) * size_t(h) * 3) std::abort();
    if (auto e = image_formats::read_exr_layer(path, "D", w, h, rgb); e && e->empty() && rgb.size() != size_t(w) * size_t(h) * 3)
        std::abort();
    ImageMetadata metadata;
    (void)image_formats::read_exr_metadata(path, w, h, metadata);
    return 0;
}
