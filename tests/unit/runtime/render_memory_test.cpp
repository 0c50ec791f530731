// What a render is refused by before it allocates (runtime/base/memory.h) and what its film
// is counted as (Film::bytes_per_pixel, the memory model's film).
#include <gtest/gtest.h>

#include "runtime/base/memory.h"
#include "runtime/render/film.h"

namespace crex {
namespace {

TEST(MemoryAvailable, IsMemAvailablePlusSwapFreeFromMeminfo) {
    const std::string meminfo =
        "MemTotal:       24576000 kB\nMemFree:         1000000 kB\nMemAvailable:   20000000 kB\n"
        "Buffers:           1234 kB\nSwapTotal:       2048000 kB\nSwapFree:        1024000 kB\n";
    EXPECT_EQ(memory_available_bytes(meminfo), size_t{21024000} * 1024);
    // Without swap lines: the memory alone. Without MemAvailable (kernels before 3.14): unknown.
    EXPECT_EQ(memory_available_bytes("MemAvailable:   100 kB\n"), size_t{100} * 1024);
    EXPECT_EQ(memory_available_bytes("MemTotal:       24576000 kB\nMemFree:         1000000 kB\n"), std::nullopt);
    EXPECT_EQ(memory_available_bytes(""), std::nullopt);
}

TEST(MemoryAvailable, ThisMachineSaysSomething) {
    const auto bytes = memory_available_bytes();
    ASSERT_TRUE(bytes.has_value());
    EXPECT_GT(*bytes, size_t{64} << 20);
}

// The model counts what the film allocates: every buffer for_each_buffer shares, in every
// layout, with and without capict's tracked branches.
TEST(FilmBytes, CountEveryPerPixelBuffer) {
    const FilmLayout d_only{0b011, false, true};
    for (const FilmLayout& layout : {FilmLayout{}, FilmLayout::minimal(), d_only})
        for (uint8_t tracked : {uint8_t{0}, uint8_t{0b1}, uint8_t{0b1011}}) {
            Film film(5, 3, layout);
            if (tracked) film.track_branches(tracked);
            size_t per_pixel = 0;
            film.for_each_buffer([&](void*, size_t bytes) { per_pixel += bytes; });
            EXPECT_EQ(Film::bytes_per_pixel(layout, tracked), per_pixel) << int(tracked) << " " << int(layout.aovs);
        }
    EXPECT_EQ(Film::bytes_per_pixel(FilmLayout{}) - Film::bytes_per_pixel(FilmLayout::minimal()), (6 + 2) * 24u + 4u);
}

// A film without a component's sum adds that component's light to the camera's: the
// composite is the same, and the component's image is empty.
TEST(FilmLayout, LightOfAnAovWithoutASumGoesToTheComposite) {
    Film every(2, 1), minimal(2, 1, FilmLayout::minimal());
    for (Film* f : {&every, &minimal}) {
        f->add_sample(0, false), f->add_sample(1, true);
        f->add(kCameraAov, 0, {1, 2, 3}), f->add(aov_of(Component::kD), 0, {0.5, 0.25, 0.125});
        f->add(aov_of(Component::kS), 1, {2, 0, 1}, kRayOddSample);
    }
    EXPECT_EQ(every.composite(), minimal.composite());
    EXPECT_TRUE(minimal.aov_image(aov_of(Component::kD)).empty());
    EXPECT_EQ(every.aov_image(aov_of(Component::kD))[0], 0.5f);
    EXPECT_EQ(minimal.aov_image(kCameraAov)[0], 1.5f);  // "the rest": the camera's and D's
}

}  // namespace
}  // namespace crex
