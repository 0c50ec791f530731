// The Python module `crex` (its C++ half, `crex._crex`; python/crex/__init__.py is the face):
// the library's API with numpy arrays for images. Every call goes through runtime/runtime.h,
// the same functions `crex run` calls, so an image rendered here is the CLI's, bit for bit, for
// the same plan, scene, options and seed. Diagnostics become exceptions carrying them; a
// render runs with the GIL released and stops on Ctrl-C (KeyboardInterrupt) with nothing
// written.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "base/render_json.h"
#include "base/render_text.h"
#include "compiler/pipeline/stdlib_pipelines.h"
#include "compiler/sched/print.h"
#include "runtime/runtime.h"

namespace py = pybind11;

namespace crex::python {
namespace {

// --- Errors -------------------------------------------------------------------------------

// Python's classes, made in the module's init.
py::object g_error, g_compile_error, g_input_error;

struct PythonDiagnostic {
    std::string code, severity, message, file, help;
    uint32_t line = 0, column = 0, end_line = 0, end_column = 0;
    std::vector<std::string> notes;
    std::string text;  // as `crex check` prints it, with the source line and the caret
};

std::vector<PythonDiagnostic> diagnostics_of(const DiagnosticSink& sink) {
    std::vector<PythonDiagnostic> out;
    for (const Diagnostic& d : sink.sorted()) {
        PythonDiagnostic p;
        p.code = d.code;
        p.severity = std::string(severity_name(d.severity));
        p.message = d.message;
        p.help = d.help;
        const SourceLocation at = SourceLocation::of(d.span);
        p.file = at.file, p.line = at.line, p.column = at.col, p.end_line = at.end_line, p.end_column = at.end_col;
        for (const auto& n : d.notes) p.notes.push_back(n.message);
        p.text = render_text(std::vector<Diagnostic>{d});
        out.push_back(std::move(p));
    }
    return out;
}

// Raises crex.CompileError carrying the sink's diagnostics (its message: the first error's text).
[[noreturn]] void raise_compile_error(const DiagnosticSink& sink, const std::string& what) {
    std::vector<PythonDiagnostic> ds = diagnostics_of(sink);
    std::string first;
    for (const auto& d : ds)
        if (d.severity == "error") {
            first = d.text;
            break;
        }
    py::object e = g_compile_error(what + (first.empty() ? "" : ":\n" + first));
    e.attr("diagnostics") = py::cast(ds);
    PyErr_SetObject(g_compile_error.ptr(), e.ptr());
    throw py::error_already_set();
}

[[noreturn]] void raise_input_error(const std::string& what) {
    PyErr_SetString(g_input_error.ptr(), what.c_str());
    throw py::error_already_set();
}

// --- Scenes and plans ---------------------------------------------------------------------

// A scene loaded, with the texts its diagnostics point into.
struct PythonScene {
    std::string spec;
    std::shared_ptr<SceneInput> input;
    nlohmann::json warnings = nlohmann::json::array();  // said while it loaded: a run's summary lists them
    const Scene& scene() const { return *input->scene; }
};

PythonScene load_scene(const std::string& spec) {
    DiagnosticSink sink;
    std::shared_ptr<SceneInput> in = load_scene_input(spec, sink);
    if (!in->failure.empty()) raise_input_error(in->failure);
    if (!in->scene || sink.has_errors()) raise_compile_error(sink, "the scene " + spec + " has errors");
    PythonScene out{spec, std::move(in)};
    for (const Diagnostic& d : sink.sorted())
        if (d.severity == Severity::kWarning) out.warnings.push_back(to_json(d));
    return out;
}

// A compiled plan, with the source its diagnostics point into.
struct PythonPlan {
    std::shared_ptr<SourceFile> source;
    PipelinePlan plan;
    std::optional<CrexPlan> crex;      // a crex's plan as `crex plan -e` shows it (what was pruned, and why)
    std::optional<PythonScene> scene;  // the scene it was planned for (the pipeline's, or the one given)
    nlohmann::json json() const { return crex ? plan_to_json(*crex) : pipeline_plan_to_json(plan); }
    std::string dot() const { return crex ? plan_to_dot(*crex) : pipeline_plan_to_dot(plan); }
};

bool is_file(const std::string& source, const char* extension) {
    std::error_code ec;
    return source.size() > std::strlen(extension) && source.substr(source.size() - std::strlen(extension)) == extension &&
           std::filesystem::is_regular_file(source, ec);
}

// A path as Python's file functions take one: a str or an os.PathLike (pathlib.Path).
bool is_path(const py::handle& p) { return py::isinstance<py::str>(p) || py::isinstance(p, py::module_::import("os").attr("PathLike")); }
std::string path_text(const py::handle& p) { return py::str(py::module_::import("os").attr("fspath")(p)).cast<std::string>(); }

// `scene` as Python gives it: a Scene, a spec, or None (`fallback`, else builtin:cornell).
PythonScene scene_of(const py::object& scene, const std::string& fallback = "") {
    if (py::isinstance<PythonScene>(scene)) return scene.cast<PythonScene>();
    if (!scene.is_none()) {
        if (!is_path(scene))
            throw py::type_error(fmt::format("scene: expected a crex.Scene, a scene's path or builtin: name, or None; got {}",
                                             py::str(py::type::of(scene).attr("__name__")).cast<std::string>()));
        return load_scene(path_text(scene));
    }
    return load_scene(fallback.empty() ? "builtin:cornell" : fallback);
}

// A pipeline file's text, a path to one (.pipe), a stdlib pipeline's name, or a crex.
PythonPlan compile(const std::string& source, const py::object& scene, const std::string& pipeline_name) {
    PythonPlan out;
    DiagnosticSink sink;
    std::string name = "<pipeline>", text = source;
    const pipeline::PipelineArgument stdlib = pipeline::pipeline_argument(source);  // "sel_rp", not a crex
    if (is_file(source, ".pipe") || stdlib.stdlib) {
        std::string error;
        auto read = read_input(stdlib.path, error);
        if (!read) raise_input_error(error);
        name = stdlib.path, text = std::move(*read);
    }
    const bool pipeline = name != "<pipeline>" || text.find("pipeline") != std::string::npos;
    if (!pipeline) {
        out.source = std::make_shared<SourceFile>("<crex>", text);
        CompiledCrex compiled = compile_crex(*out.source, sink);
        if (!compiled.program || sink.has_errors())
            raise_compile_error(sink, stdlib.hint.empty() ? "the crex has errors" : "the crex has errors; if a pipeline was meant: " + stdlib.hint);
        out.scene = scene_of(scene);
        const SceneFacts facts = scene_facts(out.scene->spec, out.scene->scene());
        out.crex = plan_crex(text, compiled, &facts);
        out.plan.program = out.crex->program;
        out.plan.scene = facts.spec, out.plan.census_hash = facts.census_hash;
        return out;
    }
    out.source = std::make_shared<SourceFile>(name, text);
    // The passes of compile_pipeline (compiler/compiler.h), the scene loaded between the front
    // end and the planner: the one given, else the pipeline's own, else the built-in Cornell box.
    PipelineCompilation c = compile_pipeline_front_end(*out.source, pipeline_name, sink);
    if (!c.resolved || sink.has_errors()) raise_compile_error(sink, "the pipeline has errors");
    std::string named_spec;
    if (auto named = pipeline_scene(*c.resolved, name == "<pipeline>" ? "." : name)) named_spec = named->spec;
    out.scene = scene_of(scene, named_spec);
    const SceneFacts facts = scene_facts(out.scene->spec, out.scene->scene());
    plan_for_scene(c, &facts, sink);
    if (!c.plan || sink.has_errors()) raise_compile_error(sink, "the pipeline has errors");
    out.plan = std::move(*c.plan);
    return out;
}

// --- Images -------------------------------------------------------------------------------

py::array_t<float> image_array(const std::vector<float>& rgb, int width, int height, int channels = 3) {
    py::array_t<float> a({static_cast<py::ssize_t>(height), static_cast<py::ssize_t>(width), static_cast<py::ssize_t>(channels)});
    std::copy(rgb.begin(), rgb.begin() + static_cast<std::ptrdiff_t>(a.size()), a.mutable_data());
    return a;
}

std::vector<float> rgb_of(const py::array_t<float, py::array::c_style | py::array::forcecast>& a, int& width, int& height) {
    if (a.ndim() != 3 || a.shape(2) != 3) throw std::invalid_argument("an image is an array of shape (height, width, 3)");
    if (a.shape(0) < 1 || a.shape(1) < 1 || a.shape(0) > 65535 || a.shape(1) > 65535)
        throw std::invalid_argument(fmt::format("an image is {} x {} pixels: each side from 1 to 65535", a.shape(1), a.shape(0)));
    height = static_cast<int>(a.shape(0)), width = static_cast<int>(a.shape(1));
    return std::vector<float>(a.data(), a.data() + a.size());
}

py::array_t<float> read_image_file(const std::string& path) {
    int w = 0, h = 0;
    std::vector<float> rgb;
    if (std::string error = read_image(path, w, h, rgb); !error.empty()) raise_input_error(error);
    return image_array(rgb, w, h);
}

// The tone map of spec/pipeline.md §7 that the metrics and flicker see through, for scripts
// that must see an image as they do (a stack of images through one exposure, for one).
double display_exposure_of(const py::array_t<float, py::array::c_style | py::array::forcecast>& image) {
    int w = 0, h = 0;
    return display_exposure(rgb_of(image, w, h));
}

py::array_t<float> to_display_array(const py::array_t<float, py::array::c_style | py::array::forcecast>& image, double exposure) {
    if (image.ndim() < 1 || image.shape(image.ndim() - 1) != 3) throw std::invalid_argument("to_display takes an array whose last axis is RGB (size 3)");
    if (!(exposure > 0) || !std::isfinite(exposure))
        throw std::invalid_argument(fmt::format("exposure: {} is not a number above 0 (crex.display_exposure(image) gives the metrics' own)", exposure));
    py::array_t<float> out(std::vector<py::ssize_t>(image.shape(), image.shape() + image.ndim()));
    to_display(image.data(), out.mutable_data(), static_cast<size_t>(image.size()), exposure);
    return out;
}

// --- Running ------------------------------------------------------------------------------

// Progress and Ctrl-C while the render runs without the GIL: every few milliseconds the GIL is
// taken back to let Python's signal handlers run (KeyboardInterrupt) and to call `callback`;
// a Python exception from either stops the render (RunCancelled) and is raised again after.
class PythonObserver final : public RunObserver {
public:
    explicit PythonObserver(py::object callback) : callback_(std::move(callback)) {}
    void progress(const RunProgress& p) override {
        const auto now = std::chrono::steady_clock::now();
        if (now - last_ < std::chrono::milliseconds(20)) return;
        last_ = now;
        py::gil_scoped_acquire gil;
        try {
            if (PyErr_CheckSignals() != 0) throw py::error_already_set();
            if (!callback_.is_none()) callback_(py::dict(py::arg("stage") = p.stage, py::arg("fraction") = p.fraction, py::arg("pass") = p.pass,
                                                         py::arg("passes") = p.passes, py::arg("rays") = p.rays, py::arg("step") = p.step));
        } catch (py::error_already_set& e) {
            error_ = std::move(e);
            throw RunCancelled("stopped from Python");
        }
    }
    // With the GIL held again: what stopped the render, raised in Python.
    void raise_if_stopped() {
        if (error_) {
            py::error_already_set e = std::move(*error_);
            error_.reset();
            e.restore();
            throw py::error_already_set();
        }
    }

private:
    py::object callback_;
    std::optional<py::error_already_set> error_;
    std::chrono::steady_clock::time_point last_{};
};

// The keyword options crex.run() takes, as `crex run`'s flags of the same names.
constexpr std::array<const char*, 15> kRunOptions = {"size", "spp", "seed", "lw", "max_depth", "rounds", "ambient", "budget", "no_budget",
                                                     "policy", "shadow_rays", "uniform", "irradiance_cache", "max_memory_mib", "components"};

// A number given for option `key`: a whole one where `whole` (Python and numpy integers, not
// bool), within [lo, hi] as the flag of `crex run` takes it. Else TypeError or ValueError
// naming the option (pybind11's own cast said "Unable to cast Python instance to C++ type").
double option_number(const char* key, const py::handle& v, OptionRange range, bool whole) {
    const double lo = range.lo, hi = range.hi;
    const char* kind = whole ? "a whole number" : "a number";
    // Bounds as the flags print them: 9007199254740992, not 9.00719925474099e+15.
    auto bound = [&](double b) { return whole ? fmt::format("{}", static_cast<long long>(b)) : fmt::format("{}", b); };
    if (py::isinstance<py::bool_>(v) || !PyNumber_Check(v.ptr()) || (whole && !PyIndex_Check(v.ptr())))
        throw py::type_error(fmt::format("{}: expected {} from {} to {}, got {}", key, kind, bound(lo), bound(hi), py::str(py::type::of(v).attr("__name__")).cast<std::string>()));
    // As a double (exact for every whole number in range); one too large for a double is out of range.
    const py::object as_float = py::reinterpret_steal<py::object>(PyNumber_Float(v.ptr()));
    if (!as_float) PyErr_Clear();
    const double x = as_float ? PyFloat_AsDouble(as_float.ptr()) : std::nan("");
    if (!(x >= lo && x <= hi))
        throw py::value_error(fmt::format("{}: {} is out of range: expected {} from {} to {}", key, py::repr(v).cast<std::string>(), kind, bound(lo), bound(hi)));
    return x;
}

bool option_bool(const char* key, const py::handle& v) {
    if (!py::isinstance<py::bool_>(v)) throw py::type_error(fmt::format("{}: expected True or False", key));
    return v.cast<bool>();
}

std::string option_text(const char* key, const py::handle& v) {
    if (!py::isinstance<py::str>(v)) throw py::type_error(fmt::format("{}: expected a string", key));
    return v.cast<std::string>();
}

// A run's options from keyword arguments (unset: the plan's settings, else the defaults of
// runtime/api/run_options.h), no text in between. An unknown keyword is a TypeError, as
// Python's own functions raise: a misspelt option must not render with its default.
RunOptions options_of(const py::dict& kw) {
    for (const auto& [key, value] : kw) {
        const std::string name = py::str(key).cast<std::string>();
        if (std::find(kRunOptions.begin(), kRunOptions.end(), name) == kRunOptions.end())
            throw py::type_error(fmt::format("run() got an unexpected keyword argument '{}' (options: {})", name, fmt::join(kRunOptions, ", ")));
    }
    RunOptions o;
    auto get = [&](const char* key) -> std::optional<py::object> {
        if (!kw.contains(key) || kw[key].is_none()) return std::nullopt;
        return py::reinterpret_borrow<py::object>(kw[key]);
    };
    if (auto v = get("size")) {
        const py::sequence wh = py::isinstance<py::sequence>(*v) && !py::isinstance<py::str>(*v) ? v->cast<py::sequence>() : py::sequence();
        if (wh.size() != 2) throw py::type_error("size: expected (width, height)");
        o.width = static_cast<int>(option_number("size", wh[0], kImageSideRange, true));
        o.height = static_cast<int>(option_number("size", wh[1], kImageSideRange, true));
    }
    if (auto v = get("spp")) o.spp = static_cast<uint32_t>(option_number("spp", *v, kSppRange, true));
    if (auto v = get("seed")) o.seed = static_cast<uint64_t>(option_number("seed", *v, {0, 9007199254740992.0}, true));
    if (auto v = get("lw")) o.lw = option_number("lw", *v, kWeightLimitRange, false);
    if (auto v = get("max_depth")) o.max_depth = static_cast<uint32_t>(option_number("max_depth", *v, kMaxDepthRange, true));
    if (auto v = get("rounds")) o.rounds = static_cast<uint32_t>(option_number("rounds", *v, {1, 1024}, true));
    if (auto v = get("ambient")) {
        if (py::isinstance<py::str>(*v)) {
            if (v->cast<std::string>() != "auto") throw py::value_error("ambient: a radiance (a number >= 0) or \"auto\"");
            o.ambient = AmbientStandIn{true, 0};
        } else {
            o.ambient = AmbientStandIn{false, option_number("ambient", *v, {0, 1e30}, false)};
        }
    }
    if (auto v = get("budget")) o.budget = PlanBudget{option_number("budget", *v, {1e-3, 1e9}, false), false, {}};  // seconds
    if (auto v = get("no_budget")) o.no_budget = option_bool("no_budget", *v);
    if (auto v = get("policy")) {
        o.policy = pipeline::scheduling_policy_from_name(option_text("policy", *v));
        if (!o.policy) throw py::value_error("policy: one of tasks, batches, queues, progressive");
    }
    if (auto v = get("shadow_rays")) o.shadow_rays = static_cast<uint32_t>(option_number("shadow_rays", *v, kShadowRaysRange, true));
    if (auto v = get("uniform")) {
        const std::string u = option_text("uniform", *v);
        if (u != "min" && u != "max") throw py::value_error("uniform: \"min\" or \"max\"");
        o.uniform = u == "max" ? UniformQuality::kMax : UniformQuality::kMin;
    }
    if (auto v = get("irradiance_cache")) o.irradiance_cache = option_bool("irradiance_cache", *v);
    if (auto v = get("max_memory_mib")) o.max_memory = static_cast<size_t>(option_number("max_memory_mib", *v, {64, 1048576}, false) * double(1 << 20));
    if (auto v = get("components")) o.component_images = option_bool("components", *v);
    return o;
}

py::dict run(const PythonPlan& p, const py::object& scene_given, py::object progress, const py::object& output, const py::dict& kw) {
    const PythonScene scene = scene_given.is_none() ? *p.scene : scene_of(scene_given);
    RunOptions options = options_of(kw);
    RunFiles files;
    if (!output.is_none()) {
        auto path_of = [](const py::handle& item) {
            if (!is_path(item)) throw py::type_error("output: expected an image path or a list of them");
            return path_text(item);
        };
        if (is_path(output)) {
            files.images = {path_of(output)};
        } else {
            if (!py::isinstance<py::sequence>(output)) throw py::type_error("output: expected an image path or a list of them");
            for (const py::handle& item : output.cast<py::sequence>()) files.images.push_back(path_of(item));
        }
        for (const auto& path : files.images)  // checked before anything renders
            if (std::string error = check_output_path(path); !error.empty()) raise_input_error(error);
    }
    PythonObserver observer(std::move(progress));
    LocalGroup one;
    std::optional<RunOutcome> out;
    try {
        py::gil_scoped_release free;  // the render runs without the GIL: other Python threads go on
        out = run_plan(p.plan, scene.scene(), options, one, observer);
    } catch (const RunCancelled&) {
        observer.raise_if_stopped();
        throw;
    } catch (const RunOptionError& e) {
        raise_input_error(e.where.empty() ? e.what() : e.where + ": " + e.what());
    } catch (const RunInputError& e) {
        raise_input_error(e.what());
    }
    const RunResult& r = *out->result;
    const int w = out->run.settings.width, h = out->run.settings.height;
    RunInputs inputs;  // what the summary and the files say the run was
    inputs.plan = p.plan;
    inputs.source = std::make_unique<SourceFile>(p.source->name(), p.source->text());
    inputs.scene_spec = scene.spec;
    inputs.scene = std::make_unique<SceneInput>();
    inputs.scene->scene = scene.scene();
    inputs.planned = true;
    inputs.load_warnings = scene.warnings;
    RunRecord record;
    record.inputs = &inputs;
    record.outcome = &*out;
    WrittenRun written;
    if (!files.images.empty()) {
        if (std::string error = write_run_files(files, record, written); !error.empty()) raise_input_error(error);
    } else {
        written.summary = run_summary_json(run_facts(files, record, nullptr));
    }
    py::dict result;
    result["image"] = image_array(r.image(), w, h);
    py::dict components;  // none with components=False: the film kept no sum per component
    for (size_t a = 0; a < kAovCount && options.component_images; ++a) components[py::str(aov_name(a))] = image_array(r.aov_image(a), w, h);
    result["components"] = components;
    py::dict maps;
    for (const auto& [name, raster] : r.maps) maps[py::str(name)] = image_array(raster.v, raster.width, raster.height, raster.channels);
    result["maps"] = maps;
    py::array_t<uint32_t> spp({static_cast<py::ssize_t>(h), static_cast<py::ssize_t>(w)});
    for (uint32_t q = 0; q < r.film.pixel_count(); ++q) spp.mutable_data()[q] = r.film.samples(q);
    result["samples_per_pixel"] = spp;
    if (r.staged) result["preview"] = image_array(r.preview, w, h);
    result["summary"] = py::module_::import("json").attr("loads")(written.summary.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
    return result;
}

// --- Checking and comparing -----------------------------------------------------------------

std::vector<PythonDiagnostic> check(const std::string& text, const py::object& scene) {
    DiagnosticSink sink;
    SourceFile file(text.find("pipeline") != std::string::npos ? "<pipeline>" : "<crex>", text);
    std::optional<PythonScene> loaded;
    std::optional<SceneFacts> facts;
    if (!scene.is_none()) {
        loaded = scene_of(scene);
        facts = scene_facts(loaded->spec, loaded->scene());
    }
    if (file.name() == "<pipeline>") {
        compile_pipeline(file, facts ? &*facts : nullptr, sink);
    } else if (CompiledCrex c = compile_crex(file, sink); c.program && facts) {
        for (const auto& d : find_dead_steps(*c.program, facts->spawnable))
            sink.report("W103", d.where.in(file), "step " + std::string(1, component_letter(d.component)) + " can never have work in " +
                                                      loaded->spec)
                .notes.push_back({{}, d.reason});
    }
    return diagnostics_of(sink);
}

py::dict compare(const py::array_t<float, py::array::c_style | py::array::forcecast>& test_array,
                 const py::array_t<float, py::array::c_style | py::array::forcecast>& reference_array, const std::vector<std::string>& wanted) {
    metrics::Image test, ref;
    test.rgb = rgb_of(test_array, test.width, test.height);
    ref.rgb = rgb_of(reference_array, ref.width, ref.height);
    if (test.width != ref.width || test.height != ref.height) throw std::invalid_argument("the images differ in size");
    // As `crex compare` refuses an EXR with them: a NaN made rmse NaN and FLIP 0 ("perfect").
    for (const auto& [image, name] : {std::pair{&test.rgb, "test"}, std::pair{&ref.rgb, "reference"}}) {
        const size_t bad = static_cast<size_t>(std::count_if(image->begin(), image->end(), [](float x) { return !std::isfinite(x); }));
        if (bad) throw std::invalid_argument(fmt::format("the {} image holds {} non-finite value{} (NaN or Inf): nothing to compare", name, bad, bad == 1 ? "" : "s"));
    }
    // Linear radiance, both seen through the reference's exposure, as `crex compare` sees EXRs
    // (the same metrics::compare_images).
    metrics::MetricChoice choice;
    for (const auto& m : wanted) {
        if (m == "rmse") choice.rmse = true;
        else if (m == "relmse") choice.relmse = true;
        else if (m == "ssim") choice.ssim = true;
        else if (m == "flip") choice.flip = true;
        else if (m == "perr") choice.perr = true;
        else throw std::invalid_argument("unknown metric '" + m + "': expected some of rmse, relmse, ssim, flip, perr");
    }
    const metrics::ImageComparison c = metrics::compare_images(test, ref, {true, display_exposure(ref.rgb)}, choice);
    py::dict out;
    auto put = [&](const char* name, const std::optional<double>& v) { out[name] = v ? py::cast(*v) : py::none(); };
    if (choice.rmse) put("rmse", c.rmse);
    if (choice.relmse) put("relmse", c.relmse);
    if (choice.ssim) put("ssim", c.ssim);
    if (choice.flip) put("flip", c.flip);
    if (choice.perr) put("perr", c.perr);
    return out;
}

}  // namespace
}  // namespace crex::python

PYBIND11_MODULE(_crex, m) {
    using namespace crex;
    using namespace crex::python;
    m.doc() = "crex: selective-rendering pipelines compiled and run (the C++ half of the crex package)";
    g_error = py::reinterpret_borrow<py::object>(PyExc_RuntimeError);
    g_error = py::module_::import("builtins").attr("type")("CrexError", py::make_tuple(py::reinterpret_borrow<py::object>(PyExc_Exception)),
                                                             py::dict(py::arg("__module__") = "crex"));
    g_compile_error = py::module_::import("builtins").attr("type")("CompileError", py::make_tuple(g_error), py::dict(py::arg("__module__") = "crex"));
    g_input_error = py::module_::import("builtins").attr("type")("InputError", py::make_tuple(g_error), py::dict(py::arg("__module__") = "crex"));
    m.attr("CrexError") = g_error;
    m.attr("CompileError") = g_compile_error;
    m.attr("InputError") = g_input_error;

    py::class_<PythonDiagnostic>(m, "Diagnostic")
        .def_readonly("code", &PythonDiagnostic::code)
        .def_readonly("severity", &PythonDiagnostic::severity)
        .def_readonly("message", &PythonDiagnostic::message)
        .def_readonly("file", &PythonDiagnostic::file)
        .def_readonly("line", &PythonDiagnostic::line)
        .def_readonly("column", &PythonDiagnostic::column)
        .def_readonly("end_line", &PythonDiagnostic::end_line)
        .def_readonly("end_column", &PythonDiagnostic::end_column)
        .def_readonly("notes", &PythonDiagnostic::notes)
        .def_readonly("help", &PythonDiagnostic::help)
        .def("__str__", [](const PythonDiagnostic& d) { return d.text; })
        .def("__repr__", [](const PythonDiagnostic& d) {
            return "<Diagnostic " + d.code + " " + d.file + ":" + std::to_string(d.line) + ":" + std::to_string(d.column) + ": " + d.message + ">";
        });

    py::class_<PythonScene>(m, "Scene")
        .def_readonly("spec", &PythonScene::spec)
        .def("census", [](const PythonScene& s) {
            return py::module_::import("json").attr("loads")(to_json(take_census(s.scene())).dump());
        }, "The material census: which component bins the scene can ever fill.")
        .def("__repr__", [](const PythonScene& s) { return "<crex.Scene " + s.spec + ">"; });

    py::class_<PythonPlan>(m, "Plan")
        .def_property_readonly("name", [](const PythonPlan& p) { return p.plan.name; })
        .def_property_readonly("staged", [](const PythonPlan& p) { return p.plan.staged; })
        .def_property_readonly("scene", [](const PythonPlan& p) { return p.scene; })
        .def_property_readonly("dot", &PythonPlan::dot, "The plan as a Graphviz graph.")
        .def("to_dict", [](const PythonPlan& p) { return py::module_::import("json").attr("loads")(p.json().dump()); },
             "The plan as `crex plan --format json` writes it.")
        .def("__repr__", [](const PythonPlan& p) {
            return "<crex.Plan " + (p.plan.staged ? "pipeline " + p.plan.name : sched::to_crex(p.plan.program)) + ">";
        });

    m.def("load_scene", &crex::python::load_scene, py::arg("spec"), "Loads a scene: a .json, .rad or .obj file, or builtin:NAME.");
    m.def("compile", &crex::python::compile, py::arg("source"), py::arg("scene") = py::none(), py::arg("pipeline") = "",
          "Compiles a pipeline (its text, a .pipe path or a stdlib pipeline's name) or a crex for a scene; raises CompileError with the diagnostics.");
    m.def("check", &crex::python::check, py::arg("text"), py::arg("scene") = py::none(), "The diagnostics of a crex or a pipeline's text.");
    m.def("run", &crex::python::run, py::arg("plan"), py::arg("scene") = py::none(), py::arg("progress") = py::none(), py::arg("output") = py::none(),
          py::arg("options") = py::dict(), "Renders a plan (see crex.run).");
    m.def("compare", &crex::python::compare, py::arg("test"), py::arg("reference"), py::arg("metrics"), "Image metrics of two linear images.");
    m.def("read_image", &read_image_file, py::arg("path"), "An image file as a float32 array (height, width, 3), linear.");
    m.def("display_exposure", &display_exposure_of, py::arg("image"),
          "The tone map's exposure of a linear image (height, width, 3): 0.18 over its log-average luminance.");
    m.def("to_display", &to_display_array, py::arg("image"), py::arg("exposure"),
          "Linear RGB (any shape ending in 3) to display values in [0, 1] through `exposure`: Reinhard, then the sRGB curve.");
}
