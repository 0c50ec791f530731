#include "runtime/scene/radiance/noise.h"

#include <cmath>
#include <cstdint>

namespace crex::radiance {
namespace {

// Ken Perlin's permutation of 0..255 (his reference implementation's table).
constexpr int kPermutation[256] = {
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225,
    140, 36, 103, 30, 69, 142, 8, 99, 37, 240, 21, 10, 23, 190, 6, 148,
    247, 120, 234, 75, 0, 26, 197, 62, 94, 252, 219, 203, 117, 35, 11, 32,
    57, 177, 33, 88, 237, 149, 56, 87, 174, 20, 125, 136, 171, 168, 68, 175,
    74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83, 111, 229, 122,
    60, 211, 133, 230, 220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54,
    65, 25, 63, 161, 1, 216, 80, 73, 209, 76, 132, 187, 208, 89, 18, 169,
    200, 196, 135, 130, 116, 188, 159, 86, 164, 100, 109, 198, 173, 186, 3, 64,
    52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82, 85, 212,
    207, 206, 59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183, 170, 213,
    119, 248, 152, 2, 44, 154, 163, 70, 221, 153, 101, 155, 167, 43, 172, 9,
    129, 22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232, 178, 185, 112, 104,
    218, 246, 97, 228, 251, 34, 242, 193, 238, 210, 144, 12, 191, 179, 162, 241,
    81, 51, 145, 235, 249, 14, 239, 107, 49, 192, 214, 31, 181, 199, 106, 157,
    184, 84, 204, 176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93,
    222, 114, 67, 29, 24, 72, 243, 141, 128, 195, 78, 66, 215, 61, 156, 180,
};

int p(int i) { return kPermutation[i & 0xff]; }

double fade(double t) { return t * t * t * (t * (t * 6 - 15) + 10); }
double lerp(double t, double a, double b) { return a + t * (b - a); }

// One of 12 gradient directions from the hash's low four bits, dotted with (x, y, z).
double grad(int hash, double x, double y, double z) {
    const int h = hash & 15;
    const double u = h < 8 ? x : y, v = h < 4 ? y : (h == 12 || h == 14) ? x : z;
    return ((h & 1) ? -u : u) + ((h & 2) ? -v : v);
}

// The lattice cell as RADIANCE finds it: truncation, one less below zero (so -1.0 lies in the
// cell from -2 at fraction 1, which changes nothing but is what it computes).
int cell(double& x) {
    const int i = static_cast<int>(x) - (x < 0);
    x -= i;
    return i & 255;
}

constexpr double kStep = 0.0005;  // RADIANCE's EPSILON: derivatives' step, fnoise3's grid

// RADIANCE's frand: a hash of an integer to (-1, 1]; only the low 31 bits of the product
// matter, so unsigned 32-bit arithmetic (defined on overflow) gives the same values.
double frand(uint32_t s) {
    s = (s << 13) ^ s;
    const uint32_t h = s * (s * s * 15731u + 789221u) + 1376312589u;
    return 1.0 - static_cast<double>(h & 0x7fffffffu) / 1073741824.0;
}

double frand3(const int64_t v[3]) {
    return frand(static_cast<uint32_t>(17 * v[0] + 23 * v[1] + 29 * v[2]));
}

}  // namespace

double noise3(double x, double y, double z) {
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z) || std::fabs(x) > 1e9 || std::fabs(y) > 1e9 || std::fabs(z) > 1e9)
        return 0;  // beyond an int's lattice: no noise rather than undefined behaviour
    const int X = cell(x), Y = cell(y), Z = cell(z);
    const double u = fade(x), v = fade(y), w = fade(z);
    const int A = p(X) + Y, AA = p(A) + Z, AB = p(A + 1) + Z;
    const int B = p(X + 1) + Y, BA = p(B) + Z, BB = p(B + 1) + Z;
    return lerp(w, lerp(v, lerp(u, grad(p(AA), x, y, z), grad(p(BA), x - 1, y, z)),
                        lerp(u, grad(p(AB), x, y - 1, z), grad(p(BB), x - 1, y - 1, z))),
                lerp(v, lerp(u, grad(p(AA + 1), x, y, z - 1), grad(p(BA + 1), x - 1, y, z - 1)),
                     lerp(u, grad(p(AB + 1), x, y - 1, z - 1), grad(p(BB + 1), x - 1, y - 1, z - 1))));
}

double noise3_partial(double x, double y, double z, int axis) {
    const double here = noise3(x, y, z);
    const double before = noise3(x - (axis == 0) * kStep, y - (axis == 1) * kStep, z - (axis == 2) * kStep);
    return (here - before) / kStep;
}

double fnoise3(double x, double y, double z) {
    const double p[3] = {x, y, z};
    for (double c : p)
        if (!std::isfinite(c) || std::fabs(c) > 1e12) return 0;
    int64_t s = 2000;  // 1 / kStep
    int64_t t[3], beg[3], v[3];
    for (int i = 0; i < 3; ++i) {
        t[i] = static_cast<int64_t>(static_cast<double>(s) * p[i]);
        beg[i] = static_cast<int64_t>(static_cast<double>(s) * std::floor(p[i]));
    }
    // The cell's corners: corner j has bit i set where it lies at beg + s along axis i.
    double fval[8];
    for (int j = 0; j < 8; ++j) {
        for (int i = 0; i < 3; ++i) v[i] = beg[i] + (((j >> i) & 1) ? s : 0);
        fval[j] = frand3(v);
    }
    for (;;) {
        double fc = 0.125 * (fval[0] + fval[1] + fval[2] + fval[3] + fval[4] + fval[5] + fval[6] + fval[7]);
        s >>= 1;
        if (s == 0) return fc;  // the mean of the last cell's corners
        // Which half of the cell along each axis holds the point.
        int branch = 0;
        for (int i = 0; i < 3; ++i) {
            v[i] = beg[i] + s;
            if (t[i] > v[i]) branch |= 1 << i;
        }
        const double amplitude = static_cast<double>(s) * kStep;
        // The centre, displaced, becomes the sub-cell's corner opposite the branch.
        fc += amplitude * frand3(v);
        fval[~branch & 7] = fc;
        // The centres of the three faces on the branch side.
        for (int i = 0; i < 3; ++i) {
            v[i] += ((branch >> i) & 1) ? s : -s;
            fc = 0;
            for (int j = 0; j < 8; ++j)
                if (((j >> i) & 1) == ((branch >> i) & 1)) fc += fval[j];
            fc = 0.25 * fc + amplitude * frand3(v);
            fval[~(branch ^ (1 << i)) & 7] = fc;
            v[i] = beg[i] + s;
        }
        // The midpoints of the three edges through the branch corner.
        for (int i = 0; i < 3; ++i) {
            const int j1 = (i + 1) % 3, j2 = (i + 2) % 3;
            v[j1] += ((branch >> j1) & 1) ? s : -s;
            v[j2] += ((branch >> j2) & 1) ? s : -s;
            fc = 0.5 * (fval[branch & ~(1 << i)] + fval[branch | (1 << i)]) + amplitude * frand3(v);
            fval[branch ^ (1 << i)] = fc;
            v[j1] = beg[j1] + s;
            v[j2] = beg[j2] + s;
        }
        for (int i = 0; i < 3; ++i)
            if ((branch >> i) & 1) beg[i] += s;
    }
}

}  // namespace crex::radiance
