#include "runtime/cache/irradiance_cache_file.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

#include "runtime/cache/cbor_shape.h"
#include "runtime/scene/scene.h"

namespace crex {
namespace {

constexpr size_t kRecordFloats = 30;

void put_floats(std::vector<std::uint8_t>& out, std::initializer_list<double> values) {
    for (double d : values) {
        float f = static_cast<float>(d);
        std::uint8_t b[4];
        std::memcpy(b, &f, 4);  // x86 and ARM Linux are little-endian; the header says so
        out.insert(out.end(), b, b + 4);
    }
}

// Why a record read from a file cannot be this scene's ("" if it can): everything finite, the
// position inside the scene, irradiance from 0 to what the scene can give, a positive radius.
std::string broken_record(const IrradianceRecord& r, double extent, double max_irradiance, uint32_t bounces) {
    if (!is_finite(r.position)) return "its position is not finite";
    if (std::fabs(r.position.x) > extent || std::fabs(r.position.y) > extent || std::fabs(r.position.z) > extent)
        return fmt::format("its position ({:g}, {:g}, {:g}) is outside the scene", r.position.x, r.position.y, r.position.z);
    if (!is_finite(r.normal) || normalize_or_zero(r.normal) == Vec3{}) return "its normal is zero or not finite";
    const Vec3& e = r.irradiance;
    if (!is_finite(e)) return "its irradiance is not finite (NaN or Inf)";
    if (std::min({e.x, e.y, e.z}) < 0) return fmt::format("its irradiance ({:g}, {:g}, {:g}) is negative", e.x, e.y, e.z);
    if (max_component(e) > max_irradiance)
        return fmt::format("its irradiance {:g} is beyond what this scene's emitters can give (at most {:g})", max_component(e), max_irradiance);
    for (size_t c = 0; c < 3; ++c)
        if (!is_finite(r.rotation[c]) || !is_finite(r.translation[c])) return "its gradients are not finite";
    if (!(r.harmonic_distance > 0) || !std::isfinite(r.harmonic_distance)) return "its harmonic distance is not a positive number";
    if (!(r.quality > 0 && r.quality <= 1)) return "its accuracy is not in (0, 1]";
    if (r.level > bounces) return fmt::format("its bounce {} is past the cache's {} bounces", r.level, bounces);
    return "";
}

// nlohmann's "[json.exception.type_error.302] type must be number, but is string" as
// "type must be number, but is string".
std::string plain_json_error(const std::exception& e) {
    std::string what = e.what();
    if (what.rfind("[json.exception.", 0) == 0)
        if (size_t at = what.find("] "); at != std::string::npos) what = what.substr(at + 2);
    return what;
}

}  // namespace

double brightest_irradiance(const Scene& scene, const Vec3& ambient) {
    double l = std::max(max_component(scene.background), max_component(ambient));
    for (const auto& m : scene.materials) {
        if (m.type == MaterialType::kLight || m.type == MaterialType::kGlow) l = std::max(l, max_component(m.color));
        if (m.emission) l = std::max(l, max_component(*m.emission));
    }
    return std::numbers::pi * l * 1e6;  // inter-reflections of albedo up to 1 - 1e-6
}

std::string encode_irradiance_cache(const IcFileSettings& settings, const std::vector<IrradianceRecord>& records) {
    nlohmann::json j;
    j["format"] = "crex-irradiance-cache";
    j["version"] = 2;
    j["settings"] = {{"divisions", settings.divisions}, {"bounces", settings.bounces}, {"min_radius", settings.min_radius},
                     {"max_radius", settings.max_radius}, {"extent", settings.extent}, {"caustic_photons", settings.caustic_photons}};
    j["layout"] = "float32 little-endian x 30: p n e r rot[3] tra[3] q level";
    j["count"] = records.size();
    std::vector<std::uint8_t> bytes;
    bytes.reserve(records.size() * kRecordFloats * 4);
    for (const auto& r : records) {
        put_floats(bytes, {r.position.x, r.position.y, r.position.z, r.normal.x, r.normal.y, r.normal.z, r.irradiance.x, r.irradiance.y,
                           r.irradiance.z, r.harmonic_distance});
        for (const auto& g : {r.rotation[0], r.rotation[1], r.rotation[2], r.translation[0], r.translation[1], r.translation[2]})
            put_floats(bytes, {g.x, g.y, g.z});
        put_floats(bytes, {r.quality, static_cast<double>(r.level)});
    }
    j["records"] = nlohmann::json::binary(std::move(bytes));
    // Each record's own hemisphere rays (`vary ic_rays`), only when a record has them: a cache
    // of one setting is written as before.
    if (std::any_of(records.begin(), records.end(), [](const IrradianceRecord& r) { return r.divisions != 0; })) {
        std::vector<std::uint8_t> divisions;
        divisions.reserve(records.size() * 2);
        for (const auto& r : records) {  // little-endian, as the floats
            divisions.push_back(static_cast<std::uint8_t>(r.divisions & 0xffu));
            divisions.push_back(static_cast<std::uint8_t>(r.divisions >> 8));
        }
        j["divisions"] = nlohmann::json::binary(std::move(divisions));
    }
    std::vector<std::uint8_t> cbor = nlohmann::json::to_cbor(j);
    return std::string(cbor.begin(), cbor.end());
}

std::string decode_irradiance_cache(const std::string& data, const std::string& path, const IcFileSettings& expected, double max_irradiance,
                                    std::vector<IrradianceRecord>& records) {
    // Version 2 is CBOR; version 1 was JSON text. nlohmann's CBOR reader recurses per nesting
    // level and per chunk of an indefinite-length string: damaged bytes overflowed the stack
    // (SIGSEGV) before cbor_shape.h checked them, without recursion, first.
    const bool json_text = !data.empty() && data.front() == '{';
    if (!json_text)
        if (std::string shape = check_cbor_shape(std::vector<std::uint8_t>(data.begin(), data.end()), 8); !shape.empty())
            return "'" + path + "' is not a crex irradiance cache or is damaged: " + shape;
    auto j = json_text ? nlohmann::json::parse(data, nullptr, false) : nlohmann::json::from_cbor(data, true, false);
    // Compared as JSON values: value("format", "") threw out of load() when "format" was not
    // a string (found by tests/fuzz/ic_file_fuzzer.cpp).
    if (j.is_discarded() || !j.is_object() || !j.contains("format") || j.at("format") != "crex-irradiance-cache")
        return "'" + path + "' is not a crex irradiance cache";
    size_t records_in_file = 0;
    try {
        const auto& s = j.at("settings");
        // Records made with a caustic map leave caustics out (the map adds them), and records
        // made without one hold them: the two cannot be mixed.
        if (s.at("divisions").get<uint32_t>() != expected.divisions || s.at("bounces").get<uint32_t>() != expected.bounces ||
            s.value("caustic_photons", 0u) != expected.caustic_photons ||
            std::fabs(s.at("extent").get<double>() - expected.extent) > 1e-6 * expected.extent)
            return "'" + path + "' was made with other cache settings or for another scene";
        auto v = [](const nlohmann::json& a) { return Vec3{a.at(0).get<double>(), a.at(1).get<double>(), a.at(2).get<double>()}; };
        std::vector<IrradianceRecord> loaded;
        const double extent = expected.extent;
        std::string broken;
        auto keep = [&](IrradianceRecord rec) -> bool {
            // Positions are local (recentred): a record far outside the scene sent insert()'s
            // grid indices past int (undefined behaviour); levels past `bounces` are no cache's;
            // an irradiance of 1e38 or -5 took the image's indirect light away (issue 37).
            if (std::string why = broken_record(rec, extent, max_irradiance, expected.bounces); !why.empty()) {
                broken = fmt::format("'{}' holds a broken record: record {} of {}: {}; delete the file (crex makes the cache again)", path,
                                     loaded.size() + 1, records_in_file, why);
                return false;
            }
            rec.normal = normalize_or_zero(rec.normal);
            rec.harmonic_distance = std::clamp(rec.harmonic_distance, expected.min_radius, expected.max_radius);
            loaded.push_back(rec);
            return true;
        };
        const int version = j.value("version", 1);
        if (version == 2) {
            const auto& bin = j.at("records").get_binary();
            const size_t count = j.at("count").get<size_t>();
            records_in_file = count;
            if (bin.size() / (kRecordFloats * 4) != count || bin.size() % (kRecordFloats * 4) != 0)
                return fmt::format("'{}' is truncated: {} bytes of records for {}", path, bin.size(), count);
            std::vector<float> f(count * kRecordFloats);
            if (!f.empty()) std::memcpy(f.data(), bin.data(), bin.size());
            const std::vector<std::uint8_t>* divisions = j.contains("divisions") ? &j.at("divisions").get_binary() : nullptr;
            if (divisions && divisions->size() != 2 * count)
                return fmt::format("'{}' is truncated: {} bytes of record rays for {} records", path, divisions->size(), count);
            for (size_t i = 0; i < count; ++i) {
                const float* x = &f[i * kRecordFloats];
                IrradianceRecord rec;
                rec.position = {x[0], x[1], x[2]}, rec.normal = {x[3], x[4], x[5]}, rec.irradiance = {x[6], x[7], x[8]};
                rec.harmonic_distance = x[9];
                for (size_t c = 0; c < 3; ++c) {
                    rec.rotation[c] = {x[10 + 3 * c], x[11 + 3 * c], x[12 + 3 * c]};
                    rec.translation[c] = {x[19 + 3 * c], x[20 + 3 * c], x[21 + 3 * c]};
                }
                rec.quality = x[28];
                if (!(x[29] >= 0 && x[29] < 65536))
                    return fmt::format("'{}' holds a broken record: record {} of {}: its bounce is not a level", path, i + 1, count);
                rec.level = static_cast<uint16_t>(x[29]);
                if (divisions) rec.divisions = static_cast<uint16_t>((*divisions)[2 * i] | (*divisions)[2 * i + 1] << 8);
                if (!keep(rec)) return broken;
            }
        } else if (version == 1) {
            records_in_file = j.at("records").size();
            for (const auto& r : j.at("records")) {
                IrradianceRecord rec;
                rec.position = v(r.at("p")), rec.normal = v(r.at("n")), rec.irradiance = v(r.at("e"));
                rec.harmonic_distance = r.at("r").get<double>();
                for (size_t c = 0; c < 3; ++c) rec.rotation[c] = v(r.at("rot").at(c)), rec.translation[c] = v(r.at("tra").at(c));
                rec.quality = r.at("q").get<float>();
                rec.level = r.at("level").get<uint16_t>();
                if (!keep(rec)) return broken;
            }
        } else {
            return fmt::format("'{}' is a version {} cache; this crex reads versions 1 and 2", path, version);
        }
        records = std::move(loaded);
    } catch (const std::exception& e) {  // a field missing or of another type
        return fmt::format("'{}' is damaged or not a crex irradiance cache ({}); delete it (crex makes the cache again)", path,
                           plain_json_error(e));
    }
    return "";
}

}  // namespace crex
