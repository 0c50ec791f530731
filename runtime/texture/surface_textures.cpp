#include "runtime/texture/surface_textures.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "runtime/texture/tiled_copies.h"

namespace crex {
namespace {

// Textured roughness never reaches 0: a texel of 0 is the sharpest glossy lobe, not an ideal
// mirror, so that the census can say "G" of a material whose roughness is an image.
constexpr double kMinTexturedRoughness = 1e-3;

// A normal map's texel decodes as 2 v - 1: 8-bit files cannot hold 0 (128 is +1/255, 127 is
// -1/255), so tangent-space x and y within about one 8-bit step of 0 are flat: a flat normal
// map then changes nothing at all, not a 0.2 degree tilt.
constexpr double kFlatNormal = 1.01 / 255;

// A coarse copy's longest side. An irradiance record averages hundreds of hemisphere rays and
// interpolates over many pixels: 128 texels hold the image's colours at a scale finer than
// either, and 64 Ki floats of four channels (256 KiB) an image.
constexpr int kCoarseSize = 128;

// Texel index i of a row of n under a wrap mode; -1: outside a black border.
int64_t wrapped(int64_t i, int64_t n, BackendWrap w) {
    if (i >= 0 && i < n) return i;  // most lookups: no division (two were 1 % of a textured render)
    switch (w) {
    case BackendWrap::kPeriodic: {
        const int64_t m = i % n;
        return m < 0 ? m + n : m;
    }
    case BackendWrap::kClamp: return std::clamp<int64_t>(i, 0, n - 1);
    case BackendWrap::kMirror: {
        const int64_t m = ((i % (2 * n)) + 2 * n) % (2 * n);
        return m < n ? m : 2 * n - 1 - m;
    }
    case BackendWrap::kBlack: return i < 0 || i >= n ? -1 : i;
    }
    return -1;
}

double clamp01(double x) { return min_of(max_of(x, 0.0), 1.0); }
Vec3 clamp01(const Vec3& v) { return {clamp01(v.x), clamp01(v.y), clamp01(v.z)}; }

// sRGB's curve above its linear toe, x^2.4 for x in [0, 1], from a table between whose
// entries it is linear: within 1.0e-7 of std::pow (the curvature bound h^2/8 max|f''|, with
// max|f''| = 3.36), about a 39,000th of an 8-bit step. Every colour of an 8-bit image is
// decoded, several a hit (the cache's hemisphere hits too), and three pow calls a colour were
// 2.5 % of a textured render.
constexpr int kSrgbSteps = 2048;
const std::array<double, kSrgbSteps + 2>& srgb_power_table() {
    static const std::array<double, kSrgbSteps + 2> table = [] {
        std::array<double, kSrgbSteps + 2> t{};
        for (int k = 0; k <= kSrgbSteps + 1; ++k) t[static_cast<size_t>(k)] = std::pow(static_cast<double>(k) / kSrgbSteps, 2.4);
        return t;
    }();
    return table;
}

double srgb_to_linear(double c) {
    if (c <= 0.04045) return c / 12.92;
    const double x = (c + 0.055) / 1.055;
    if (!(x <= 1)) return std::pow(x, 2.4);  // float images past white (and NaN) exactly
    const std::array<double, kSrgbSteps + 2>& t = srgb_power_table();
    const double at = x * kSrgbSteps;
    const auto k = static_cast<size_t>(at);
    const double f = at - static_cast<double>(k);
    return t[k] + (t[k + 1] - t[k]) * f;
}

BackendWrap wrap_of(TextureWrap w) {
    switch (w) {
    case TextureWrap::kRepeat: return BackendWrap::kPeriodic;
    case TextureWrap::kClamp: return BackendWrap::kClamp;
    case TextureWrap::kMirror: return BackendWrap::kMirror;
    case TextureWrap::kBlack: return BackendWrap::kBlack;
    }
    return BackendWrap::kPeriodic;
}

// Channels [first, first + n) of a w x h image of `channels` channels (texels times `scale`)
// at `at`, bilinear between the four texel centres around it (t = 0 is the top row), or the
// texel it falls in for `at.nearest`, under `ref`'s wrap modes; false where the coordinates
// are beyond any image.
template <class Texel>
bool bilinear(const Texel* texels, int w, int h, int channels, int first, int n, float scale, const TextureLookup& at, const TextureRef& ref,
              float* out) {
    // The nearest texel: the one the point falls in, as the bilinear weights of a point at its
    // centre's corner (all of the weight on (x0 + 1, y0 + 1)).
    const double half = at.nearest ? 0.0 : 0.5;
    const double x = static_cast<double>(at.s) * w - half, y = static_cast<double>(at.t) * h - half;
    const double fx0 = std::floor(x) - (at.nearest ? 1 : 0), fy0 = std::floor(y) - (at.nearest ? 1 : 0);
    if (!(std::fabs(fx0) < 1e15 && std::fabs(fy0) < 1e15)) return false;
    const int64_t x0 = static_cast<int64_t>(fx0), y0 = static_cast<int64_t>(fy0);
    const float ax = at.nearest ? 1.0f : static_cast<float>(x - fx0), ay = at.nearest ? 1.0f : static_cast<float>(y - fy0);
    const BackendWrap ws = wrap_of(ref.wrap_s), wt = wrap_of(ref.wrap_t);
    const int64_t xs[2] = {wrapped(x0, w, ws), wrapped(x0 + 1, w, ws)};
    const int64_t ys[2] = {wrapped(y0, h, wt), wrapped(y0 + 1, h, wt)};
    const float wx[2] = {1 - ax, ax}, wy[2] = {1 - ay, ay};
    for (int k = 0; k < n; ++k) out[k] = 0;
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            if (xs[i] < 0 || ys[j] < 0) continue;  // a black border
            const float weight = wx[i] * wy[j];
            const Texel* texel = texels + (static_cast<size_t>(ys[j]) * static_cast<size_t>(w) + static_cast<size_t>(xs[i])) * static_cast<size_t>(channels);
            for (int k = 0; k < n; ++k) out[k] += weight * (static_cast<float>(texel[first + k]) * scale);
        }
    return true;
}

}  // namespace

size_t texture_cache_bytes(size_t max_memory) {
    return std::clamp<size_t>(max_memory / 8, size_t{16} << 20, size_t{1} << 30);
}

uint64_t TextureImage::memory_bytes() const {
    const uint64_t top = uint64_t(info.width) * uint64_t(info.height) * uint64_t(info.channels) * uint64_t(std::max(info.bytes_per_channel, 1));
    return top + top / 3;
}

SurfaceTextures::SurfaceTextures(const Scene& scene, size_t cache_bytes, std::vector<Diagnostic>& warnings, TiledCopies copies,
                                 TextureProgress progress)
    : scene_(scene), cache_bytes_(cache_bytes), copies_(copies), progress_(std::move(progress)) {
    bool referenced = false;
    for (const Material& m : scene.materials) referenced = referenced || m.textures.any();
    if (referenced) {  // the image plugin only when there are images
        std::string error;
        backend_ = make_texture_backend(cache_bytes, error);
        if (!backend_) throw std::runtime_error("cannot read the scene's textures: " + error);
    }
    slots_.resize(scene.materials.size());
    for (size_t i = 0; i < scene.materials.size(); ++i) {
        const Material& m = scene.materials[i];
        const MaterialTextures& t = m.textures;
        MaterialSlots& s = slots_[i];
        s.color = open_slot(t.color, SlotKind::kColour, scene, warnings);
        s.specular_color = open_slot(t.specular_color, SlotKind::kColour, scene, warnings);
        s.specularity = open_slot(t.specularity, SlotKind::kScalar, scene, warnings);
        s.roughness = open_slot(t.roughness, SlotKind::kScalar, scene, warnings);
        s.metallic = open_slot(t.metallic, SlotKind::kScalar, scene, warnings);
        s.normal = open_slot(t.normal, SlotKind::kVector, scene, warnings);
        s.bump = open_slot(t.bump, SlotKind::kScalar, scene, warnings);
        s.opacity = open_slot(t.opacity, SlotKind::kOpacity, scene, warnings);
        s.emission = open_slot(t.emission, SlotKind::kColour, scene, warnings);
        s.any = t.any();
        s.cuts_out = s.opacity.image >= 0 || m.opacity < 1;
    }
    coarse_.resize(images_.size());
    for (auto& c : coarse_) c = std::make_unique<CoarseImage>();
    failed_lookups_ = std::make_unique<std::atomic<uint64_t>[]>(images_.size());
    non_finite_lookups_ = std::make_unique<std::atomic<uint64_t>[]>(images_.size());
    size_t mask_budget = cache_bytes / kMaskShare;
    for (MaterialSlots& s : slots_) plan_mask(s.opacity, mask_budget);
}

void SurfaceTextures::plan_mask(Slot& slot, size_t& budget) {
    if (slot.image < 0 || slot.ref.channel < 0) return;
    for (size_t k = 0; k < masks_.size(); ++k)
        if (masks_[k]->image == slot.image && masks_[k]->channel == slot.ref.channel) {
            slot.mask = static_cast<int>(k);
            return;
        }
    const TextureImageInfo& info = images_[static_cast<size_t>(slot.image)].info;
    const uint64_t bytes = uint64_t(info.width) * uint64_t(info.height) * (info.eight_bit ? 1u : 4u);
    if (info.width <= 0 || info.height <= 0 || bytes > budget) return;
    budget -= bytes;
    mask_bytes_ += bytes;
    auto m = std::make_unique<OpacityMask>();
    m->image = slot.image, m->channel = slot.ref.channel;
    slot.mask = static_cast<int>(masks_.size());
    masks_.push_back(std::move(m));
}

const SurfaceTextures::OpacityMask& SurfaceTextures::opacity_mask(int mask) const {
    OpacityMask& m = *masks_[static_cast<size_t>(mask)];
    std::call_once(m.once, [&] {
        const TextureImageInfo& info = images_[static_cast<size_t>(m.image)].info;
        std::vector<float> texels(size_t(info.width) * size_t(info.height));
        if (!backend_->texels(ids_[static_cast<size_t>(m.image)], m.channel, 1, texels.data())) return;
        for (float v : texels)
            if (!std::isfinite(v)) return;
        if (info.eight_bit) {
            m.bytes.resize(texels.size());
            for (size_t k = 0; k < texels.size(); ++k) m.bytes[k] = static_cast<uint8_t>(std::lround(std::clamp(texels[k], 0.0f, 1.0f) * 255.0f));
        } else {
            m.floats = std::move(texels);
        }
        m.width = info.width, m.height = info.height;
        m.ok = true;
    });
    return m;
}

SurfaceTextures::~SurfaceTextures() = default;

int SurfaceTextures::open_tiled_copy(const std::string& file, const std::string* bytes, int id, TextureImage& image,
                                     std::vector<Diagnostic>& warnings) {
    namespace fs = std::filesystem;
    const std::string too_large =
        fmt::format("{}x{} texels without tiles, {:.0f} MiB with their MIP levels, more than the {:.0f} MiB the texture cache may hold "
                    "(an eighth of --max-memory)",
                    image.info.width, image.info.height, double(image.memory_bytes()) / (1 << 20), double(cache_bytes_) / (1 << 20));
    const std::string maketx = "'maketx FILE -o FILE.tx' makes a tiled copy, read tile by tile";
    const std::string copy = bytes ? embedded_tiled_copy_path(image.name, *bytes) : tiled_copy_path(file);
    if (copy.empty()) {
        image.error = fmt::format("{}; {}", too_large, maketx);
        return -1;
    }
    const bool band_fits = tiled_copy_memory(image.info) <= cache_bytes_;  // making it holds a band of rows
    std::error_code ec;
    image.tiled_copy = copy;
    // Makes the copy (false with image.error set when it cannot be made). A copy made before,
    // under a larger cache, is read tile by tile all the same.
    auto make = [&] {
        if (!band_fits) {
            image.error = fmt::format("{}; {}", too_large, maketx);
            return false;
        }
        const auto start = std::chrono::steady_clock::now();
        fs::create_directories(fs::path(copy).parent_path(), ec);
        remove_stale_temporaries(copy);
        std::string error;
        const std::string step = fmt::format("a tiled copy of {} ({}x{})", fs::path(image.name).filename().string(), image.info.width, image.info.height);
        auto progress = [&](double done) {
            if (progress_) progress_(step, done);
        };
        // An image embedded in the scene's file (a .glb's) is made a file of its own first.
        const std::string source = bytes ? write_embedded_source(copy, *bytes, error) : file;
        const bool made = !source.empty() && backend_->make_tiled_copy(source, copy, error, progress);
        if (bytes && !source.empty()) fs::remove(source, ec);
        if (!made) {
            image.error = fmt::format("{}, and its tiled copy could not be made at {} ({}); {}", too_large, copy, error, maketx);
            return false;
        }
        image.tiled_copy_made = true;
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        warnings.push_back(run_diagnostic("W312", image.name,
                                          fmt::format("{}: read through a tiled copy made in {:.1f} s at {} ({:.1f} MiB; the folder may "
                                                      "be emptied at any time); a tiled file beside it ({}) or a larger --max-memory "
                                                      "is read directly",
                                                      too_large, seconds, copy, double(fs::file_size(copy, ec)) / (1 << 20), maketx)));
        return true;
    };
    if (!fs::is_regular_file(copy, ec)) {
        if (copies_ == TiledCopies::kFindOnly) {  // what a render would make
            if (band_fits) return id;
            image.error = fmt::format("{}; {}", too_large, maketx);
            return -1;
        }
        if (!make()) return -1;
    }
    TextureImageInfo info;
    std::string error;
    auto open_copy = [&] {
        const int copy_id = backend_->open(copy, nullptr, info, error);
        return copy_id >= 0 && info.width == image.info.width && info.height == image.info.height && info.channels == image.info.channels
                   ? copy_id : -1;
    };
    int copy_id = open_copy();
    if (copy_id < 0 && !image.tiled_copy_made && copies_ == TiledCopies::kMake) {
        // A copy an earlier render left that cannot be read now (damaged, or written by another
        // program under its name): made again, once.
        fs::remove(copy, ec);
        backend_->forget(copy);
        error.clear();
        if (!make()) return -1;
        copy_id = open_copy();
    }
    if (copy_id < 0) {
        image.error = fmt::format("{}, and its tiled copy at {} cannot be read ({}); {}", too_large, copy,
                                  error.empty() ? "not an image of the same size" : error, maketx);
        return -1;
    }
    // The source's own colour space and alpha (a TIFF may not say the sRGB a PNG implies), and
    // the copy's tiles (64x64: an image no larger is one tile, which info.tiled does not count).
    image.info.tiled = true;
    image.info.mip_levels = info.mip_levels;
    return copy_id;
}

SurfaceTextures::Slot SurfaceTextures::open_slot(const std::optional<TextureRef>& ref, SlotKind kind, const Scene& scene,
                                                 std::vector<Diagnostic>& warnings) {
    const bool colour = kind == SlotKind::kColour;
    Slot slot;
    if (!ref) return slot;
    slot.ref = *ref;
    const std::string& name = ref->source();
    auto known = std::find_if(images_.begin(), images_.end(), [&](const TextureImage& i) { return i.name == name; });
    size_t index = static_cast<size_t>(known - images_.begin());
    if (known == images_.end()) {
        TextureImage image;
        image.name = name;
        const std::string* bytes = nullptr;
        if (ref->file.empty()) {
            for (const auto& e : scene.images)
                if (e.name == ref->image) bytes = &e.bytes;
            if (!bytes) image.error = "no embedded image of that name";
        }
        // Only a regular file is opened: a device or a pipe (/dev/zero, a FIFO) never ends.
        std::error_code ec;
        if (image.error.empty() && !ref->file.empty() && !std::filesystem::is_regular_file(ref->file, ec))
            image.error = std::filesystem::exists(ref->file, ec) ? "not a regular file" : "no such file";
        int id = -1;
        if (image.error.empty()) id = backend_->open(name, bytes, image.info, image.error);
        // An image without tiles is read whole, and its MIP levels made whole, whatever the
        // cache's limit: a 2.6 MB PNG of 30000x30000 texels held 6.9 GB. One larger than the
        // cache may hold is read through a tiled copy, tile by tile within the limit.
        if (id >= 0 && !image.info.tiled && image.memory_bytes() > cache_bytes_) id = open_tiled_copy(ref->file, bytes, id, image, warnings);
        if (id < 0)
            warnings.push_back(run_diagnostic("W310", name, fmt::format("texture cannot be read ({}): it renders magenta where it gives a colour", image.error)));
        ids_.push_back(id);
        images_.push_back(image);
        index = images_.size() - 1;
    }
    const TextureImage& image = images_[index];
    if (ids_[index] < 0) {
        slot.image = kMissing;
        return slot;
    }
    if (slot.ref.prefer_alpha && image.info.alpha_channel >= 0) slot.ref.channel = image.info.alpha_channel;
    // A channel the image does not have: an opacity from the alpha of an image without one
    // (glTF's RGB base colour) is opaque, as glTF says; anything else is a warning.
    const int needed = kind == SlotKind::kVector ? 3 : 1;
    if (slot.ref.channel + needed > image.info.channels) {
        if (kind != SlotKind::kOpacity)
            warnings.push_back(run_diagnostic("W311", name,
                                              fmt::format("texture has {} channel{}, not channel {}{}: the material's constant is used instead",
                                                          image.info.channels, image.info.channels == 1 ? "" : "s", slot.ref.channel,
                                                          needed > 1 ? fmt::format(" and the {} after it", needed - 1) : "")));
        slot.image = kNone;
        return slot;
    }
    slot.image = static_cast<int>(index);
    slot.srgb = colour ? (ref->color_space == TextureColorSpace::kAuto ? image.info.srgb : ref->color_space == TextureColorSpace::kSrgb)
                       : ref->color_space == TextureColorSpace::kSrgb;
    slot.grey = colour && image.info.channels - slot.ref.channel < 3;
    return slot;
}

TextureLookup SurfaceTextures::coordinates(const Slot& slot, const SurfacePoint& p) const {
    const TextureRef& r = slot.ref;
    double u = p.u, v = p.v, dudx = p.dudx, dvdx = p.dvdx, dudy = p.dudy, dvdy = p.dvdy;
    if (r.mapping == TextureMapping::kPlanar) {
        const Vec3 a{r.planar[0], r.planar[1], r.planar[2]}, b{r.planar[4], r.planar[5], r.planar[6]};
        u = dot(a, p.position) + r.planar[3], v = dot(b, p.position) + r.planar[7];
        dudx = dot(a, p.dpdx), dvdx = dot(b, p.dpdx), dudy = dot(a, p.dpdy), dvdy = dot(b, p.dpdy);
    }
    const UvTransform& m = r.uv_transform;
    TextureLookup at;
    at.s = static_cast<float>(m[0] * u + m[1] * v + m[2]);
    at.t = static_cast<float>(m[3] * u + m[4] * v + m[5]);
    at.dsdx = static_cast<float>(m[0] * dudx + m[1] * dvdx);
    at.dtdx = static_cast<float>(m[3] * dudx + m[4] * dvdx);
    at.dsdy = static_cast<float>(m[0] * dudy + m[1] * dvdy);
    at.dtdy = static_cast<float>(m[3] * dudy + m[4] * dvdy);
    // Coordinates beyond float's reach (a planar mapping far away) read the texture's centre.
    if (!std::isfinite(at.s) || !std::isfinite(at.t)) at = TextureLookup{0.5f, 0.5f};
    if (!std::isfinite(at.dsdx + at.dtdx + at.dsdy + at.dtdy)) at.dsdx = at.dtdx = at.dsdy = at.dtdy = 0;
    at.indirect = p.indirect;
    at.nearest = r.filter == TextureFilter::kNearest;
    return at;
}

const SurfaceTextures::CoarseImage& SurfaceTextures::coarse_image(size_t image) const {
    CoarseImage& c = *coarse_[image];
    std::call_once(c.once, [&] {
        const TextureImageInfo& info = images_[image].info;
        if (ids_[image] < 0 || info.width <= 0 || info.height <= 0 || info.channels <= 0) return;
        // The first MIP level no larger than kCoarseSize a side (OpenImageIO halves each side,
        // rounding down, to at least 1), each texel the backend's filtered lookup over its own
        // footprint: the same filter as an indirect lookup of that footprint.
        int level = 0;
        while ((info.width >> level) > kCoarseSize || (info.height >> level) > kCoarseSize) ++level;
        c.width = std::max(1, info.width >> level), c.height = std::max(1, info.height >> level);
        c.channels = std::min(info.channels, 4);
        c.texels.assign(static_cast<size_t>(c.width) * static_cast<size_t>(c.height) * static_cast<size_t>(c.channels), 0.0f);
        TextureLookup at;
        at.indirect = true;
        at.dsdx = 1.0f / static_cast<float>(c.width), at.dtdy = 1.0f / static_cast<float>(c.height);
        for (int y = 0; y < c.height; ++y)
            for (int x = 0; x < c.width; ++x) {
                at.s = (static_cast<float>(x) + 0.5f) * at.dsdx, at.t = (static_cast<float>(y) + 0.5f) * at.dtdy;
                float* texel = c.texels.data() + (static_cast<size_t>(y) * static_cast<size_t>(c.width) + static_cast<size_t>(x)) * static_cast<size_t>(c.channels);
                if (!backend_->lookup(ids_[image], at, BackendWrap::kClamp, BackendWrap::kClamp, 0, c.channels, texel)) return;
            }
        for (float v : c.texels)
            if (!std::isfinite(v)) return;
        c.ok = true;
    });
    return c;
}

bool SurfaceTextures::read_coarse(const Slot& slot, const TextureLookup& at, int first_channel, int n, float* out) const {
    const CoarseImage& c = coarse_image(static_cast<size_t>(slot.image));
    if (!c.ok || first_channel < 0 || first_channel + n > c.channels) return false;
    return bilinear(c.texels.data(), c.width, c.height, c.channels, first_channel, n, 1.0f, at, slot.ref, out);
}

bool SurfaceTextures::read(const Slot& slot, const SurfacePoint& p, int n, float* out, float* d_ds, float* d_dt) const {
    const TextureLookup at = coordinates(slot, p);
    const int channels = slot.grey ? 1 : n;
    if (slot.mask >= 0 && channels == 1 && !d_ds && !d_dt && at.dsdx == 0 && at.dtdx == 0 && at.dsdy == 0 && at.dtdy == 0) {
        const OpacityMask& m = opacity_mask(slot.mask);
        const bool read = m.ok && (m.bytes.empty() ? bilinear(m.floats.data(), m.width, m.height, 1, 0, 1, 1.0f, at, slot.ref, out)
                                                   : bilinear(m.bytes.data(), m.width, m.height, 1, 0, 1, 1.0f / 255, at, slot.ref, out));
        if (read) {
            ++counters_.local().mask_lookups;
            if (channels < n) out[1] = out[2] = out[0];
            return true;
        }
    }
    if (p.coarse && !d_ds && !d_dt && read_coarse(slot, at, slot.ref.channel, channels, out)) {
        ++counters_.local().coarse_lookups;
        if (channels < n) out[1] = out[2] = out[0];
        return true;
    }
    // Every lookup is timed: the first ones of an image read and MIP-map it (milliseconds),
    // so a sample of them would not stand for the rest. Two clock reads cost ~40 ns.
    Counters& c = counters_.local();
    ++c.lookups;
    const auto start = std::chrono::steady_clock::now();
    bool ok = backend_->lookup(ids_[static_cast<size_t>(slot.image)], at, wrap_of(slot.ref.wrap_s), wrap_of(slot.ref.wrap_t), slot.ref.channel,
                               channels, out, d_ds, d_dt);
    c.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!ok) failed_lookups_[static_cast<size_t>(slot.image)].fetch_add(1, std::memory_order_relaxed);
    // NaN or infinite texels in the file. Filtering spreads one to every lookup whose footprint
    // or coarser MIP level holds it (one NaN texel blackened a whole plane), so such a lookup
    // is asked again of the nearest texel of the finest level, and only what is still not
    // finite reads as 0. Counted, so the render can say so. (The coarse copy and the opacity
    // masks are made only from finite texels.)
    if (ok && !std::all_of(out, out + channels, [](float v) { return std::isfinite(v); })) {
        non_finite_lookups_[static_cast<size_t>(slot.image)].fetch_add(1, std::memory_order_relaxed);
        TextureLookup nearest = at;
        nearest.dsdx = nearest.dtdx = nearest.dsdy = nearest.dtdy = 0;
        nearest.indirect = false, nearest.nearest = true;
        float again[4] = {0, 0, 0, 0};
        const bool retried = channels <= 4 && backend_->lookup(ids_[static_cast<size_t>(slot.image)], nearest, wrap_of(slot.ref.wrap_s),
                                                               wrap_of(slot.ref.wrap_t), slot.ref.channel, channels, again);
        for (int k = 0; k < channels; ++k)
            if (!std::isfinite(out[k])) out[k] = retried && std::isfinite(again[k]) ? again[k] : 0.0f;
    }
    for (float* d : {d_ds, d_dt})
        if (ok && d)
            for (int k = 0; k < channels; ++k)
                if (!std::isfinite(d[k])) d[k] = 0;
    if (ok && channels < n) out[1] = out[2] = out[0];
    return ok;
}

Vec3 SurfaceTextures::colour(const Slot& slot, const SurfacePoint& p, const Vec3& constant) const {
    if (slot.image == kNone) return constant;
    if (slot.image == kMissing) return {1, 0, 1};  // magenta: seen, not mistaken for the material
    float texel[3] = {0, 0, 0};
    if (!read(slot, p, 3, texel)) return {1, 0, 1};
    Vec3 c{texel[0], texel[1], texel[2]};
    if (slot.srgb) c = {srgb_to_linear(c.x), srgb_to_linear(c.y), srgb_to_linear(c.z)};
    c = vmax(c, Vec3{}) * slot.ref.scale;
    if (slot.ref.power != 1) c = {std::pow(c.x, slot.ref.power), std::pow(c.y, slot.ref.power), std::pow(c.z, slot.ref.power)};
    return is_finite(c) ? c : Vec3{};
}

double SurfaceTextures::scalar(const Slot& slot, const SurfacePoint& p, double constant) const {
    if (slot.image < 0) return constant;
    float texel = 0;
    if (!read(slot, p, 1, &texel)) return constant;
    double x = max_of(static_cast<double>(texel), 0.0);
    if (slot.srgb) x = srgb_to_linear(x);
    x *= slot.ref.scale.x;
    if (slot.ref.power != 1) x = std::pow(x, slot.ref.power);
    return std::isfinite(x) ? x : constant;
}

MaterialValues SurfaceTextures::values(uint32_t m, const SurfacePoint& p) const {
    const Material& mat = scene_.materials[m];
    MaterialValues v = constant_values(mat);
    const MaterialSlots& s = slots_[m];
    if (!s.any) return v;
    if (s.color.image != kNone) {
        const bool emitter = mat.type == MaterialType::kLight || mat.type == MaterialType::kGlow;
        const Vec3 c = colour(s.color, p, mat.color);
        v.color = emitter ? vmin(c, Vec3{kMaxRadiance, kMaxRadiance, kMaxRadiance}) : clamp01(c);  // reflectance above 1 makes light
    }
    if (s.specular_color.image != kNone) v.specular_tint = clamp01(colour(s.specular_color, p, {1, 1, 1}));
    v.specularity = clamp01(scalar(s.specularity, p, mat.specularity));
    if (s.roughness.image != kNone) v.roughness = std::clamp(scalar(s.roughness, p, mat.roughness), kMinTexturedRoughness, 1.0);
    v.metallic = clamp01(scalar(s.metallic, p, mat.metallic));
    if (s.emission.image != kNone) v.emission = emission(m, p);
    return v;
}

Vec3 SurfaceTextures::emission(uint32_t m, const SurfacePoint& p) const {
    const Material& mat = scene_.materials[m];
    const Vec3 constant = mat.emission.value_or(Vec3{});
    if (slots_[m].emission.image == kNone) return constant;
    return vmin(colour(slots_[m].emission, p, constant), Vec3{kMaxRadiance, kMaxRadiance, kMaxRadiance});
}

double SurfaceTextures::opacity(uint32_t m, const SurfacePoint& p) const {
    const Slot& slot = slots_[m].opacity;
    return clamp01(scalar(slot, p, scene_.materials[m].opacity));
}

Vec3 SurfaceTextures::perturbed_normal(uint32_t m, const SurfacePoint& p, const Vec3& n, const Vec3& dpdu, const Vec3& dpdv) const {
    const MaterialSlots& s = slots_[m];
    Vec3 out = n;
    // The surface's derivatives in the slot's (s, t): [dpdu dpdv] = [dpds dpdt] A, A the linear
    // part of the slot's uv transform (planar mappings have no mesh derivatives: left flat).
    auto in_texture_space = [&](const Slot& slot, Vec3& dpds, Vec3& dpdt) {
        if (slot.ref.mapping != TextureMapping::kUv || dpdu == Vec3{} || dpdv == Vec3{}) return false;
        const UvTransform& a = slot.ref.uv_transform;
        const double det = a[0] * a[4] - a[1] * a[3];
        if (!(std::fabs(det) > 1e-12)) return false;
        dpds = (dpdu * a[4] - dpdv * a[3]) / det;
        dpdt = (dpdv * a[0] - dpdu * a[1]) / det;
        return is_finite(dpds) && is_finite(dpdt);
    };
    Vec3 dpds, dpdt;
    if (s.normal.image >= 0 && in_texture_space(s.normal, dpds, dpdt)) {
        float texel[3] = {0.5f, 0.5f, 1.0f};
        if (read(s.normal, p, 3, texel)) {
            const double k = s.normal.ref.scale.x;
            const double x = (2.0 * texel[0] - 1.0) * k, y = (2.0 * texel[1] - 1.0) * k, z = 2.0 * texel[2] - 1.0;
            if (std::fabs(x) > kFlatNormal || std::fabs(y) > kFlatNormal) {
                // Tangent along +s; the map's +y is up in the image, which is -t (t = 0 is the top row).
                const Vec3 t = normalize_or_zero(dpds - n * dot(n, dpds));
                Vec3 b = -dpdt;
                b = normalize_or_zero(b - n * dot(n, b) - t * dot(t, b));
                const Vec3 bent = normalize_or_zero(t * x + b * y + n * max_of(z, 0.0));
                if (t != Vec3{} && b != Vec3{} && dot(bent, n) > 0) out = bent;
            }
        }
    }
    if (s.bump.image >= 0 && in_texture_space(s.bump, dpds, dpdt)) {
        float h = 0, dh_ds = 0, dh_dt = 0;
        if (read(s.bump, p, 1, &h, &dh_ds, &dh_dt)) {
            // The surface displaced by height x scale along its normal: its new tangents, crossed.
            const double k = s.bump.ref.scale.x;
            const Vec3 ts = dpds + out * (k * dh_ds), tt = dpdt + out * (k * dh_dt);
            Vec3 bent = normalize_or_zero(cross(ts, tt));
            if (dot(bent, out) < 0) bent = -bent;
            if (bent != Vec3{} && (dh_ds != 0 || dh_dt != 0)) out = bent;
        }
    }
    return out;
}

std::string image_text(const TextureImage& i) {
    std::string text = fmt::format("{}  {}x{}, {} channel{}, {}, {:.1f} KiB on disk, {:.1f} MiB in memory\n", i.name, i.info.width, i.info.height,
                                   i.info.channels, i.info.channels == 1 ? "" : "s", i.info.format, double(i.info.file_bytes) / 1024.0,
                                   double(i.memory_bytes()) / double(1 << 20));
    if (!i.tiled_copy.empty())
        text += fmt::format("      no tiles and larger than the cache: read through {} tiled copy at {}\n",
                            i.info.tiled ? "the" : "the first render's", i.tiled_copy);
    return text;
}

nlohmann::json images_json(const std::vector<TextureImage>& images) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& i : images) {
        nlohmann::json e = {{"name", i.name}};
        if (!i.error.empty()) {
            e["error"] = i.error;
        } else {
            e["width"] = i.info.width, e["height"] = i.info.height, e["channels"] = i.info.channels;
            e["format"] = i.info.format, e["file_bytes"] = i.info.file_bytes;
            e["memory_bytes"] = i.memory_bytes(), e["tiled"] = i.info.tiled, e["mip_levels"] = i.info.mip_levels;
            if (i.failed_lookups > 0) e["failed_lookups"] = i.failed_lookups;
            if (i.non_finite_lookups > 0) e["non_finite_lookups"] = i.non_finite_lookups;
            if (!i.tiled_copy.empty()) e["tiled_copy"] = i.tiled_copy, e["tiled_copy_made"] = i.tiled_copy_made;
        }
        out.push_back(e);
    }
    return out;
}

nlohmann::json to_json(const TextureStats& s, double render_thread_seconds, double render_cpu_seconds) {
    nlohmann::json j;
    j["images"] = images_json(s.images);
    j["cache"] = {{"memory_limit_bytes", s.cache.memory_limit}, {"memory_bytes", s.cache.memory_bytes},
                  {"bytes_read", s.cache.bytes_read},         {"tiles_peak", s.cache.tiles_peak},
                  {"tile_misses", s.cache.cache_misses},      {"files", s.cache.files},
                  {"file_io_seconds", s.cache.file_io_seconds}, {"queries", s.cache.queries}};
    j["lookups"] = s.lookups;
    j["lookup_seconds"] = s.lookup_seconds;
    j["coarse_lookups"] = s.coarse_lookups;
    j["mask_lookups"] = s.mask_lookups;
    j["mask_bytes"] = s.mask_bytes;
    j["render_thread_seconds"] = render_thread_seconds;
    j["render_cpu_seconds"] = render_cpu_seconds;
    j["lookup_share_of_render"] = render_thread_seconds > 0 ? s.lookup_seconds / render_thread_seconds : 0.0;
    return j;
}

TextureStats SurfaceTextures::stats() const {
    TextureStats s;
    s.images = images_;
    for (size_t i = 0; i < s.images.size(); ++i) {
        s.images[i].failed_lookups = failed_lookups_[i].load(std::memory_order_relaxed);
        s.images[i].non_finite_lookups = non_finite_lookups_[i].load(std::memory_order_relaxed);
    }
    if (backend_) s.cache = backend_->stats();
    for (const Counters& c : counters_)
        s.lookups += c.lookups, s.lookup_seconds += c.seconds, s.coarse_lookups += c.coarse_lookups, s.mask_lookups += c.mask_lookups;
    s.mask_bytes = mask_bytes_;
    return s;
}

TextureStats TextureStats::since(const TextureStats& earlier) const {
    TextureStats s = *this;
    for (size_t i = 0; i < s.images.size() && i < earlier.images.size(); ++i) {
        s.images[i].failed_lookups -= std::min(earlier.images[i].failed_lookups, s.images[i].failed_lookups);
        s.images[i].non_finite_lookups -= std::min(earlier.images[i].non_finite_lookups, s.images[i].non_finite_lookups);
    }
    s.lookups -= std::min(earlier.lookups, lookups);
    s.lookup_seconds = std::max(0.0, lookup_seconds - earlier.lookup_seconds);
    s.coarse_lookups -= std::min(earlier.coarse_lookups, coarse_lookups);
    s.mask_lookups -= std::min(earlier.mask_lookups, mask_lookups);
    s.cache.queries -= std::min(earlier.cache.queries, cache.queries);
    s.cache.bytes_read -= std::min(earlier.cache.bytes_read, cache.bytes_read);
    s.cache.cache_misses -= std::min(earlier.cache.cache_misses, cache.cache_misses);
    s.cache.file_io_seconds = std::max(0.0, cache.file_io_seconds - earlier.cache.file_io_seconds);
    return s;
}

}  // namespace crex
