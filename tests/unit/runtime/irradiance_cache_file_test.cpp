// Damaged irradiance cache files (runtime/cache/irradiance_cache.cpp, cbor_shape.cpp): refused
// with a message naming the file, nothing loaded, and never a crash: deep nesting, indefinite
// lengths and impossible counts are caught before nlohmann's recursive reader sees them;
// records outside the scene or past `bounces` are refused. (Round trips and settings:
// tests/numerics/irradiance_cache_test.cpp.)
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

#include "runtime/cache/irradiance_cache.h"
#include "runtime/render/render_scene.h"
#include "runtime/scene/load_scene.h"
#include "tests/support/test_scenes.h"

namespace crex {
namespace {

namespace fs = std::filesystem;

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void spill(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << bytes;
}

class IrradianceCacheFile : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("crex_ic_file_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
        settings_.divisions = 64, settings_.bounces = 2, settings_.ambient = {0.1, 0.2, 0.3};
        // Records of every field's range, as the cache makes them: inside the scene, unit
        // normals, E >= 0, R > 0, levels up to `bounces`.
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> u(-1, 1);
        for (int i = 0; i < 40; ++i) {
            IrradianceRecord r;
            r.position = {u(rng), u(rng), u(rng)};
            r.normal = normalize_or_zero(Vec3{u(rng), u(rng), 1.5});
            r.irradiance = {1 + u(rng), 2 + u(rng), 3 + u(rng)};
            r.harmonic_distance = 0.1 + 0.05 * u(rng);
            for (auto& g : r.rotation) g = {u(rng), u(rng), u(rng)};
            for (auto& g : r.translation) g = {u(rng), u(rng), u(rng)};
            r.quality = static_cast<float>(0.2 + 0.1 * u(rng));
            r.level = static_cast<uint16_t>(i % 3);
            records_.push_back(r);
        }
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string path(const std::string& f) const { return (dir_ / f).string(); }
    std::string save(const std::string& name, const std::vector<IrradianceRecord>& records) {
        IrradianceCache c(scene_, settings_);
        for (const auto& r : records) c.insert(r);
        std::string file = path(name);
        EXPECT_EQ(c.save(file), "");
        return file;
    }
    fs::path dir_;
    Scene cornell_ = *builtin_scene("cornell_diffuse");
    RenderScene scene_{cornell_};
    IcSettings settings_;
    std::vector<IrradianceRecord> records_;
};

TEST_F(IrradianceCacheFile, RecordsOutsideTheSceneOrPastItsBouncesAreRefused) {
    auto far = records_;
    far[3].position = {1e12, 0, 0};  // would send insert()'s grid indices past int
    auto deep = records_;
    deep[5].level = 9;  // settings_.bounces is 2
    for (const auto& [name, records] : {std::pair{"far.ic", far}, std::pair{"deep.ic", deep}}) {
        std::string file = save(name, records);
        IrradianceCache c(scene_, settings_);
        std::string error = c.load(file);
        EXPECT_NE(error.find(std::string(name) + "' holds a broken record"), std::string::npos) << error;
        EXPECT_TRUE(c.records().empty());  // all or nothing
    }
    IrradianceCache good(scene_, settings_);
    EXPECT_EQ(good.load(save("good.ic", records_)), "");
    EXPECT_EQ(good.records().size(), records_.size());
}

TEST_F(IrradianceCacheFile, TruncationsAreLocatedErrorsNeverCrashes) {
    const std::string bytes = slurp(save("a.ic", records_));
    ASSERT_GT(bytes.size(), 1000u);
    // Every cut in the first and last 260 bytes (the keys, the settings and the blob's length:
    // nlohmann writes keys in sorted order, so the settings come after the records), and a
    // sample of the record data (each case is a file write, slow on a busy machine).
    auto near_ends = [&](size_t i) { return i < 260 || i + 260 > bytes.size(); };
    for (size_t n = 0; n < bytes.size(); n += near_ends(n) ? 1 : 61) {
        spill(path("cut.ic"), bytes.substr(0, n));
        IrradianceCache c(scene_, settings_);
        std::string error = c.load(path("cut.ic"));
        ASSERT_NE(error, "") << "cut at " << n;
        ASSERT_NE(error.find("cut.ic"), std::string::npos) << error;
        ASSERT_TRUE(c.records().empty()) << "cut at " << n;
    }
    // The message says where the input ended.
    spill(path("cut.ic"), bytes.substr(0, bytes.size() / 2));
    std::string error = IrradianceCache(scene_, settings_).load(path("cut.ic"));
    EXPECT_NE(error.find("at byte"), std::string::npos) << error;
}

TEST_F(IrradianceCacheFile, DeepNestingIndefiniteLengthsAndHugeCountsAreRefusedBeforeParsing) {
    // 0x81: a CBOR array of one element; two million of them overflowed the recursive reader.
    spill(path("deep.ic"), std::string(2'000'000, '\x81'));
    std::string error = IrradianceCache(scene_, settings_).load(path("deep.ic"));
    EXPECT_NE(error.find("deep.ic' is not a crex irradiance cache or is damaged: at byte 8: nested deeper than 8 levels"),
              std::string::npos)
        << error;
    // 0x7f: an indefinite-length text string, whose chunks nlohmann's reader reads recursively
    // (found by tests/fuzz/ic_file_fuzzer.cpp).
    spill(path("chunks.ic"), "\xa1" + std::string(100'000, '\x7f'));
    error = IrradianceCache(scene_, settings_).load(path("chunks.ic"));
    EXPECT_NE(error.find("at byte 1: an indefinite length"), std::string::npos) << error;
    // A count no file of this size can hold: refused before anything is allocated for it.
    spill(path("count.ic"), std::string("\x9b\x40\x00\x00\x00\x00\x00\x00\x00\x01", 10));
    error = IrradianceCache(scene_, settings_).load(path("count.ic"));
    EXPECT_NE(error.find("at byte 0: a count of 4611686018427387904 items with 1 bytes left"), std::string::npos) << error;
}

TEST_F(IrradianceCacheFile, AFormatOfAnotherTypeIsRefusedNotThrown) {
    // {"format": 4}: "format" was read with value(key, ""), which throws for a number.
    spill(path("number.ic"), std::string("\xa1\x66" "format" "\x04", 9));
    std::string error;
    EXPECT_NO_THROW(error = IrradianceCache(scene_, settings_).load(path("number.ic")));
    EXPECT_NE(error.find("number.ic' is not a crex irradiance cache"), std::string::npos) << error;
}

TEST_F(IrradianceCacheFile, CorruptBytesAreRefusedOrLoadSaneRecords) {
    const std::string bytes = slurp(save("a.ic", records_));
    size_t refused = 0;
    auto near_ends = [&](size_t i) { return i < 260 || i + 260 > bytes.size(); };
    for (size_t i = 0; i < bytes.size(); i += near_ends(i) ? 1 : 29) {
        std::string bad = bytes;
        bad[i] = static_cast<char>(bad[i] ^ 0x5a);
        spill(path("bad.ic"), bad);
        IrradianceCache c(scene_, settings_);
        std::string error = c.load(path("bad.ic"));
        if (!error.empty()) {
            ++refused;
            ASSERT_NE(error.find("bad.ic"), std::string::npos) << error;
            continue;
        }
        for (const auto& r : c.records())  // a flipped mantissa bit may pass: values stay usable
            ASSERT_TRUE(is_finite(r.position) && is_finite(r.irradiance) && r.harmonic_distance > 0) << "byte " << i;
    }
    EXPECT_GT(refused, 0u);
}

}  // namespace
}  // namespace crex
