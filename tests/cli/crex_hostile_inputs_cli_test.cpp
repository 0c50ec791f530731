// The findings of a hostile user's third round (issue 37), each as that user ran it: what crashed,
// hung or said something wrong now exits with its code and says what was wrong where. Every
// crashing input is made here, not kept as a file.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>

#include "runtime/io/image_io.h"
#include "runtime/report/reference_cache.h"
#include "runtime/scene/load_scene.h"
#include "tests/support/crex_cli.h"
#include "tests/support/float_map.h"
#include "tests/support/scratch_folder.h"
#include "tests/support/test_scenes.h"

namespace crex {
namespace {

namespace fs = std::filesystem;

using testing::crex_cli;
using testing::run_command;

class HostileInputs : public testing::ScratchFolderTest {
protected:
    HostileInputs() : ScratchFolderTest("crex_hostile_") {}
    std::string write(const std::string& name, const std::string& text) const {
        std::ofstream(path(name), std::ios::binary) << text;
        return path(name);
    }
    std::string read(const std::string& name) const {
        std::ifstream in(path(name), std::ios::binary);
        std::stringstream s;
        s << in.rdbuf();
        return s.str();
    }
    std::vector<std::string> files() const {
        std::vector<std::string> out;
        for (const auto& e : fs::directory_iterator(dir_)) out.push_back(e.path().filename().string());
        std::sort(out.begin(), out.end());
        return out;
    }
    // crex under `timeout`: a hang is a failure here, not a stuck test.
    testing::CommandResult bounded(std::vector<std::string> args) const {
        args.insert(args.begin(), {"/usr/bin/timeout", "60", CREX_BINARY});
        return run_command(args);
    }
};

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// `D` and 70,000 stacked '*' lowered to a tree 70,000 deep: exit 139 in check, plan and run.
TEST_F(HostileInputs, StackedStarsAreTooDeepNotAStackOverflow) {
    const std::string crex = "D" + std::string(70000, '*');
    for (const auto& args : std::vector<std::vector<std::string>>{{"check", "-e", crex},
                                                                  {"plan", "-e", crex},
                                                                  {"run", "-e", crex, "--size", "1x1", "-o", path("x.exr")},
                                                                  {"check", write("stars.crex", crex + "\n")}}) {
        auto r = bounded(args);
        EXPECT_EQ(r.exit_code, 1) << args[0] << ": " << r.err.substr(0, 400);
        EXPECT_TRUE(has(r.err, "error[E010]: groups and repeats nested more than 256 deep")) << r.err.substr(0, 400);
    }
    // The limit counts brackets and repeats together; 200 stars after a group of 50 is fine.
    auto fine = crex_cli({"check", "-q", "-e", std::string(50, '(') + "D" + std::string(50, ')') + std::string(200, '*')});
    EXPECT_EQ(fine.exit_code, 0) << fine.err.substr(0, 400);
}

// A profile's numbers of another type ended as "internal error: [json.exception.type_error.302]".
TEST_F(HostileInputs, ProfileNumbersOfAnotherTypeAreLocated) {
    for (const char* value : {"\"x\"", "null", "-1", "true"}) {
        const std::string p =
            write("p.json", std::string(R"({"format": "crex-profile", "version": 1, "full_render_seconds": )") + value + "}\n");
        auto r = crex_cli({"run", "--profile", p, "--budget", "50%", "--size", "4x4", "-q", "-o", path("x.exr")});
        EXPECT_EQ(r.exit_code, 1) << value << ": " << r.err;
        EXPECT_FALSE(has(r.err, "internal error")) << r.err;
        EXPECT_TRUE(has(r.err, "crex run: error: profile " + p + ":1:")) << r.err;
        EXPECT_TRUE(has(r.err, "full_render_seconds")) << r.err;
    }
    EXPECT_FALSE(fs::exists(path("x.exr")));
}

// An empty profile said "not a JSON object" with no position; one without a full render's time
// said "pass --profile FILE" although one was passed.
TEST_F(HostileInputs, ProfileMessagesSayWhatIsWrongWithTheFileGiven) {
    auto empty = crex_cli({"run", "--profile", write("empty.json", ""), "--size", "4x4", "-q", "-o", path("x.exr")});
    EXPECT_EQ(empty.exit_code, 1) << empty.err;
    EXPECT_TRUE(has(empty.err, path("empty.json") + ":1:1: the file is empty")) << empty.err;
    const std::string zero = write("zero.json", R"({"format": "crex-profile", "version": 1, "full_render_seconds": 0})");
    auto r = crex_cli({"run", "--profile", zero, "--budget", "25%", "--size", "4x4", "-q", "-o", path("x.exr")});
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_TRUE(has(r.err, "the profile '" + zero + "' holds no full render time")) << r.err;
    EXPECT_FALSE(has(r.err, "then pass --profile FILE")) << r.err;
    // --budget 101% is out of its range, whatever the profile.
    auto over = crex_cli({"run", "--budget", "101%", "--size", "4x4", "-q", "-o", path("x.exr")});
    EXPECT_EQ(over.exit_code, 2) << over.err;
    EXPECT_TRUE(has(over.err, "--budget 101%: out of range: expected a share in (0, 100] %")) << over.err;
}

// /dev/zero as any input read until memory ran out (std::bad_alloc under ulimit -v); a FIFO
// with no writer hung. Both are not files: refused at once (exit 3), naming what they are.
TEST_F(HostileInputs, DevicesAndFifosAreRefusedNotReadForEver) {
    ASSERT_EQ(::mkfifo(path("fifo.pipe").c_str(), 0600), 0);
    fs::create_symlink("/dev/zero", path("zero.json"));
    fs::create_symlink("/dev/zero", path("zero.rad"));
    fs::create_symlink("/dev/zero", path("zero.obj"));
    struct Case {
        std::vector<std::string> args;
        std::string said;
    };
    const std::string device = "is a character device, not a file", fifo = "is a named pipe (FIFO), not a file";
    for (const Case& c : {Case{{"check", "/dev/zero"}, device},
                          Case{{"check", path("fifo.pipe")}, fifo},
                          Case{{"plan", "/dev/zero"}, device},
                          Case{{"plan", path("fifo.pipe")}, fifo},
                          Case{{"run", "/dev/zero", "-q", "-o", path("x.exr")}, device},
                          Case{{"run", "--view", "/dev/zero", "--size", "4x4", "-q", "-o", path("x.exr")}, device},
                          Case{{"run", "--profile", "/dev/zero", "--size", "4x4", "-q", "-o", path("x.exr")}, device},
                          Case{{"run", "--profile", path("fifo.pipe"), "--size", "4x4", "-q", "-o", path("x.exr")}, fifo},
                          Case{{"scene-info", path("zero.json")}, device},
                          Case{{"scene-info", path("zero.rad")}, device},
                          Case{{"scene-info", path("zero.obj")}, device},
                          Case{{"run", "--scene", path("zero.rad"), "--size", "4x4", "-q", "-o", path("x.exr")}, device},
                          Case{{"compare", "/dev/zero", "/dev/zero"}, device}}) {
        auto r = bounded(c.args);
        EXPECT_NE(r.exit_code, 124) << c.args[0] << " " << c.args[1] << ": hung";
        EXPECT_TRUE(r.exit_code == 3 || r.exit_code == 1) << c.args[0] << " " << c.args[1] << ": " << r.exit_code << " " << r.err;
        EXPECT_TRUE(has(r.err, c.said)) << c.args[0] << " " << c.args[1] << ": " << r.err;
        EXPECT_FALSE(has(r.err, "internal error")) << r.err;
    }
    EXPECT_FALSE(fs::exists(path("x.exr")));
}

// A texture is an input too: an OBJ whose map_Kd named /dev/zero or a FIFO hung the render in
// the image reader. It is not opened; the render goes on with it magenta (W310, exit 0).
TEST_F(HostileInputs, ATextureThatIsADeviceOrAFifoIsNotOpened) {
    ASSERT_EQ(::mkfifo(path("leaf.png").c_str(), 0600), 0);
    for (const std::string& texture : {std::string("/dev/zero"), path("leaf.png")}) {
        write("quad.obj", "mtllib quad.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                          "usemtl tex\nf 1/1 2/2 3/3 4/4\nv -0.5 -0.5 2\nv 0.5 -0.5 2\nv 0.5 0.5 2\nv -0.5 0.5 2\nusemtl lamp\nf 8 7 6 5\n");
        write("quad.mtl", "newmtl tex\nKd 1 1 1\nmap_Kd " + texture + "\nnewmtl lamp\nKd 0 0 0\nKe 10 10 10\n");
        auto r = bounded({"run", "--scene", path("quad.obj"), "--size", "8x8", "--spp", "1", "-o", path("x.exr")});
        EXPECT_NE(r.exit_code, 124) << texture << ": hung";
        EXPECT_EQ(r.exit_code, 0) << texture << ": " << r.err;
        EXPECT_TRUE(has(r.err, "warning[W310]: texture cannot be read (not a regular file): it renders magenta")) << r.err;
        EXPECT_TRUE(fs::exists(path("x.exr")));
    }
}

// OpenImageIO allocates what an image's header claims before it reads a pixel: a 486-byte TIFF
// whose header claimed 40000 x 40000 took 23.7 GB in `crex compare` before it was killed, and
// 12 GB and two minutes as a texture of a 32x32 render. A header is held to the readers' pixel
// limit and to what its file could hold: the compare refuses it by name (exit 3), the texture
// renders magenta with W310.
TEST_F(HostileInputs, AnImageHeaderClaimingMoreThanItsFileHoldsIsRefused) {
    ASSERT_EQ(write_image(path("small.tif"), 8, 8, {{"", std::vector<float>(8 * 8 * 3, 0.5f)}}), "");
    std::ifstream in(path("small.tif"), std::ios::binary);
    const std::string sound((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_EQ(sound.substr(0, 4), std::string("II*\0", 4));
    auto u = [&](const std::string& b, size_t at, size_t n) {
        uint32_t v = 0;
        for (size_t k = n; k-- > 0;) v = v << 8 | static_cast<unsigned char>(b[at + k]);
        return v;
    };
    // The same file with ImageWidth (256) and ImageLength (257) set to `side`.
    auto claiming = [&](const std::string& name, uint32_t side) {
        std::string bytes = sound;
        const size_t ifd = u(bytes, 4, 4), entries = u(bytes, ifd, 2);
        for (size_t e = 0; e < entries; ++e) {
            const size_t at = ifd + 2 + 12 * e;
            const uint32_t tag = u(bytes, at, 2), type = u(bytes, at + 2, 2);
            if (tag != 256 && tag != 257) continue;
            for (size_t k = 0; k < (type == 3 ? 2u : 4u); ++k) bytes[at + 8 + k] = static_cast<char>(side >> (8 * k) & 0xff);
        }
        std::ofstream(path(name), std::ios::binary) << bytes;
        return path(name);
    };
    const std::string huge = claiming("huge.tif", 40000), claims = claiming("claims.tif", 4000);
    auto r = bounded({"compare", huge, huge});
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_TRUE(has(r.err, "cannot read '" + huge + "': an image of 40000 x 40000 pixels is beyond what crex reads")) << r.err;
    r = bounded({"compare", claims, claims});
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_TRUE(has(r.err, "is too small for the 4000 x 4000 pixels its header claims")) << r.err;
    write("quad.obj", "mtllib quad.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                      "usemtl tex\nf 1/1 2/2 3/3 4/4\n");
    write("quad.mtl", "newmtl tex\nKd 1 1 1\nmap_Kd " + claims + "\n");
    r = bounded({"run", "--scene", path("quad.obj"), "--size", "8x8", "--spp", "1", "-o", path("x.exr")});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(has(r.err, "warning[W310]: texture cannot be read (the file (")) << r.err;
    EXPECT_TRUE(has(r.err, "is too small for the 4000 x 4000 pixels its header claims (truncated?)): it renders magenta")) << r.err;
}

// Every input is read up to a stated size: a larger one is refused before it is read, by name.
TEST_F(HostileInputs, InputsLargerThanTheCapAreRefusedBeforeTheyAreRead) {
    std::ofstream(path("big.pipe")) << "pipeline big {}\n";
    fs::resize_file(path("big.pipe"), (size_t{64} << 20) + 1);  // sparse: nothing is written
    auto r = crex_cli({"check", path("big.pipe")});
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_TRUE(has(r.err, "cannot read '" + path("big.pipe") + "': it is 64 MiB, more than the 64 MiB crex reads from one input"))
        << r.err;
}

// ulimit -f killed a run with SIGXFSZ (exit 153) and left a staged file behind: it is a write
// failure like any other (exit 3), the old output stays as it was and nothing is left over.
TEST_F(HostileInputs, AFileSizeLimitIsAWriteFailure) {
    write("old.exr", "the old image");
    auto r = run_command({"/bin/sh", "-c", std::string("ulimit -f 16; exec ") + CREX_BINARY + " run --size 64x64 --spp 1 -q -o " +
                                               path("old.exr")});
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_TRUE(has(r.err, "File too large")) << r.err;
    EXPECT_EQ(read("old.exr"), "the old image");
    EXPECT_EQ(files(), std::vector<std::string>{"old.exr"});
}

// `-o X -o X` and `-o X --save-profile X` replaced X, then said "cannot move 'X' into place: No
// such file or directory". One path for two outputs is refused before anything renders.
TEST_F(HostileInputs, OnePathForTwoOutputsIsRefusedBeforeRendering) {
    const std::string x = write("x.exr", "kept");
    for (const auto& extra : std::vector<std::vector<std::string>>{{"-o", x},
                                                                   {"--save-profile", x},
                                                                   {"-o", path("./x.exr")},
                                                                   {"--ic-file", x},
                                                                   {"--report", path("r"), "--maps", path("r/")}}) {
        std::vector<std::string> args = {"run", "--size", "4x4", "--spp", "1", "-q", "-o", x};
        if (extra[0] == "--report") args = {"run", "--size", "4x4", "--spp", "1", "-q", "-o", path("y.exr")};
        args.insert(args.end(), extra.begin(), extra.end());
        auto r = crex_cli(args);
        EXPECT_EQ(r.exit_code, 2) << extra[0] << ": " << r.err;
        EXPECT_TRUE(has(r.err, "name the same path: each output needs its own")) << r.err;
        EXPECT_EQ(read("x.exr"), "kept");
    }
    EXPECT_EQ(files(), std::vector<std::string>{"x.exr"});
}

// --ic-file DIR said "basic_filebuf::underflow error reading the file" after the render.
TEST_F(HostileInputs, ACacheFileThatIsADirectoryIsSaidFirst) {
    fs::create_directories(path("cache"));
    auto r = crex_cli({"run", "--size", "4x4", "--spp", "1", "-q", "-o", path("x.exr"), "--ic-file", path("cache")});
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_TRUE(has(r.err, "--ic-file: cannot read '" + path("cache") + "': it is a directory; it names the cache's file")) << r.err;
    EXPECT_FALSE(fs::exists(path("x.exr")));
}

// The records of a version-2 cache file, patched: irradiance 1e38 or -5 loaded ("3052 records
// loaded") and the image lost its indirect light. NaN and Inf were refused already.
TEST_F(HostileInputs, CacheRecordsOutOfTheScenesBoundsAreRefused) {
    const std::vector<std::string> run = {"run", "--size", "8x8", "--spp", "1", "--ad", "16", "--ab", "1", "--caustic-photons", "0",
                                          "-q", "-o", path("x.exr"), "--ic-file"};
    auto made = crex_cli([&] { auto a = run; a.push_back(path("c.ic")); return a; }());
    ASSERT_EQ(made.exit_code, 0) << made.err;
    const std::string bytes = read("c.ic");
    const size_t key = bytes.find("records");
    ASSERT_NE(key, std::string::npos);
    size_t at = key + 7, length = 0;
    const auto byte = [&](size_t i) { return static_cast<unsigned char>(bytes[i]); };
    if (byte(at) == 0x59) length = size_t{byte(at + 1)} << 8 | byte(at + 2), at += 3;
    else if (byte(at) == 0x5a) length = size_t{byte(at + 1)} << 24 | size_t{byte(at + 2)} << 16 | size_t{byte(at + 3)} << 8 | byte(at + 4), at += 5;
    else FAIL() << "unexpected CBOR header " << int(byte(at));
    ASSERT_GE(length, 120u);
    struct Case {
        float value;
        std::string said;
    };
    for (const Case& c : {Case{1e38f, "is beyond what this scene's emitters can give"}, Case{-5.0f, "is negative"},
                          Case{std::nanf(""), "is not finite"}}) {
        std::string patched = bytes;
        for (size_t k = 6; k < 9; ++k) std::memcpy(&patched[at + 4 * k], &c.value, 4);  // record 1's E
        write("bad.ic", patched);
        auto a = run;
        a.push_back(path("bad.ic"));
        auto r = crex_cli(a);
        EXPECT_EQ(r.exit_code, 1) << c.value << ": " << r.err;
        EXPECT_TRUE(has(r.err, "holds a broken record: record 1 of ")) << r.err;
        EXPECT_TRUE(has(r.err, c.said)) << r.err;
    }
    // A version-1 cache (JSON) whose records lack fields printed a raw JSON exception.
    write("v1.ic", R"({"format": "crex-irradiance-cache", "version": 1, "records": [{"p": [0, 0, 0]}]})");
    auto a = run;
    a.push_back(path("v1.ic"));
    auto r = crex_cli(a);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_TRUE(has(r.err, "is damaged or not a crex irradiance cache")) << r.err;
    EXPECT_FALSE(has(r.err, "json.exception")) << r.err;
}

// A NaN reference gave a report of rmse nan and perr 100 with exit 0, where compare refuses it;
// the same from the reference cache (--reference auto).
TEST_F(HostileInputs, ANonFiniteReferenceIsRefusedAsCompareRefusesIt) {
    // crex's writer never writes a NaN: a float map (PFM) by hand, which OpenImageIO reads
    // whatever the file's extension says.
    std::vector<float> rgb(4 * 4 * 3, 0.5f);
    rgb[5] = std::nanf("");
    testing::write_pfm(path("nan.exr"), 4, 4, rgb);
    auto r = crex_cli({"run", "--size", "4x4", "--spp", "1", "-q", "-o", path("x.exr"), "--reference", path("nan.exr")});
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_TRUE(has(r.err, "holds 1 non-finite value (NaN or Inf)")) << r.err;
    auto compared = crex_cli({"compare", path("nan.exr"), path("nan.exr")});
    EXPECT_EQ(compared.exit_code, 1) << compared.err;
    // The cached reference of builtin:cornell at 4x4, replaced by the NaN image.
    ::setenv("CREX_CACHE", path("cache").c_str(), 1);
    ReferenceSettings s;
    s.width = s.height = 4;
    const std::string cached = reference_path(*builtin_scene("cornell"), s);
    fs::create_directories(fs::path(cached).parent_path());
    fs::copy_file(path("nan.exr"), cached);
    auto automatic = crex_cli({"run", "--size", "4x4", "--spp", "1", "-q", "-o", path("x.exr"), "--reference", "auto"});
    ::unsetenv("CREX_CACHE");
    EXPECT_EQ(automatic.exit_code, 1) << automatic.err;
    EXPECT_TRUE(has(automatic.err, "render it again with 'crex reference builtin:cornell --size 4x4 --force'")) << automatic.err;
    EXPECT_FALSE(fs::exists(path("x.exr")));
}

// Files given to the wrong command: `crex run scene.rad` read the scene as a plan ("E401
// malformed JSON"), `crex plan plan.json` as a pipeline ("E201 unexpected '{'").
TEST_F(HostileInputs, AFileGivenToTheWrongCommandIsNamedForWhatItIs) {
    const std::string rad = write("box.rad", "void light lamp 0 0 3 1 1 1\nlamp sphere ball 0 0 4 0 0 0 1\n");
    auto run = crex_cli({"run", rad, "-q", "-o", path("x.exr")});
    EXPECT_EQ(run.exit_code, 2) << run.err;
    EXPECT_TRUE(has(run.err, rad + " is a scene, not a plan or a pipeline: render it with --scene " + rad)) << run.err;
    auto made = crex_cli({"plan", "-e", "TT", "--format", "json", "-o", path("p.json")});
    ASSERT_EQ(made.exit_code, 0) << made.err;
    auto plan = crex_cli({"plan", path("p.json")});
    EXPECT_EQ(plan.exit_code, 2) << plan.err;
    EXPECT_TRUE(has(plan.err, path("p.json") + " is a plan already")) << plan.err;
    EXPECT_TRUE(has(plan.err, "crex run " + path("p.json"))) << plan.err;
    auto check = crex_cli({"check", rad});
    EXPECT_EQ(check.exit_code, 2) << check.err;
    EXPECT_TRUE(has(check.err, "is a scene, not a crex or pipeline file")) << check.err;
}

// `crex reference -o DIR` rendered, then said "no image writer for 'DIR'".
TEST_F(HostileInputs, AReferenceIntoADirectoryIsRefusedBeforeRendering) {
    fs::create_directories(path("refs"));
    auto r = crex_cli({"reference", "--size", "4x4", "--spp", "1", "-q", "-o", path("refs")});
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_TRUE(has(r.err, "-o " + path("refs") + ": is a directory; give a file name such as")) << r.err;
    EXPECT_FALSE(has(r.err, "no image writer")) << r.err;
}

// Binary .rad or .vf bytes, ESC included, were echoed to the terminal in messages.
TEST_F(HostileInputs, ControlCharactersInMessagesAreEscaped) {
    const std::string rad = write("esc.rad", "\x1b[31mred\x1b[0m\n");
    auto r = crex_cli({"scene-info", rad});
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_EQ(r.err.find('\x1b'), std::string::npos) << r.err;
    EXPECT_TRUE(has(r.err, "\\x1B[31mred")) << r.err;
    const std::string vf = write("esc.vf", "rview -vp 0 0 5 -v\x1b[2Jx 1\n");
    auto v = crex_cli({"run", "--view", vf, "--size", "4x4", "--spp", "1", "-q", "-o", path("x.exr")});
    EXPECT_EQ(v.err.find('\x1b'), std::string::npos) << v.err;
}

// A pipeline's `seed 9007199254740993` became 2^53 silently, where --seed refuses it.
TEST_F(HostileInputs, APipelineSeedBeyondTwoToThe53IsRefused) {
    const std::string pipe = write("seed.pipe", "pipeline s {\n  seed 9007199254740993\n  preselective { crex \"TT\" }\n}\n");
    for (const char* command : {"check", "plan"}) {
        auto r = crex_cli({command, pipe});
        EXPECT_EQ(r.exit_code, 1) << r.err;
        EXPECT_TRUE(has(r.err, pipe + ":2:8: error[E203]: seed: '9007199254740993' is out of range: expected a whole number from 0 to "
                                      "9007199254740992"))
            << r.err;
    }
    auto exact = crex_cli({"check", "-q", write("ok.pipe", "pipeline s {\n  seed 9007199254740992\n  preselective { crex \"TT\" }\n}\n")});
    EXPECT_EQ(exact.exit_code, 0) << exact.err;
}

// A 0-byte .rad and "shapes": [] rendered black without W302; a .rad without a view put the
// camera at (0, 0, 5) without a word.
TEST_F(HostileInputs, EmptyScenesAndMissingViewsAreSaid) {
    for (const auto& scene : {write("empty.rad", ""), write("empty.json", R"({"materials": [], "shapes": []})")}) {
        auto r = crex_cli({"scene-info", scene});
        EXPECT_EQ(r.exit_code, 0) << r.err;
        EXPECT_TRUE(has(r.err, "warning[W302]: the scene has no shapes")) << r.err;
    }
    const std::string rad = write("lit.rad", "void light lamp 0 0 3 1 1 1\nlamp sphere ball 0 0 4 0 0 -3 1\n");
    auto r = crex_cli({"run", "--scene", rad, "--size", "4x4", "--spp", "1", "-q", "-o", path("x.exr")});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(has(r.err, rad + ":1:1: warning[W305]: no view: '" + path("lit.vf") + "' does not exist")) << r.err;
    const std::string vf = write("other.vf", "rview -vp 0 0 5 -vd 0 0 -1 -vu 0 1 0 -vh 40 -vv 40\n");
    auto given = crex_cli({"run", "--scene", rad, "--view", vf, "--size", "4x4", "--spp", "1", "-q", "-o", path("x.exr")});
    EXPECT_EQ(given.exit_code, 0) << given.err;
    EXPECT_FALSE(has(given.err, "W305")) << given.err;
    write("lit.vf", "rview -vp 0 0 5 -vd 0 0 -1 -vu 0 1 0 -vh 40 -vv 40\n");
    auto beside = crex_cli({"scene-info", rad});
    EXPECT_FALSE(has(beside.err, "W305")) << beside.err;
}

// `crex check` passed a pipeline whose stdlib base was broken or extended itself across files,
// which plan and run refused: check now runs plan's front-end passes.
TEST_F(HostileInputs, CheckRefusesWhatPlanRefusesAcrossFiles) {
    fs::create_directories(path("lib/pipelines"));
    write("lib/pipelines/cyc_a.pipe", "pipeline cyc_a extends cyc_b {\n}\n");
    write("lib/pipelines/cyc_b.pipe", "pipeline cyc_b extends cyc_a {\n}\n");
    write("lib/pipelines/unk.pipe", "pipeline unk extends nosuchbase {\n}\n");
    write("lib/pipelines/broken.pipe", "pipeline broken {\n  preselective { crex \"TT\" }\n  guidance { x = nosuch(preview) }\n}\n");
    write("lib/pipelines/badcrex.pipe", "pipeline badcrex {\n  selective { crex \"{D*}\" }\n}\n");
    ::setenv("CREX_STDLIB", path("lib").c_str(), 1);
    for (const char* base : {"cyc_a", "unk", "broken", "badcrex"}) {
        const std::string mine = write(std::string("mine_") + base + ".pipe",
                                       std::string("pipeline mine extends ") + base + " {\n  image 8 x 8\n}\n");
        auto check = crex_cli({"check", mine});
        auto plan = crex_cli({"plan", mine});
        EXPECT_EQ(check.exit_code, 1) << base << ": " << check.err;
        EXPECT_EQ(plan.exit_code, 1) << base << ": " << plan.err;
        EXPECT_TRUE(has(check.err, mine + ":1:23: error[E210]: pipeline 'mine' extends '" + std::string(base) + "', which cannot be used"))
            << check.err;
        EXPECT_FALSE(has(plan.err, "the file holds no pipeline")) << plan.err;
    }
    ::unsetenv("CREX_STDLIB");
}

// OBJ `v nan` was read as 0; `f -1 -2 -99` dropped the whole mesh; MTL `Ke -10 10 10` lost its
// red; tinyobjloader's warnings were all placed at 1:1.
TEST_F(HostileInputs, ObjAndMtlValuesAreCheckedWhereTheyAre) {
    const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    struct Case {
        std::string obj, mtl, said;
    };
    for (const Case& c : {Case{"v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "", "n.obj:1:3: error[E303]: vertex: 'nan' is not a finite number"},
                          Case{"v inf 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "", "n.obj:1:3: error[E303]: vertex: 'inf' is not a finite number"},
                          Case{tri + "f -1 -2 -99\nf 1 2 3\n", "", "n.obj:4:9: error[E303]: face: vertex index -99 names no vertex: 3 are "
                                                                  "defined above this line"},
                          Case{tri + "f 1 2 7\n", "", "n.obj:4:7: error[E303]: face: vertex index 7 names no vertex: the file has 3"},
                          Case{"mtllib n.mtl\n" + tri + "usemtl L\nf 1 2 3\n", "newmtl L\nKe -10 10 10\n",
                               "n.mtl:2:4: error[E303]: Ke (a colour, each channel >= 0): -10 is out of range"},
                          Case{"mtllib n.mtl\n" + tri + "usemtl L\nf 1 2 3\n", "newmtl L\nKd nan 0.5 0.5\n",
                               "n.mtl:2:4: error[E303]: Kd (a colour, each channel >= 0): 'nan' is not a finite number"},
                          // -0 to strtod, NaN to tinyobjloader (0 x 5^3080 x 2^3080): a NaN roughness.
                          Case{"mtllib n.mtl\n" + tri + "usemtl L\nf 1 2 3\n", "newmtl L\nKd 0.5 0.5 0.5\nKs 0.2 0.2 0.2\nNs -0E3080\n",
                               "n.mtl:4:4: error[E303]: Ns (the Phong exponent): '-0E3080' has a decimal exponent beyond a double's"},
                          Case{"v 0e400 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "",
                               "n.obj:1:3: error[E303]: vertex: '0e400' has a decimal exponent beyond a double's"}}) {
        write("n.obj", c.obj);
        if (!c.mtl.empty()) write("n.mtl", c.mtl);
        auto r = crex_cli({"scene-info", path("n.obj"), "--export-json", path("n.json")});
        EXPECT_EQ(r.exit_code, 1) << c.obj << ": " << r.err;
        EXPECT_TRUE(has(r.err, path(c.said))) << r.err;
        EXPECT_FALSE(fs::exists(path("n.json")));
        fs::remove(path("n.mtl"));
    }
    // A warning tinyobjloader gives with its line is placed there, and so is an error.
    write("w.obj", tri + "g \nf 1 2 3\n");  // "Empty group name. line: 4"
    auto w = crex_cli({"scene-info", path("w.obj")});
    EXPECT_EQ(w.exit_code, 0) << w.err;
    EXPECT_TRUE(has(w.err, path("w.obj") + ":4:1: warning[W301]: OBJ: ")) << w.err;
    write("l.obj", tri + "l 0 1\nf 1 2 3\n");  // "Failed parse `l' line(e.g. zero value for vertex index. line 4.)"
    auto l = crex_cli({"scene-info", path("l.obj")});
    EXPECT_EQ(l.exit_code, 1) << l.err;
    EXPECT_TRUE(has(l.err, path("l.obj") + ":4:1: error[E308]: OBJ: ")) << l.err;
}

// A closed box of albedo 0.999 lit from inside rendered at a fifth of its radiance without a
// word: the light the depth limit (and the cache's bounces) left out is said, with the flag.
TEST_F(HostileInputs, LightLeftOutByTheLimitsIsSaid) {
    const std::string box = write("box.json", scene_json_text(testing::furnace_box(0.999, 0.25)));
    auto r = crex_cli({"run", "--scene", box, "-e", "D*", "--size", "8x8", "--spp", "1", "--format", "json", "-o", path("x.exr")});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(has(r.err, "crex run: warning[W404]: paths ended at max-depth 256 left out about ")) << r.err;
    EXPECT_TRUE(has(r.err, "raise --max-depth")) << r.err;
    const auto j = nlohmann::json::parse(r.out, nullptr, false);
    ASSERT_TRUE(j.is_object()) << r.out;
    EXPECT_GT(j["light_left_out"]["max_depth"].get<double>(), 0.3);
    auto cached = crex_cli({"run", "--scene", box, "-e", "D*", "--ic", "--ad", "64", "--caustic-photons", "0", "--size", "8x8", "--spp",
                            "1", "-q", "-o", path("x.exr")});
    ASSERT_EQ(cached.exit_code, 0) << cached.err;
    EXPECT_TRUE(has(cached.err, "warning[W404]: the irradiance cache's 8 ambient bounces left out about ")) << cached.err;
    EXPECT_TRUE(has(cached.err, "raise --ab")) << cached.err;
    // Albedo 0.5: nothing worth a word.
    const std::string dim = write("dim.json", scene_json_text(testing::furnace_box(0.5, 0.25)));
    auto quiet = crex_cli({"run", "--scene", dim, "-e", "D*", "--size", "8x8", "--spp", "1", "-q", "-o", path("x.exr")});
    EXPECT_EQ(quiet.exit_code, 0) << quiet.err;
    EXPECT_FALSE(has(quiet.err, "W404")) << quiet.err;
}

// A 2 s budget with --ad 16384 --ab 64 ran 14.5 s (at --ad 65536 past a minute): the first 17
// queries' records, each hemisphere ray asking the next bounce for its own. The cache now stops
// between pieces of records once the budget is spent and the queries wait: a run ends, the D
// rays not answered are said, and the records finished are kept in --ic-file for the next run.
TEST_F(HostileInputs, ACacheThatWouldOutlastTheBudgetStopsInsideIt) {
    auto r = bounded({"run", "--size", "4x4", "--ic", "--ad", "65536", "--ab", "64", "--budget", "0.3s", "--format", "json", "--ic-file",
                      path("x.ic"), "-o", path("x.exr")});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out, nullptr, false);
    ASSERT_TRUE(j.is_object()) << r.out;
    EXPECT_GT(j["components"]["D"]["rays_left"].get<uint64_t>(), 0u) << r.out;
    EXPECT_TRUE(has(j["skipped_tasks"].dump(), "D at <crex>:1:8")) << r.out;
    EXPECT_EQ(j["irradiance_cache"]["records"].get<uint64_t>(), j["irradiance_cache"]["records_made"].get<uint64_t>());
    int w = 0, h = 0;
    std::vector<float> rgb;
    ASSERT_EQ(read_image(path("x.exr"), w, h, rgb), "");
    ASSERT_EQ(rgb.size(), 4u * 4u * 3u);
    for (float v : rgb) ASSERT_TRUE(std::isfinite(v));
}

}  // namespace
}  // namespace crex
