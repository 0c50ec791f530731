#include "runtime/scene/radiance/sky_generators.h"

#include "runtime/base/sampling.h"
#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <cstdlib>

#include "runtime/scene/sky_model.h"

namespace crex::radiance {
namespace {

constexpr double kDeg = kPi / 180;
// Luminous efficacies RADIANCE converts photometric sky and sun values with (lm/W).
constexpr double kSkyEfficacy = 203, kSunEfficacy = 208;

// Standard meridians of the time zones gensky knows (degrees west).
struct Zone {
    const char* name;
    double meridian;
};
constexpr Zone kZones[] = {{"YST", 135}, {"YDT", 120}, {"PST", 120}, {"PDT", 105}, {"MST", 105}, {"MDT", 90},   {"CST", 90},
                           {"CDT", 75},  {"EST", 75},  {"EDT", 60},  {"AST", 60},  {"ADT", 45},  {"NST", 52.5}, {"NDT", 37.5},
                           {"GMT", 0},   {"BST", -15}, {"CET", -15}, {"CEST", -30}, {"EET", -30}, {"EEST", -45}, {"GST", -60},
                           {"GDT", -75}, {"IST", -82.5}, {"IDT", -97.5}, {"JST", -135}, {"NZST", -180}, {"NZDT", -195}};

struct Site {
    double latitude = 0.66;          // radians north (gensky's default site)
    double longitude = 2.13;         // radians west
    double meridian = 120.0 * kDeg;  // standard meridian, radians west
};

int day_of_year(int month, int day) {
    static const int kStart[12] = {0, 31, 59, 90, 120, 151, 181, 212, 243, 273, 304, 334};
    return kStart[month - 1] + day;
}

// The solar position formulas gensky uses (declination and the equation of time by fits of
// the day of year; or, with a year, the Astronomical Almanac's algorithm after Michalsky).
double declination(int jd) { return 0.4093 * std::sin((2 * kPi / 365) * (jd - 81)); }
double solar_time_offset(int jd, const Site& s) {
    return 0.170 * std::sin((4 * kPi / 373) * (jd - 80)) - 0.129 * std::sin((2 * kPi / 355) * (jd - 8)) +
           (12 / kPi) * (s.meridian - s.longitude);
}
double wrap(double r, double p) { return r - p * std::floor(r / p); }
double almanac_declination(int year, int month, int day, double hour, const Site& s, double* solar_time) {
    int jd = day_of_year(month, day) + ((month > 2) && (year % 4 == 0));
    jd += (year - 1949) * 365 + (year - 1949) / 4;
    const double mjd = jd + (hour + s.meridian * (12 / kPi)) / 24 + (2432916.5 - 2451545.0);
    const double L = wrap((280.460 + 0.9856474 * mjd) * kDeg, 2 * kPi), g = wrap((357.528 + 0.9856003 * mjd) * kDeg, 2 * kPi);
    const double l = L + 1.915 * kDeg * std::sin(g) + 0.020 * kDeg * std::sin(2 * g), ep = (23.439 - 4e-7 * mjd) * kDeg;
    if (solar_time) {
        const double ra = std::atan2(std::sin(l) * std::cos(ep), std::cos(l));
        const double utime = 24 * (mjd - std::floor(mjd)) + 12;
        const double lmst = 6.697375 + 0.0657098242 * mjd + utime - s.longitude * (12 / kPi);
        *solar_time = wrap(lmst - ra * (12 / kPi) + 12, 24);
    }
    return std::asin(std::sin(ep) * std::sin(l));
}
double altitude_of(double sd, double st, const Site& s) {
    return std::asin(std::sin(s.latitude) * std::sin(sd) - std::cos(s.latitude) * std::cos(sd) * std::cos(st * (kPi / 12)));
}
double azimuth_of(double sd, double st, const Site& s) {
    return -std::atan2(std::cos(sd) * std::sin(st * (kPi / 12)),
                       -std::cos(s.latitude) * std::sin(sd) - std::sin(s.latitude) * std::cos(sd) * std::cos(st * (kPi / 12)));
}

// gensky's fits of the horizontal irradiance under the clear and intermediate skies.
double horizontal_fit(bool intermediate, double altitude) {
    static const double kFit[2][5] = {{2.766521, 0.547665, -0.369832, 0.009237, 0.059229}, {3.5556, -2.7152, -1.3081, 1.0660, 0.60227}};
    const double* f = kFit[intermediate ? 1 : 0];
    const double x = (altitude - kPi / 4) / (kPi / 4);
    double v = f[4];
    for (int i = 3; i >= 0; --i) v = v * x + f[i];
    return v;
}

struct Args {
    const CommandWords& w;
    DiagnosticSink& sink;
    bool number(size_t i, double& x) {
        if (i >= w.size()) {
            sink.report("E301", w.front().span.merge(w.back().span), fmt::format("{}: '{}' needs a number after it", w[0].text, w.back().text));
            return false;
        }
        char* end = nullptr;
        x = std::strtod(w[i].text.c_str(), &end);
        if (w[i].text.empty() || end != w[i].text.c_str() + w[i].text.size() || !std::isfinite(x)) {
            sink.report("E302", w[i].span, fmt::format("{}: expected a number, got '{}'", w[0].text, w[i].text));
            return false;
        }
        return true;
    }
};

bool gensky(const CommandWords& w, std::vector<Primitive>& out, DiagnosticSink& sink) {
    Args args{w, sink};
    const SourceSpan where = w.front().span.merge(w.back().span);
    if (w.size() < 4) {
        sink.report("E301", where, "gensky: expected 'gensky month day hour [options]' or 'gensky -ang altitude azimuth [options]'");
        return false;
    }
    Site site;
    int month = 0, day = 0, year = 0;
    double hour = 0, altitude = 0, azimuth = 0;
    bool solar_time = false, zone_given = false;
    if (w[1].text == "-ang") {
        if (!args.number(2, altitude) || !args.number(3, azimuth)) return false;
        altitude *= kDeg, azimuth *= kDeg;
    } else {
        double m, d;
        if (!args.number(1, m) || !args.number(2, d)) return false;
        if (m != std::floor(m) || m < 1 || m > 12) {
            sink.report("E303", w[1].span, "gensky: the month must be 1 .. 12");
            return false;
        }
        if (d != std::floor(d) || d < 1 || d > 31) {
            sink.report("E303", w[2].span, "gensky: the day must be 1 .. 31");
            return false;
        }
        month = static_cast<int>(m), day = static_cast<int>(d);
        // The time: [+]hh[:mm] or [+]hh.hh, then an optional time zone (a '+' means solar time).
        std::string t = w[3].text;
        size_t i = 0;
        solar_time = !t.empty() && t[0] == '+';
        if (solar_time) ++i;
        size_t digits = i;
        while (i < t.size() && (std::isdigit(static_cast<unsigned char>(t[i])) || t[i] == '.' || t[i] == ':')) ++i;
        std::string clock = t.substr(digits, i - digits), zone = t.substr(i);
        size_t colon = clock.find(':');
        char* end = nullptr;
        if (colon != std::string::npos) hour = std::atoi(clock.c_str()) + std::atoi(clock.c_str() + colon + 1) / 60.0;
        else hour = std::strtod(clock.c_str(), &end);
        bool ok = !clock.empty() && (colon != std::string::npos || end == clock.c_str() + clock.size()) && hour >= 0 && hour <= 24;
        if (ok && !zone.empty()) {
            ok = false;
            std::string upper;
            for (char c : zone) upper += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
            for (const Zone& z : kZones)
                if (upper == z.name && !solar_time) site.meridian = z.meridian * kDeg, ok = zone_given = true;
        }
        if (!ok) {
            sink.report("E302", w[3].span, fmt::format("gensky: cannot read the time '{}'; expected hh, hh:mm or hh.hh, a '+' before it "
                                                       "for solar time, or a time zone after it (EST, CET, ...)", t));
            return false;
        }
    }
    SkyModel::Type type = SkyModel::Type::kClear;
    bool sun = true;
    double zenith = 0, solar = 0, turbidity = 2.45, ground_reflectance = 0.2;
    int zenith_units = 0, solar_units = 0;  // 1: radiance given, -1: irradiance given
    for (size_t i = 4; i < w.size(); ++i) {
        const std::string& o = w[i].text;
        if (o.size() != 2 || (o[0] != '-' && o[0] != '+')) {
            sink.report("E303", w[i].span, fmt::format("gensky: unknown option '{}'", o));
            return false;
        }
        double x = 0;
        switch (o[1]) {
        case 's': type = SkyModel::Type::kClear, sun = o[0] == '+'; break;
        case 'i': type = SkyModel::Type::kIntermediate, sun = o[0] == '+'; break;
        case 'c': type = SkyModel::Type::kOvercast; break;
        case 'u': type = SkyModel::Type::kUniform; break;
        case 'r':
        case 'R':
            if (!args.number(++i, solar)) return false;
            solar_units = o[1] == 'R' ? -1 : 1;
            break;
        case 'b':
        case 'B':
            if (!args.number(++i, zenith)) return false;
            zenith_units = o[1] == 'B' ? -1 : 1;
            break;
        case 't':
            if (!args.number(++i, turbidity)) return false;
            break;
        case 'g':
            if (!args.number(++i, ground_reflectance)) return false;
            break;
        case 'a':
            if (!args.number(++i, x)) return false;
            site.latitude = x * kDeg;
            break;
        case 'o':
            if (!args.number(++i, x)) return false;
            site.longitude = x * kDeg;
            break;
        case 'm':
            if (!args.number(++i, x)) return false;
            if (!zone_given) site.meridian = x * kDeg;  // a time zone on the time wins
            break;
        case 'y':
            if (!args.number(++i, x)) return false;
            year = static_cast<int>(x);
            if (year < 1950 || year > 2050) sink.report("W306", w[i].span, "gensky -y: the solar position is accurate for 1950 .. 2050 only");
            break;
        default:
            sink.report("E303", w[i].span, fmt::format("gensky: unknown option '{}'", o));
            return false;
        }
    }
    if (month) {
        double st = hour, sd;
        if (year) {
            sd = almanac_declination(year, month, day, hour, site, solar_time ? nullptr : &st);
        } else {
            const int jd = day_of_year(month, day);
            sd = declination(jd);
            if (!solar_time) st = hour + solar_time_offset(jd, site);
        }
        altitude = altitude_of(sd, st, site);
        azimuth = azimuth_of(sd, st, site);
    }
    const bool overcast = type == SkyModel::Type::kOvercast || type == SkyModel::Type::kUniform;
    if (!overcast && altitude > 87 * kDeg) {
        sink.report("W306", where, "gensky: the sun is too close to the zenith; its altitude is reduced to 87 degrees (as gensky does)");
        altitude = 87 * kDeg;
    }
    const Vec3 sun_dir{-std::sin(azimuth) * std::cos(altitude), -std::cos(azimuth) * std::cos(altitude), std::sin(altitude)};
    double normalization = 1, f2 = 1;
    if (type == SkyModel::Type::kOvercast) normalization = 0.777778;
    if (type == SkyModel::Type::kClear || type == SkyModel::Type::kIntermediate) {
        f2 = sky_normalization(type, sun_dir);
        normalization = horizontal_fit(type == SkyModel::Type::kIntermediate, altitude) / f2 / kPi;
    }
    if (zenith_units == -1) {
        zenith /= normalization * kPi;
    } else if (zenith_units == 0) {
        zenith = overcast ? 8.6 * sun_dir.z + 0.123 : (1.376 * turbidity - 1.81) * std::tan(altitude) + 0.38;
        if (type == SkyModel::Type::kIntermediate) zenith = (zenith + 8.6 * sun_dir.z + 0.123) / 2;
        zenith = zenith < 0 ? 0 : zenith * 1000 / kSkyEfficacy;
    }
    double ground = zenith * normalization;
    if (!overcast && sun_dir.z > 0 && (!solar_units || solar > 0)) {
        if (solar_units == -1) {
            solar /= 6e-5 * sun_dir.z;
        } else if (solar_units == 0) {
            solar = 1.5e9 / kSunEfficacy * (1.147 - 0.147 / std::fmax(sun_dir.z, 0.16));
            if (type == SkyModel::Type::kIntermediate) solar *= 0.15;
        }
        ground += 6e-5 / kPi * solar * sun_dir.z;
    } else {
        sun = false;
    }
    ground *= ground_reflectance;

    auto add = [&](const std::string& mod, const std::string& t, const std::string& id, std::vector<std::string> strings,
                   std::vector<double> reals) {
        Primitive p;
        p.modifier = {mod, where};
        p.type = {t, where};
        p.id = {id, where};
        for (auto& s : strings) p.strings.push_back({s, where});
        p.reals = std::move(reals);
        p.real_spans.assign(p.reals.size(), where);
        p.span = where;
        out.push_back(std::move(p));
    };
    if (sun) {
        add("void", "light", "solar", {}, {solar, solar, solar});
        add("solar", "source", "sun", {}, {sun_dir.x, sun_dir.y, sun_dir.z, 0.5});
    }
    if (overcast) add("void", "brightfunc", "skyfunc", {"skybr", "skybright.cal"}, {static_cast<double>(type), zenith, ground});
    else
        add("void", "brightfunc", "skyfunc", {"skybr", "skybright.cal"},
            {static_cast<double>(type), zenith, ground, f2, sun_dir.x, sun_dir.y, sun_dir.z});
    return true;
}

}  // namespace

bool is_sky_generator(const std::string& name) { return name == "gensky"; }

bool run_sky_generator(const CommandWords& argv, std::vector<Primitive>& out, DiagnosticSink& sink) {
    return gensky(argv, out, sink);
}

}  // namespace crex::radiance
