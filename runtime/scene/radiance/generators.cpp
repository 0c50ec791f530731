#include "runtime/scene/radiance/generators.h"

#include <fmt/format.h>

#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "runtime/scene/radiance/calc.h"
#include "runtime/scene/radiance/sky_generators.h"

namespace crex::radiance {
namespace {

// What every generator's primitives share: made by this command.
struct Maker {
    SourceSpan where;
    Word modifier;
    std::vector<Primitive>& out;

    Primitive& add(const std::string& type, const std::string& id, std::vector<double> reals) {
        Primitive p;
        p.modifier = modifier;
        p.type = {type, where};
        p.id = {id, where};
        p.reals = std::move(reals);
        p.real_spans.assign(p.reals.size(), where);
        p.span = where;
        out.push_back(std::move(p));
        return out.back();
    }
};

SourceSpan stage_span(const CommandWords& argv) { return argv.front().span.merge(argv.back().span); }

bool number(const CommandWords& argv, size_t i, double& x, DiagnosticSink& sink) {
    if (i >= argv.size()) {
        sink.report("E301", stage_span(argv), fmt::format("{}: more arguments expected", argv[0].text));
        return false;
    }
    if (!parse_real(argv[i].text, x)) {
        sink.report("E302", argv[i].span, fmt::format("{}: expected a number, got '{}'", argv[0].text, argv[i].text));
        return false;
    }
    return true;
}

// ---- genbox -------------------------------------------------------------------------------
// A box from the origin to (x, y, z). Its corners and bevel points are numbered as genbox
// numbers them, because the digits make the face names: in octal, bit k of the low digit puts
// coordinate k at its far end, bit k of the high digit pulls it in by the bevel.

bool genbox(const CommandWords& argv, std::vector<Primitive>& out, DiagnosticSink& sink) {
    if (argv.size() < 6) {
        sink.report("E301", stage_span(argv), "genbox: expected 'genbox material name xsize ysize zsize [-i] [-b bevel | -r radius]'");
        return false;
    }
    double size[3];
    for (int k = 0; k < 3; ++k)
        if (!number(argv, 3 + static_cast<size_t>(k), size[k], sink)) return false;
    for (int k = 0; k < 3; ++k)
        if (!(size[k] > 0)) {
            sink.report("E303", argv[3 + static_cast<size_t>(k)].span, "genbox: the sizes must be > 0");
            return false;
        }
    bool inward = false, round = false;
    double bevel = 0;
    for (size_t i = 6; i < argv.size(); ++i) {
        const std::string& o = argv[i].text;
        if (o == "-i") {
            inward = true;
        } else if (o == "-b" || o == "-r") {
            if (!number(argv, i + 1, bevel, sink)) return false;
            if (!(bevel > 0) || !(2 * bevel < std::fmin(size[0], std::fmin(size[1], size[2])))) {
                sink.report("E303", argv[i + 1].span, fmt::format("genbox: {} must be > 0 and less than half the smallest side", o));
                return false;
            }
            round = o == "-r";
            ++i;
        } else if (o == "-n" || o == "-s" || o == "-o") {
            sink.report("E307", argv[i].span, fmt::format("genbox {} (edges made of polygons, or OBJ output) is not supported", o))
                .help = "leave it out: crex builds rounded edges from cylinders and spheres";
            return false;
        } else {
            sink.report("E303", argv[i].span, fmt::format("genbox: unknown option '{}'", o));
            return false;
        }
    }
    if (round && inward) {
        sink.report("E307", stage_span(argv), "genbox -r with -i (rounded edges made of polygons) is not supported");
        return false;
    }
    static const char kLetters[] = "0123456789._ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz";
    Maker m{stage_span(argv), argv[1], out};
    const std::string name = argv[2].text;
    const int rev = inward ? 1 : 0;
    auto vertex = [&](int v) {
        double p[3];
        for (int k = 0; k < 3; ++k, v >>= 1) {
            const bool far = ((v & 01) ^ rev) != 0;
            if (v & 010) p[k] = far ? size[k] - bevel : bevel;
            else p[k] = far ? size[k] : 0.0;
        }
        return Vec3{p[0], p[1], p[2]};
    };
    auto face = [&](std::initializer_list<int> vs) {
        std::string id = name + ".";
        std::vector<double> r;
        for (int v : vs) {
            id += kLetters[v];
            Vec3 p = vertex(v);
            r.insert(r.end(), {p.x, p.y, p.z});
        }
        m.add("polygon", id, std::move(r));
    };
    if (bevel > 0) {  // the six faces, inset
        face({051, 055, 054, 050}), face({064, 066, 062, 060}), face({032, 033, 031, 030});
        face({053, 052, 056, 057}), face({065, 061, 063, 067}), face({036, 034, 035, 037});
    }
    if (bevel > 0 && !round) {  // flat bevels along the edges and across the corners
        face({031, 051, 050, 030}), face({060, 062, 032, 030}), face({050, 054, 064, 060});
        face({034, 036, 066, 064}), face({037, 057, 056, 036}), face({052, 062, 066, 056});
        face({052, 053, 033, 032}), face({057, 067, 063, 053}), face({061, 031, 033, 063});
        face({065, 067, 037, 035}), face({055, 051, 061, 065}), face({034, 054, 055, 035});
        face({030, 050, 060}), face({051, 031, 061}), face({032, 062, 052}), face({064, 054, 034});
        face({036, 056, 066}), face({065, 035, 055}), face({053, 063, 033}), face({037, 067, 057});
    }
    if (bevel > 0 && round) {  // rounded: cylinders along the edges, spheres at the corners
        const int edges[12][2] = {{070, 071}, {070, 074}, {070, 072}, {073, 071}, {073, 072}, {073, 077},
                                  {075, 071}, {075, 074}, {075, 077}, {076, 072}, {076, 074}, {076, 077}};
        for (const auto& e : edges) {
            Vec3 a = vertex(e[0]), b = vertex(e[1]);
            m.add("cylinder", name + "." + kLetters[e[0]] + kLetters[e[1]], {a.x, a.y, a.z, b.x, b.y, b.z, bevel});
        }
        for (int v = 070; v <= 077; ++v) {
            Vec3 a = vertex(v);
            m.add("sphere", name + "." + kLetters[v], {a.x, a.y, a.z, bevel});
        }
    }
    if (bevel == 0) {
        face({1, 5, 4, 0}), face({4, 6, 2, 0}), face({2, 3, 1, 0});
        face({3, 2, 6, 7}), face({5, 1, 3, 7}), face({6, 4, 5, 7});
    }
    return true;
}

// ---- genprism -----------------------------------------------------------------------------
// A polygon in z = 0 extruded along a vector: the two end polygons (".b", ".t") and a side
// between each pair of consecutive vertices (".1", ".2", ...). With -c the vertex list is
// already closed (its seams included), so no side joins the last vertex to the first.

bool genprism(const CommandWords& argv, const GeneratorFiles& files, std::vector<Primitive>& out, DiagnosticSink& sink) {
    if (argv.size() < 4) {
        sink.report("E301", stage_span(argv), "genprism: expected 'genprism material name N x1 y1 .. xN yN [-l lx ly lz] [-c] [-e]'");
        return false;
    }
    std::vector<std::array<double, 2>> v;
    size_t i = 3;
    const std::string& third = argv[3].text;
    if (third == "-") {
        sink.report("E307", argv[3].span, "genprism: vertices from the standard input ('-') cannot be given to a scene file's command")
            .help = "list them on the command line (N x1 y1 ...) or in a file";
        return false;
    }
    if (!third.empty() && std::isdigit(static_cast<unsigned char>(third[0]))) {
        double n;
        if (!number(argv, 3, n, sink)) return false;
        if (n != std::floor(n) || n < 3 || n > 1e6) {
            sink.report("E303", argv[3].span, "genprism: the number of vertices must be an integer >= 3");
            return false;
        }
        const size_t count = static_cast<size_t>(n);
        if (argv.size() < 4 + 2 * count) {
            sink.report("E301", stage_span(argv), fmt::format("genprism: {} vertices need {} coordinates, got {}", count, 2 * count, argv.size() - 4));
            return false;
        }
        for (size_t k = 0; k < count; ++k) {
            double x, y;
            if (!number(argv, 4 + 2 * k, x, sink) || !number(argv, 5 + 2 * k, y, sink)) return false;
            v.push_back({x, y});
        }
        i = 4 + 2 * count;
    } else {  // a file of x y pairs
        std::string path = find_file(third, files.dir, files.library_dirs);
        std::ifstream in(path);
        if (path.empty() || !in) {
            sink.report("E308", argv[3].span, fmt::format("genprism: cannot read the vertex file '{}'", third));
            return false;
        }
        double x, y;
        while (in >> x >> y) v.push_back({x, y});
        i = 4;
    }
    if (v.size() < 3) {
        sink.report("E303", stage_span(argv), "genprism: not enough vertices (3 at least)");
        return false;
    }
    Vec3 l{0, 0, 1};
    bool closed = false, ends = true;
    for (; i < argv.size(); ++i) {
        const std::string& o = argv[i].text;
        if (o == "-l") {
            if (!number(argv, i + 1, l.x, sink) || !number(argv, i + 2, l.y, sink) || !number(argv, i + 3, l.z, sink)) return false;
            if (std::fabs(l.z) <= 1e-6) {
                sink.report("E303", argv[i + 3].span, "genprism: the extrusion vector must leave the z = 0 plane (its z is 0)");
                return false;
            }
            i += 3;
        } else if (o == "-c") {
            closed = !closed;
        } else if (o == "-e") {
            ends = !ends;
        } else if (o == "-r") {
            sink.report("E307", argv[i].span, "genprism -r (rounded corners) is not supported");
            return false;
        } else {
            sink.report("E303", argv[i].span, fmt::format("genprism: unknown option '{}'", o));
            return false;
        }
    }
    Maker m{stage_span(argv), argv[1], out};
    const std::string name = argv[2].text;
    const size_t n = v.size();
    if (ends) {
        std::vector<double> bottom, top;
        for (size_t k = 0; k < n; ++k) bottom.insert(bottom.end(), {v[k][0], v[k][1], 0.0});
        for (size_t k = n; k-- > 0;) top.insert(top.end(), {v[k][0] + l.x, v[k][1] + l.y, l.z});
        m.add("polygon", name + ".b", std::move(bottom));
        m.add("polygon", name + ".t", std::move(top));
    }
    auto side = [&](size_t a, size_t b) {
        m.add("polygon", fmt::format("{}.{}", name, a + 1),
              {v[a][0], v[a][1], 0.0, v[a][0] + l.x, v[a][1] + l.y, l.z, v[b][0] + l.x, v[b][1] + l.y, l.z, v[b][0], v[b][1], 0.0});
    };
    for (size_t k = 0; k + 1 < n; ++k) side(k, k + 1);
    if (!closed) side(n - 1, 0);
    return true;
}

// ---- genrev -------------------------------------------------------------------------------
// A surface of revolution about the z axis: for each step of t the curve (z(t), r(t)) sweeps
// a cylinder (tube when z falls), a cone (cup when z falls) or a ring.

bool genrev(const CommandWords& argv, const GeneratorFiles& files, std::vector<Primitive>& out, DiagnosticSink& sink) {
    if (argv.size() < 6) {
        sink.report("E301", stage_span(argv), "genrev: expected \"genrev material name 'z(t)' 'r(t)' nseg [-e expr] [-f file] [-s]\"");
        return false;
    }
    calc::Program program;
    auto located = [&](const Word& w, const calc::Error& e, const std::string& what) {
        // The word's text and the expression's differ by quotes at most: point at the word.
        sink.report("E302", w.span, fmt::format("genrev: {}: {}", what, e.message));
    };
    for (size_t i = 6; i < argv.size(); ++i) {
        const std::string& o = argv[i].text;
        calc::Error e;
        if (o == "-e" && i + 1 < argv.size()) {
            if (!program.define(argv[i + 1].text, e)) return located(argv[i + 1], e, "in -e"), false;
            ++i;
        } else if (o == "-f" && i + 1 < argv.size()) {
            std::string path = find_file(argv[i + 1].text, files.dir, files.library_dirs);
            std::ifstream in(path);
            if (path.empty() || !in) {
                sink.report("E308", argv[i + 1].span, fmt::format("genrev: cannot read the function file '{}'", argv[i + 1].text));
                return false;
            }
            std::stringstream text;
            text << in.rdbuf();
            if (!program.define(text.str(), e)) {
                const SourceFile* f = files.sources ? &files.sources->add(path, text.str()) : nullptr;
                if (f) sink.report("E302", {f, static_cast<uint32_t>(std::min(e.offset, f->text().size())), static_cast<uint32_t>(std::min(e.offset + 1, f->text().size()))},
                                   fmt::format("genrev: {}", e.message));
                else located(argv[i + 1], e, argv[i + 1].text);
                return false;
            }
            ++i;
        } else if (o == "-s") {
            sink.report("W306", argv[i].span, "genrev -s: crex does not smooth normals; the surface stays faceted along the curve");
        } else {
            sink.report("E303", argv[i].span, fmt::format("genrev: unknown option '{}'", o));
            return false;
        }
    }
    calc::Error e;
    auto z = program.parse(argv[3].text, e);
    if (!z) return located(argv[3], e, "z(t)"), false;
    auto r = program.parse(argv[4].text, e);
    if (!r) return located(argv[4], e, "r(t)"), false;
    auto nseg_expr = program.parse(argv[5].text, e);
    if (!nseg_expr) return located(argv[5], e, "nseg"), false;
    auto nseg_value = program.evaluate(*nseg_expr, {}, e);
    if (!nseg_value) return located(argv[5], e, "nseg"), false;
    const double nseg = std::floor(*nseg_value + 0.5);
    if (nseg < 1 || nseg > 100000) {
        sink.report("E303", argv[5].span, fmt::format("genrev: the number of segments must be in 1 .. 100000, got {}", nseg));
        return false;
    }
    double t = 0;
    calc::Environment env;
    env.variable = [&](const std::string& name) -> std::optional<double> {
        if (name == "t") return t;
        return std::nullopt;
    };
    std::vector<double> zs, rs;
    for (int k = 0; k <= static_cast<int>(nseg); ++k) {
        t = k / nseg;
        auto zv = program.evaluate(*z, env, e);
        if (!zv) return located(argv[3], e, fmt::format("z({:g})", t)), false;
        auto rv = program.evaluate(*r, env, e);
        if (!rv) return located(argv[4], e, fmt::format("r({:g})", t)), false;
        if (*rv < 0) {
            sink.report("E303", argv[4].span, fmt::format("genrev: r({:g}) = {:g}: the radius must not be negative", t, *rv));
            return false;
        }
        zs.push_back(*zv);
        rs.push_back(*rv);
    }
    Maker m{stage_span(argv), argv[1], out};
    const std::string name = argv[2].text;
    constexpr double kTiny = 1e-9;
    for (size_t k = 1; k < zs.size(); ++k) {
        const double z0 = zs[k - 1], z1 = zs[k], r0 = rs[k - 1], r1 = rs[k];
        const bool down = z1 < z0 - kTiny, up = z1 > z0 + kTiny, in = r1 < r0 - kTiny, outward = r1 > r0 + kTiny;
        const std::string id = fmt::format("{}.{}", name, k);
        if (!(down || up || in || outward)) continue;
        if (!in && !outward) m.add(down ? "tube" : "cylinder", id, {0, 0, z0, 0, 0, z1, r1});
        else if (!up && !down) m.add("ring", id, {0, 0, z1, 0, 0, in ? 1.0 : -1.0, r0, r1});
        else m.add(down ? "cup" : "cone", id, {0, 0, z0, 0, 0, z1, r0, r1});
    }
    return true;
}

}  // namespace

std::string find_file(const std::string& name, const std::string& dir, const std::vector<std::string>& library_dirs) {
    namespace fs = std::filesystem;
    if (name.empty()) return "";
    std::error_code ec;
    auto exists = [&](const fs::path& p) { return fs::is_regular_file(p, ec); };
    if (name[0] == '/') return exists(name) ? name : "";
    fs::path local = (fs::path(dir.empty() ? "." : dir) / name).lexically_normal();
    if (name[0] == '.' || name[0] == '~') return exists(local) ? local.string() : "";
    if (exists(local)) return local.string();
    for (const auto& d : library_dirs) {
        fs::path p = (fs::path(d) / name).lexically_normal();
        if (exists(p)) return p.string();
    }
    return "";
}

bool is_generator(const std::string& name) {
    return name == "genbox" || name == "genprism" || name == "genrev" || is_sky_generator(name);
}

bool run_generator(const CommandWords& argv, const GeneratorFiles& files, std::vector<Primitive>& out, DiagnosticSink& sink) {
    const std::string& g = argv[0].text;
    if (g == "genbox") return genbox(argv, out, sink);
    if (g == "genprism") return genprism(argv, files, out, sink);
    if (g == "genrev") return genrev(argv, files, out, sink);
    return run_sky_generator(argv, out, sink);
}

}  // namespace crex::radiance
