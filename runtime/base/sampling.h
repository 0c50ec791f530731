/// \file sampling.h
/// Deterministic sampling. Random numbers are a hash of *what* is sampled (a ray's path id,
/// its depth and a purpose), never of *when*: renders are identical whatever the thread count
/// and execution order. Camera samples follow the Halton (2, 3) sequence per pixel with a
/// per-pixel rotation, so sample k of a pixel is the same whether it is drawn in a 1-spp
/// preview or a 16-spp render (progressive, hierarchical).
#pragma once

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>

#include "runtime/base/vec3.h"

namespace crex {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kInvPi = 1 / kPi;

/// SplitMix64 finaliser: a good 64-bit mixer.
inline uint64_t mix64(uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

inline uint64_t hash_combine(uint64_t a, uint64_t b) { return mix64(a ^ mix64(b)); }

/// A uniform double in [0, 1) from a hash.
inline double to_unit(uint64_t h) { return static_cast<double>(h >> 11) * 0x1.0p-53; }

/// Purposes of random numbers at a hit (one stream each).
enum class RandomUse : uint64_t { kRoulette = 1, kLobeD, kLobeG, kLobeDT, kLight, kLightPick, kCamera, kIcTheta, kIcPhi, kIcLobe, kMediumDistance, kMediumLight, kMediumPick, kIcTrans, kCausticLookup, kIcHot, kHotLight };

/// The random numbers of one hit (path `path_id` at `depth`): the key is hashed once, then
/// each number is one more mix. Equal to random_at() number for number.
class HitRandom {
public:
    HitRandom(uint64_t path_id, uint32_t depth) : key_(hash_combine(path_id, depth)) {}
    /// The hit of camera sample `sample` of the pixel keyed `pixel_key`: as above, but the
    /// directions of its scattering lobes (D, G, DT) are point `sample` of the pixel's own
    /// scrambled (0,2)-sequence, one per lobe, so the first bounces of a pixel's samples are
    /// stratified together over the hemisphere (independent directions left the indirect light
    /// as noisy as one sample's each).
    static HitRandom camera_hit(uint64_t path_id, uint32_t depth, uint64_t pixel_key, uint32_t sample) {
        HitRandom r(path_id, depth);
        r.pixel_key_ = pixel_key;
        r.sample_ = sample;
        r.pixel_sequence_ = true;
        return r;
    }
    double operator()(RandomUse use, uint32_t index = 0) const {
        return to_unit(hash_combine(key_, (static_cast<uint64_t>(use) << 32) | index));
    }
    /// Two uniforms in [0, 1) with 32 bits each from one hash (a 2-D sample for one purpose).
    inline void pair(RandomUse use, double& u, double& v) const;

private:
    uint64_t key_;
    uint64_t pixel_key_ = 0;
    uint32_t sample_ = 0;
    bool pixel_sequence_ = false;
};

/// Random number `index` for `use` at the hit of path `path_id` at `depth`.
inline double random_at(uint64_t path_id, uint32_t depth, RandomUse use, uint32_t index = 0) {
    return HitRandom(path_id, depth)(use, index);
}

/// Van der Corput radical inverse in base 2 (bit reversal) and base 3.
inline uint32_t reverse_bits_32(uint32_t k) {
    k = (k << 16) | (k >> 16);
    k = ((k & 0x00ff00ffu) << 8) | ((k & 0xff00ff00u) >> 8);
    k = ((k & 0x0f0f0f0fu) << 4) | ((k & 0xf0f0f0f0u) >> 4);
    k = ((k & 0x33333333u) << 2) | ((k & 0xccccccccu) >> 2);
    return ((k & 0x55555555u) << 1) | ((k & 0xaaaaaaaau) >> 1);
}
inline double radical_inverse_2(uint32_t k) { return static_cast<double>(reverse_bits_32(k)) * 0x1.0p-32; }
inline double radical_inverse_3(uint32_t k) {
    double inv = 1.0 / 3.0, f = inv, r = 0;
    while (k > 0) {
        r += f * (k % 3);
        k /= 3;
        f *= inv;
    }
    return r;
}

/// Point k of a 2-D Halton set rotated (Cranley-Patterson) by (u0, u1).
inline void rotated_halton(uint32_t k, double u0, double u1, double& x, double& y) {
    x = radical_inverse_2(k) + u0;  // both in [0, 2): wrap without floor (a libm call on x86-64)
    y = radical_inverse_3(k) + u1;
    if (x >= 1) x -= 1;
    if (y >= 1) y -= 1;
}

/// Owen's nested uniform scramble of the bits of x, by hashing (Burley 2020, "Practical
/// Hash-based Owen Scrambling", JCGT 9(4), after Laine and Karras): a different random
/// permutation of every subinterval, so nets stay nets.
inline uint32_t owen_scramble(uint32_t x, uint32_t seed) {
    x = reverse_bits_32(x);
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return reverse_bits_32(x);
}

/// Sobol's second dimension: index bit j selects the column v_j of the binary Pascal matrix
/// (v_0 = 2^31, v_{j+1} = v_j ^ (v_j >> 1)), and the point is the XOR of the selected ones,
/// here a byte at a time: table b holds the XOR of the columns of every value of index byte b.
/// A loop over the bits branched on each bit of a scrambled (random) index, mispredicted half
/// the time, and made owen_sobol_2d most of direct_light_sample (prog_all's corridor walk, issue 36).
inline constexpr std::array<std::array<uint32_t, 256>, 4> kSobolSecondBytes = [] {
    std::array<uint32_t, 32> v{};
    v[0] = 1u << 31;
    for (size_t j = 1; j < 32; ++j) v[j] = v[j - 1] ^ (v[j - 1] >> 1);
    std::array<std::array<uint32_t, 256>, 4> t{};
    for (size_t b = 0; b < 4; ++b)
        for (uint32_t x = 0; x < 256; ++x)
            for (size_t bit = 0; bit < 8; ++bit)
                if ((x >> bit) & 1u) t[b][x] ^= v[8 * b + bit];
    return t;
}();
inline uint32_t sobol_second(uint32_t i) {
    return kSobolSecondBytes[0][i & 0xffu] ^ kSobolSecondBytes[1][(i >> 8) & 0xffu] ^ kSobolSecondBytes[2][(i >> 16) & 0xffu] ^
           kSobolSecondBytes[3][i >> 24];
}

/// Point `index` of the first two dimensions of Sobol' (a (0,2)-sequence: every power-of-two
/// prefix is stratified in both dimensions at once), shuffled and Owen-scrambled by `seed`
/// (Burley 2020): the shuffle decorrelates it from other sequences driven by the same index
/// (the camera's sub-pixel position), the scramble makes each point uniform.
inline void owen_sobol_2d(uint32_t index, uint64_t seed, double& x, double& y) {
    const uint32_t i = owen_scramble(index, static_cast<uint32_t>(seed));
    const uint32_t second = sobol_second(i);
    const uint64_t h = mix64(seed);
    x = owen_scramble(reverse_bits_32(i), static_cast<uint32_t>(h)) * 0x1.0p-32;
    y = owen_scramble(second, static_cast<uint32_t>(h >> 32)) * 0x1.0p-32;
}

inline void HitRandom::pair(RandomUse use, double& u, double& v) const {
    if (pixel_sequence_ && (use == RandomUse::kLobeD || use == RandomUse::kLobeG || use == RandomUse::kLobeDT)) {
        owen_sobol_2d(sample_, mix64(pixel_key_ ^ (static_cast<uint64_t>(use) * 0x632be59bd9b4e019ull)), u, v);
        return;
    }
    uint64_t h = hash_combine(key_, (static_cast<uint64_t>(use) << 32) | 0xffffffffu);
    u = static_cast<double>(h >> 32) * 0x1.0p-32;
    v = static_cast<double>(h & 0xffffffffu) * 0x1.0p-32;
}

/// An orthonormal frame around unit `n` (Duff et al. 2017).
inline void orthonormal_basis(const Vec3& n, Vec3& t, Vec3& b) {
    double sign = std::copysign(1.0, n.z);
    double a = -1.0 / (sign + n.z);
    double c = n.x * n.y * a;
    t = {1 + sign * n.x * n.x * a, sign * c, -sign * n.x};
    b = {c, sign + n.y * n.y * a, -n.y};
}

/// cos and sin of 2 pi u for u in [0, 1), inline: libm's double sincos was 5 % of a render.
inline void sincos_2pi(double u, double& c, double& s) {
    // Nearest quarter turn q, remainder r in [-pi/4, pi/4]; Taylor to degree 11/12 there
    // (error < 1e-11), then rotate by q quarters. No libm call and no branch: the rotation is
    // a swap and two sign flips chosen by bit masks (a switch on a random quarter was
    // mispredicted three times in four, about 2 % of a Cornell box render).
    double t = 4 * u;
    const int quarter = static_cast<int>(t + 0.5);  // t >= 0: truncation rounds
    double r = (t - static_cast<double>(quarter)) * (kPi / 2), r2 = r * r;
    double sr = r * (1 + r2 * (-1.0 / 6 + r2 * (1.0 / 120 + r2 * (-1.0 / 5040 + r2 * (1.0 / 362880 + r2 * (-1.0 / 39916800))))));
    double cr = 1 + r2 * (-0.5 + r2 * (1.0 / 24 + r2 * (-1.0 / 720 + r2 * (1.0 / 40320 + r2 * (-1.0 / 3628800 + r2 * (1.0 / 479001600))))));
    // Quarter k: (c, s) = (cr, sr), (-sr, cr), (-cr, -sr), (sr, -cr).
    const auto k = static_cast<uint64_t>(quarter & 3);
    const uint64_t swap = 0 - (k & 1), bc = std::bit_cast<uint64_t>(cr), bs = std::bit_cast<uint64_t>(sr);
    const uint64_t first = (bc & ~swap) | (bs & swap), second = (bs & ~swap) | (bc & swap);
    c = std::bit_cast<double>(first ^ (((k + 1) >> 1 & 1) << 63));
    s = std::bit_cast<double>(second ^ ((k >> 1) << 63));
}

/// Cosine-weighted direction around unit `n`; pdf = cos / pi.
inline Vec3 sample_cosine(const Vec3& n, double u1, double u2) {
    double r = std::sqrt(u1), c, s;
    sincos_2pi(u2, c, s);
    Vec3 t, b;
    orthonormal_basis(n, t, b);
    double z = std::sqrt(1 - u1 > 0 ? 1 - u1 : 0.0);
    return t * (r * c) + b * (r * s) + n * z;
}

/// The unit direction at angle cosine `cos_t` from unit `axis`, a fraction `turn` of the way
/// round it.
inline Vec3 direction_around(const Vec3& axis, double cos_t, double turn) {
    double sin_t2 = 1 - cos_t * cos_t, sin_t = std::sqrt(sin_t2 > 0 ? sin_t2 : 0.0), c, s;
    sincos_2pi(turn, c, s);
    Vec3 t, b;
    orthonormal_basis(axis, t, b);
    return t * (sin_t * c) + b * (sin_t * s) + axis * cos_t;
}

/// Direction around unit `axis` with pdf (e+1)/(2 pi) cos^e (normalised Phong lobe).
inline Vec3 sample_phong(const Vec3& axis, double exponent, double u1, double u2) {
    return direction_around(axis, std::pow(u1, 1.0 / (exponent + 1)), u2);
}

inline Vec3 reflect(const Vec3& d, const Vec3& n) { return d - n * (2 * dot(d, n)); }

}  // namespace crex
