// The guidance operators at 1920x1080 on one core (issue 34: they must be fast enough to be
// invisible next to a render):
//   build/release/bench/guidance_bench --benchmark_repetitions=3
// Every operator runs on the same deterministic synthetic frame: smooth gradients, a few
// discs and boxes of distinct colours, and per-pixel noise from a fixed hash. items/s are
// pixels per second. `--dump=DIR` instead writes each operator's map to DIR/<name>.f32 (raw
// float32, row-major, 1920x1080), so two builds' outputs can be compared value by value.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <string>
#include <vector>

#include "stdlib/guidance/filters.h"
#include "stdlib/guidance/operators.h"

namespace {

using namespace crex::guidance;

constexpr int kWidth = 1920, kHeight = 1080;
constexpr double kFovea = 2 * std::numbers::pi / 180;  // the runtime's default fovea

// A hash, not a generator: the frame must not depend on the order pixels are visited in.
double hash01(uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    x ^= x >> 31;
    return static_cast<double>(x >> 11) * 0x1.0p-53;
}

struct Shape {
    double cx, cy, r;  // a disc, or a box of half-size r when `box`
    bool box;
    float rgb[3];
    int task;  // 1..3: the task set it belongs to
};

std::vector<Shape> shapes() {
    std::vector<Shape> s;
    for (uint64_t i = 0; i < 12; ++i) {
        Shape sh{};
        sh.cx = hash01(4 * i) * kWidth;
        sh.cy = hash01(4 * i + 1) * kHeight;
        sh.r = 30 + hash01(4 * i + 2) * 120;
        sh.box = i % 2 == 1;
        for (int c = 0; c < 3; ++c) sh.rgb[c] = static_cast<float>(hash01(100 + 3 * i + static_cast<uint64_t>(c)));
        sh.task = static_cast<int>(i % 3) + 1;
        s.push_back(sh);
    }
    return s;
}

bool inside(const Shape& s, int x, int y) {
    double dx = x + 0.5 - s.cx, dy = y + 0.5 - s.cy;
    return s.box ? std::fabs(dx) <= s.r && std::fabs(dy) <= s.r * 0.6 : dx * dx + dy * dy <= s.r * s.r;
}

// The display frame (values 0..1); `noise_sign` shifts it by its per-pixel noise, for the
// noise map's two half-buffers.
Raster frame(int noise_sign = 0) {
    Raster img(kWidth, kHeight, 3);
    const std::vector<Shape> sh = shapes();
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            double u = static_cast<double>(x) / kWidth, v = static_cast<double>(y) / kHeight;
            float rgb[3] = {static_cast<float>(0.2 + 0.5 * u), static_cast<float>(0.3 + 0.4 * v), static_cast<float>(0.6 - 0.4 * u * v)};
            for (const Shape& s : sh)
                if (inside(s, x, y)) std::copy(s.rgb, s.rgb + 3, rgb);
            uint64_t p = static_cast<uint64_t>(y) * kWidth + static_cast<uint64_t>(x);
            for (int c = 0; c < 3; ++c) {
                double grain = 0.03 * (hash01(1000003 * p + static_cast<uint64_t>(c)) - 0.5);
                double error = noise_sign * 0.05 * hash01(7777777 * p + static_cast<uint64_t>(c));
                img.at(x, y, c) = std::clamp(static_cast<float>(rgb[c] + grain + error), 0.0f, 1.0f);
            }
        }
    return img;
}

std::vector<std::vector<bool>> task_sets() {
    std::vector<std::vector<bool>> covered(3, std::vector<bool>(static_cast<size_t>(kWidth) * kHeight, false));
    for (const Shape& s : shapes())
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x)
                if (inside(s, x, y)) covered[static_cast<size_t>(s.task - 1)][static_cast<size_t>(y) * kWidth + static_cast<size_t>(x)] = true;
    return covered;
}

// Pixels that see a distractor: the first disc only (the q-buffer map's work grows with
// its area times the foveal disc's).
std::vector<bool> detectable() {
    std::vector<bool> d(static_cast<size_t>(kWidth) * kHeight, false);
    Shape s = shapes()[0];
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) d[static_cast<size_t>(y) * kWidth + static_cast<size_t>(x)] = inside(s, x, y);
    return d;
}

const ViewGeometry kView{kWidth, kHeight, 1.0};

template <class F>
void run(benchmark::State& state, F&& op) {
    for (auto _ : state) {
        Raster m = op();
        benchmark::DoNotOptimize(m.v.data());
    }
    state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * kWidth * kHeight);
}

void BM_Saliency(benchmark::State& state) {
    Raster img = frame();
    run(state, [&] { return saliency(img); });
}

void BM_Edges(benchmark::State& state) {
    Raster img = frame();
    run(state, [&] { return edges(img); });
}

void BM_RadianceDifference(benchmark::State& state) {
    Raster img = frame();
    run(state, [&] { return radiance_difference(img); });
}

// blur(m) of a pipeline: a one-channel map, sigma 2 (the operator's default).
void BM_Blur(benchmark::State& state) {
    Raster map = luminance(frame());
    run(state, [&] { return gaussian_blur(map, 2.0); });
}

void BM_TaskMap(benchmark::State& state) {
    auto covered = task_sets();
    run(state, [&] { return task_map(covered, {1.0 / 3, 2.0 / 3, 1.0}, kView, kFovea); });
}

void BM_DistractorMap(benchmark::State& state) {
    auto seen = detectable();
    run(state, [&] { return distractor_map(seen, kView, kFovea); });
}

void BM_Noise(benchmark::State& state) {
    Raster high = frame(1), low = frame(-1);
    run(state, [&] { return noise_map(high, low); });
}

BENCHMARK(BM_Saliency)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Edges)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RadianceDifference)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Blur)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TaskMap)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DistractorMap)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Noise)->Unit(benchmark::kMillisecond);

void dump(const std::string& dir) {
    auto write = [&](const std::string& name, const Raster& m) {
        std::string path = dir + "/" + name + ".f32";
        if (FILE* f = std::fopen(path.c_str(), "wb")) {
            std::fwrite(m.v.data(), sizeof(float), m.v.size(), f);
            std::fclose(f);
        } else {
            std::fprintf(stderr, "cannot write %s\n", path.c_str());
        }
    };
    Raster img = frame();
    write("saliency", saliency(img));
    write("edges", edges(img));
    write("radiance_difference", radiance_difference(img));
    write("blur", gaussian_blur(luminance(img), 2.0));
    write("task_map", task_map(task_sets(), {1.0 / 3, 2.0 / 3, 1.0}, kView, kFovea));
    write("distractor_map", distractor_map(detectable(), kView, kFovea));
    write("noise", noise_map(frame(1), frame(-1)));
}

}  // namespace

int main(int argc, char** argv) {
    // --dump=DIR is ours (and times nothing); everything else is Google Benchmark's.
    for (int i = 1; i < argc; ++i)
        if (std::strncmp(argv[i], "--dump=", 7) == 0) {
            dump(argv[i] + 7);
            return 0;
        }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
