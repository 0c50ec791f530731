#pragma once
// A float image written byte by byte as a PFM, for tests that need a NaN, an infinite or a
// negative value in a file (crex's own writer keeps images finite). OpenImageIO reads it
// whatever its name says.
#include <fstream>
#include <string>
#include <vector>

namespace crex::testing {

/// `rgb`: width x height RGB floats, rows from the bottom up as PFM stores them; written
/// little-endian (the "-1.0" scale), as the machines crex builds on are.
inline void write_pfm(const std::string& path, int width, int height, const std::vector<float>& rgb) {
    std::ofstream f(path, std::ios::binary);
    f << "PF\n" << width << ' ' << height << "\n-1.0\n";
    f.write(reinterpret_cast<const char*>(rgb.data()), static_cast<std::streamsize>(rgb.size() * sizeof(float)));
}

}  // namespace crex::testing
