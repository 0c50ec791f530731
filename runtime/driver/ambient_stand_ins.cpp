#include "runtime/driver/ambient_stand_ins.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "runtime/render/camera_samples.h"

namespace crex {
namespace {

// ambient += av x the throughput left unexecuted per pixel (RGB).
void add_stand_in(const std::vector<float>& left, const Vec3& av, std::vector<double>& ambient) {
    // Every pixel its own sum, so threads change no bit; at the end of a render this is on
    // the budget's clock.
    const size_t pixels = std::min(left.size(), ambient.size()) / 3;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, pixels, 1 << 13), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = 3 * r.begin(); i < 3 * r.end(); i += 3) {
            ambient[i] += av.x * left[i];
            ambient[i + 1] += av.y * left[i + 1];
            ambient[i + 2] += av.z * left[i + 2];
        }
    });
}

// What the executed rays of component c found in pixels [p0, p1) (sample-summed RGB). The
// film's sums as they are: dividing each pixel by its count and multiplying back was most of
// a short render's end (6 ms at 384x288).
Vec3 found_by(const Film& film, size_t c, size_t p0, size_t p1) {
    return film.aov_total(aov_of(static_cast<Component>(c)), static_cast<uint32_t>(p0), static_cast<uint32_t>(p1));
}

// The end of an automatic render reads the film on the budget's clock: over fixed chunks of
// pixels in parallel, each chunk's sums kept apart and added in chunk order (so the totals do
// not depend on the thread count), every buffer in one pass.
constexpr size_t kSumChunk = size_t{1} << 14;  // pixels

// sums[0..3): the image's RGB over pixels [p0, p1) (non-finite values as 0); sums[3 + 6c ..+3):
// what component c's executed rays found there (the film's sample sums; none for an AOV the
// film does not keep).
void image_and_found_sums(const std::vector<float>& image, const std::array<const double*, kComponentCount>& found, size_t p0, size_t p1,
                          std::vector<double>& sums) {
    const size_t n = p1 > p0 ? p1 - p0 : 0, chunks = (n + kSumChunk - 1) / kSumChunk;
    constexpr size_t kPerChunk = 3 + 3 * kComponentCount;
    std::vector<double> partial(chunks * kPerChunk, 0.0);
    tbb::parallel_for(size_t{0}, chunks, [&](size_t k) {
        double* out = &partial[k * kPerChunk];
        const size_t a = p0 + k * kSumChunk, b = std::min(p1, a + kSumChunk);
        double s0 = 0, s1 = 0, s2 = 0;
        for (size_t i = 3 * a; i < 3 * b; i += 3) {
            s0 += std::isfinite(image[i]) ? image[i] : 0.0f;
            s1 += std::isfinite(image[i + 1]) ? image[i + 1] : 0.0f;
            s2 += std::isfinite(image[i + 2]) ? image[i + 2] : 0.0f;
        }
        out[0] = s0, out[1] = s1, out[2] = s2;
        for (size_t c = 0; c < kComponentCount; ++c) {
            const double* f = found[c];
            if (!f) continue;
            double f0 = 0, f1 = 0, f2 = 0;
            for (size_t i = 3 * a; i < 3 * b; i += 3) f0 += f[i], f1 += f[i + 1], f2 += f[i + 2];
            out[3 + 3 * c] = f0, out[4 + 3 * c] = f1, out[5 + 3 * c] = f2;
        }
    });
    for (size_t k = 0; k < chunks; ++k) {
        const double* in = &partial[k * kPerChunk];
        for (size_t j = 0; j < 3; ++j) sums[j] += in[j];
        for (size_t c = 0; c < kComponentCount; ++c)
            for (size_t j = 0; j < 3; ++j) sums[3 + 6 * c + j] += in[3 + 3 * c + j];
    }
}

// ambient += av[c] x component c's throughput left, for every component `applied`, per pixel in
// component order: the same sums as one add_stand_in per component, bit for bit, in one pass
// over the ambient buffer instead of one per component (measured: the end of a budgeted cbtcr
// render at 512x384 took 9-11 ms, most of it these passes).
void add_stand_ins(const std::array<std::vector<float>, kComponentCount>& left, const std::array<Vec3, kComponentCount>& av,
                   const std::array<bool, kComponentCount>& applied, std::vector<double>& ambient) {
    std::array<const float*, kComponentCount> from{};
    std::array<Vec3, kComponentCount> with{};
    size_t used = 0, pixels = ambient.size() / 3;
    for (size_t c = 0; c < kComponentCount; ++c)
        if (applied[c] && !left[c].empty()) from[used] = left[c].data(), with[used] = av[c], ++used, pixels = std::min(pixels, left[c].size() / 3);
    if (used == 0) return;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, pixels, 1 << 13), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = 3 * r.begin(); i < 3 * r.end(); i += 3) {
            double a0 = ambient[i], a1 = ambient[i + 1], a2 = ambient[i + 2];
            for (size_t u = 0; u < used; ++u) {
                const float* l = from[u];
                a0 += with[u].x * l[i], a1 += with[u].y * l[i + 1], a2 += with[u].z * l[i + 2];
            }
            ambient[i] = a0, ambient[i + 1] = a1, ambient[i + 2] = a2;
        }
    });
}

}  // namespace

AmbientStandIns::AmbientStandIns(size_t pixels, const Vec3& av, bool automatic)
    // Decided from the settings alone, so alike on every process of a group.
    : pixels_(pixels), av_(av), automatic_(automatic), ambient_(per_pixel(av, automatic) ? 3 * pixels : 0, 0.0) {}

void AmbientStandIns::keep(const std::array<bool, kComponentCount>& components) {
    if (!automatic_) return;
    for (size_t c = 0; c < kComponentCount; ++c)
        if (components[c] && left_[c].empty()) left_[c].assign(3 * pixels_, 0.0f);
}

void AmbientStandIns::flush(std::array<RayBatch, kComponentCount>& bins, std::array<size_t, kComponentCount>& left_count) {
    for (size_t c = 0; c < kComponentCount; ++c) {
        RayBatch& bin = bins[c];
        if (automatic_ && !bin.empty()) {
            std::vector<float>& left = left_[c];
            if (left.empty()) left.assign(3 * pixels_, 0.0f);
            for (size_t i = 0; i < bin.size(); ++i) {
                float* l = &left[3 * static_cast<size_t>(bin.pixel[i])];
                l[0] += bin.br[i], l[1] += bin.bg[i], l[2] += bin.bb[i];
            }
            flushed_[c] += bin.size();
        } else if (c == static_cast<size_t>(Component::kD)) {
            add_ambient(bin, av_, ambient_);
        }
        left_count[c] += bin.size();
        bin = RayBatch();  // freed: bins kept at their largest would add up over passes
    }
}

std::vector<double> AmbientStandIns::if_stopped_now(const Film& film, const ExecutorStats& stats,
                                                    const std::array<RayBatch, kComponentCount>& waiting,
                                                    const std::array<RayBatch, kComponentCount>& carried) const {
    std::vector<double> ambient = ambient_;
    if (automatic_) {
        // The image if the render stopped here: rays still waiting (this pass's, the preview's
        // carried ones, those dropped at earlier passes' ends) stand in with what their
        // component's rays brought back so far, as at the end of a render. Without this a
        // checkpoint inside a pass counted its new samples with only their camera light and
        // the error curve rose through every pass (issue 17).
        for (size_t c = 0; c < kComponentCount; ++c) {
            const double* beta = stats.components[c].beta;
            if (!(beta[0] + beta[1] + beta[2] > 0)) continue;
            const Vec3 av = per_unit(found_by(film, c, 0, film.pixel_count()), {beta[0], beta[1], beta[2]});
            add_ambient(waiting[c], av, ambient);
            add_ambient(carried[c], av, ambient);
            add_stand_in(left_[c], av, ambient);
        }
    } else {
        add_ambient(waiting[static_cast<size_t>(Component::kD)], av_, ambient);
        add_ambient(carried[static_cast<size_t>(Component::kD)], av_, ambient);
    }
    return ambient;
}

void AmbientStandIns::finish_automatic(const Film& film, const ExecutorStats& stats, const std::vector<float>& image_before, size_t p0,
                                       size_t p1, ProcessGroup* group, std::array<Vec3, kComponentCount>& auto_ambient,
                                       std::vector<std::string>& notes) {
    // Over this process's rows: distributed, each pixel is final in the band of the process
    // that rendered the last stage there, so the sums over every process's rows are those of
    // the whole image, and what every process's rays did stands in for every process's rays.
    // sums: the image's radiance summed (3), then per component what its executed rays found
    // (3) and their throughput (3), then per component the rays left (1).
    std::vector<double> sums(3 + 7 * kComponentCount, 0.0);
    std::array<const double*, kComponentCount> found{};
    for (size_t c = 0; c < kComponentCount; ++c) found[c] = film.aov_sums(aov_of(static_cast<Component>(c)));
    image_and_found_sums(image_before, found, p0, p1, sums);
    for (size_t c = 0; c < kComponentCount; ++c) {
        const double* beta = stats.components[c].beta;
        double* at = &sums[3 + 6 * c];
        at[3] = beta[0], at[4] = beta[1], at[5] = beta[2];
        sums[3 + 6 * kComponentCount + c] = static_cast<double>(flushed_[c]);
    }
    if (group) group->sum(sums);
    const Vec3 mean = Vec3{sums[0], sums[1], sums[2]} / double(std::max<size_t>(pixels_, 1));
    std::array<Vec3, kComponentCount> av_of_left{};
    std::array<bool, kComponentCount> applied{};
    std::string unmeasured;  // the components none of whose rays ran: one note for them all
    for (size_t c = 0; c < kComponentCount; ++c) {
        // Whether any process left rays of c, from the counts: a scan of the buffers for a
        // non-zero value was a serial pass over up to 1.3 MB per component at 384x288 on the
        // budget's clock. A process with none of its own adds zeros.
        if (!(sums[3 + 6 * kComponentCount + c] > 0)) continue;
        const double* at = &sums[3 + 6 * c];
        const bool measured = at[3] + at[4] + at[5] > 0;
        const Vec3 av = measured ? per_unit({at[0], at[1], at[2]}, {at[3], at[4], at[5]}) : mean;
        auto_ambient[c] = av_of_left[c] = av;
        applied[c] = true;
        if (measured)
            notes.push_back(fmt::format("unexecuted {} rays stood in with av = ({:.3g}, {:.3g}, {:.3g}), what its executed rays brought back "
                                        "per unit throughput",
                                        kComponentTable[c].letter, av.x, av.y, av.z));
        else
            unmeasured += kComponentTable[c].letter;
    }
    if (!unmeasured.empty()) {
        std::string letters;  // "G", "G and S", "G, S and R"
        for (size_t i = 0; i < unmeasured.size(); ++i)
            letters += (i == 0 ? "" : i + 1 == unmeasured.size() ? " and " : ", ") + std::string(1, unmeasured[i]);
        notes.push_back(fmt::format("unexecuted {} rays stood in with av = ({:.3g}, {:.3g}, {:.3g}), the mean radiance of the image (none of {} "
                                    "rays ran)",
                                    letters, mean.x, mean.y, mean.z, unmeasured.size() == 1 ? "its" : "their"));
    }
    add_stand_ins(left_, av_of_left, applied, ambient_);
    // The buffers stay until release(), after the render's clock: freeing megabytes is time too.
    flushed_ = {};
}

void AmbientStandIns::leave_everywhere(float throughput) {
    for (size_t c = 0; c < kComponentCount; ++c) {
        left_[c].assign(3 * pixels_, throughput);
        flushed_[c] += pixels_;
    }
}

void AmbientStandIns::release() {
    for (auto& left : left_) left = {};
}

}  // namespace crex
