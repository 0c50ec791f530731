#include "runtime/scene/radiance/calc.h"

#include <fmt/format.h>

#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <set>
#include <span>

#include "runtime/scene/radiance/noise.h"

namespace crex::radiance::calc {

// The library: functions whose arguments are all numbers (evaluated before the call), by
// name, each with its number of arguments (-1: one or more).
struct LibraryFunction {
    std::string_view name;
    int arity;
    double (*fn)(std::span<const double> a);
};

struct Node {
    enum class Kind { kNumber, kName, kParam, kCall, kCallParam, kNegate, kAdd, kSubtract, kMultiply, kDivide, kPower };
    Kind kind = Kind::kNumber;
    double value = 0;
    std::string name;
    int param = -1;
    std::vector<std::shared_ptr<Node>> kids;
    size_t offset = 0;
    // Set by Program::bind(): names resolved once, so evaluation looks nothing up by name.
    bool bound = false;
    const Program::Definition* def = nullptr;  // the definition a kName or kCall names, if any
    const LibraryFunction* lib = nullptr;      // else the library function a kCall names
    enum class Lazy : uint8_t { kNone, kIf, kSelect, kArg } lazy = Lazy::kNone;  // else if, select or arg
    // A kName no definition gives: a constant (PI), an argument (A3: 3; AC: 0), or -1 (the caller's).
    std::optional<double> constant;
    int argument = -1;
};

struct Program::Definition {
    std::vector<std::string> params;  // empty for a variable
    bool function = false;
    std::shared_ptr<Node> body;
};

namespace {

using NodePtr = std::shared_ptr<Node>;

// RADIANCE names carry an optional context mark (a backquote): `x` and x` name the same
// thing for us, who keep one context.
std::string plain_name(const std::string& n) {
    std::string out;
    for (char c : n)
        if (c != '`') out += c;
    return out;
}

class Parser {
public:
    explicit Parser(const std::string& t) : t_(t) {}

    bool at_end() {
        skip();
        return i_ >= t_.size();
    }
    bool peek(char c) {
        skip();
        return i_ < t_.size() && t_[i_] == c;
    }
    bool eat(char c) {
        if (!peek(c)) return false;
        ++i_;
        return true;
    }
    size_t pos() {
        skip();
        return i_;
    }
    bool name(std::string& out) {
        skip();
        if (i_ >= t_.size() || !(std::isalpha(static_cast<unsigned char>(t_[i_])) || t_[i_] == '`' || t_[i_] == '_')) return false;
        size_t b = i_;
        while (i_ < t_.size() && (std::isalnum(static_cast<unsigned char>(t_[i_])) || t_[i_] == '_' || t_[i_] == '.' || t_[i_] == '`')) ++i_;
        out = plain_name(t_.substr(b, i_ - b));
        return true;
    }
    NodePtr expression(Error& e) {
        nodes_ = 0;
        return sum(e);
    }
    void fail(Error& e, const std::string& message) {
        if (e.message.empty()) e = {message, std::min(pos(), t_.size())};
    }

private:
    void skip() {
        while (i_ < t_.size()) {
            if (std::isspace(static_cast<unsigned char>(t_[i_]))) {
                ++i_;
            } else if (t_[i_] == '{') {  // comments nest
                int depth = 0;
                do {
                    if (t_[i_] == '{') ++depth;
                    if (t_[i_] == '}') --depth;
                    ++i_;
                } while (i_ < t_.size() && depth > 0);
            } else {
                break;
            }
        }
    }
    NodePtr binary(Node::Kind k, NodePtr a, NodePtr b, size_t at) {
        if (++nodes_ > kMaxNodes) return nullptr;  // sum() and product() report it
        auto n = std::make_shared<Node>();
        n->kind = k;
        n->kids = {std::move(a), std::move(b)};
        n->offset = at;
        return n;
    }
    // Nesting deeper than this is not an expression a person wrote; refusing it keeps the
    // parser's recursion (and the evaluator's) far from the end of the stack.
    static constexpr int kMaxNesting = 200;
    struct Nest {
        int& depth;
        explicit Nest(int& d) : depth(d) { ++depth; }
        ~Nest() { --depth; }
    };
    NodePtr sum(Error& e) {
        Nest nest(depth_);
        if (depth_ > kMaxNesting) {
            fail(e, "the expression nests too deeply");
            return nullptr;
        }
        NodePtr a = product(e);
        while (a && (peek('+') || peek('-'))) {
            size_t at = pos();
            Node::Kind k = t_[i_++] == '+' ? Node::Kind::kAdd : Node::Kind::kSubtract;
            NodePtr b = product(e);
            if (!b) return nullptr;
            a = binary(k, a, b, at);
            if (!a) fail(e, "the expression is too long");
        }
        return a;
    }
    NodePtr product(Error& e) {
        NodePtr a = power(e);
        while (a && (peek('*') || peek('/'))) {
            size_t at = pos();
            Node::Kind k = t_[i_++] == '*' ? Node::Kind::kMultiply : Node::Kind::kDivide;
            NodePtr b = power(e);
            if (!b) return nullptr;
            a = binary(k, a, b, at);
            if (!a) fail(e, "the expression is too long");
        }
        return a;
    }
    NodePtr power(Error& e) {  // right associative; unary minus binds tighter (RADIANCE's rule)
        Nest nest(depth_);
        if (depth_ > kMaxNesting) {
            fail(e, "the expression nests too deeply");
            return nullptr;
        }
        NodePtr a = unary(e);
        if (a && peek('^')) {
            size_t at = pos();
            ++i_;
            NodePtr b = power(e);
            if (!b) return nullptr;
            NodePtr n = binary(Node::Kind::kPower, a, b, at);
            if (!n) fail(e, "the expression is too long");
            return n;
        }
        return a;
    }
    NodePtr unary(Error& e) {
        if (peek('-') || peek('+')) {
            size_t at = pos();
            bool neg = t_[i_++] == '-';
            NodePtr a = primary(e);
            if (!a || !neg) return a;
            auto n = std::make_shared<Node>();
            n->kind = Node::Kind::kNegate;
            n->kids = {a};
            n->offset = at;
            return n;
        }
        return primary(e);
    }
    NodePtr primary(Error& e) {
        size_t at = pos();
        if (eat('(')) {
            NodePtr a = sum(e);
            if (a && !eat(')')) {
                fail(e, "expected ')'");
                return nullptr;
            }
            return a;
        }
        if (i_ < t_.size() && (std::isdigit(static_cast<unsigned char>(t_[i_])) || t_[i_] == '.')) {
            const char* b = t_.c_str() + i_;
            char* end = nullptr;
            double v = std::strtod(b, &end);
            if (end == b) {
                fail(e, "expected a number");
                return nullptr;
            }
            i_ += static_cast<size_t>(end - b);
            auto n = std::make_shared<Node>();
            n->value = v;
            n->offset = at;
            return n;
        }
        std::string id;
        if (name(id)) {
            auto n = std::make_shared<Node>();
            n->kind = Node::Kind::kName;
            n->name = id;
            n->offset = at;
            if (eat('(')) {
                n->kind = Node::Kind::kCall;
                if (!eat(')')) {
                    do {
                        NodePtr a = sum(e);
                        if (!a) return nullptr;
                        n->kids.push_back(a);
                    } while (eat(','));
                    if (!eat(')')) {
                        fail(e, "expected ',' or ')' in the argument list");
                        return nullptr;
                    }
                }
            }
            return n;
        }
        fail(e, i_ < t_.size() ? fmt::format("unexpected '{}'", t_[i_]) : "the expression ends too soon");
        return nullptr;
    }

    // Left-associative chains are built by loops, not recursion: without a cap, 100 000 terms
    // made a tree whose recursive destruction overflowed the stack.
    static constexpr int kMaxNodes = 5000;

    const std::string& t_;
    size_t i_ = 0;
    int depth_ = 0;
    int nodes_ = 0;
};

// Names inside a function body that are its parameters become parameter references.
void bind_params(Node& n, const std::vector<std::string>& params) {
    for (size_t k = 0; k < params.size(); ++k) {
        if (n.name != params[k]) continue;
        if (n.kind == Node::Kind::kName) n.kind = Node::Kind::kParam, n.param = static_cast<int>(k);
        if (n.kind == Node::Kind::kCall) n.kind = Node::Kind::kCallParam, n.param = static_cast<int>(k);
    }
    for (auto& kid : n.kids) bind_params(*kid, params);
}

double deterministic_rand(double x) {  // rand(x): a fixed pseudo-random value in [0, 1) for each x
    uint64_t h;
    static_assert(sizeof h == sizeof x);
    std::memcpy(&h, &x, sizeof h);
    h ^= h >> 33, h *= 0xff51afd7ed558ccdull, h ^= h >> 33, h *= 0xc4ceb9fe1a85ec53ull, h ^= h >> 33;
    return static_cast<double>(h >> 11) * 0x1.0p-53;
}

double bound3(double lo, double x, double hi) { return x < lo ? lo : x > hi ? hi : x; }
double grey3(double r, double g, double b) { return std::fmax(0.265074126 * r + 0.670114631 * g + 0.064811243 * b, 0.0); }

const LibraryFunction kLibrary[] = {
    {"sin", 1, [](std::span<const double> a) { return std::sin(a[0]); }},
    {"cos", 1, [](std::span<const double> a) { return std::cos(a[0]); }},
    {"tan", 1, [](std::span<const double> a) { return std::tan(a[0]); }},
    {"asin", 1, [](std::span<const double> a) { return std::asin(a[0]); }},
    {"acos", 1, [](std::span<const double> a) { return std::acos(a[0]); }},
    {"atan", 1, [](std::span<const double> a) { return std::atan(a[0]); }},
    {"atan2", 2, [](std::span<const double> a) { return std::atan2(a[0], a[1]); }},
    {"exp", 1, [](std::span<const double> a) { return std::exp(a[0]); }},
    {"log", 1, [](std::span<const double> a) { return std::log(a[0]); }},
    {"log10", 1, [](std::span<const double> a) { return std::log10(a[0]); }},
    {"sqrt", 1, [](std::span<const double> a) { return std::sqrt(a[0]); }},
    {"floor", 1, [](std::span<const double> a) { return std::floor(a[0]); }},
    {"ceil", 1, [](std::span<const double> a) { return std::ceil(a[0]); }},
    {"erf", 1, [](std::span<const double> a) { return std::erf(a[0]); }},
    {"erfc", 1, [](std::span<const double> a) { return std::erfc(a[0]); }},
    {"rand", 1, [](std::span<const double> a) { return deterministic_rand(a[0]); }},
    // RADIANCE's noise functions (noise.h); noise3a/b/c are rayinit.cal's other names.
    {"noise3", 3, [](std::span<const double> a) { return noise3(a[0], a[1], a[2]); }},
    {"noise3x", 3, [](std::span<const double> a) { return noise3_partial(a[0], a[1], a[2], 0); }},
    {"noise3y", 3, [](std::span<const double> a) { return noise3_partial(a[0], a[1], a[2], 1); }},
    {"noise3z", 3, [](std::span<const double> a) { return noise3_partial(a[0], a[1], a[2], 2); }},
    {"noise3a", 3, [](std::span<const double> a) { return noise3_partial(a[0], a[1], a[2], 0); }},
    {"noise3b", 3, [](std::span<const double> a) { return noise3_partial(a[0], a[1], a[2], 1); }},
    {"noise3c", 3, [](std::span<const double> a) { return noise3_partial(a[0], a[1], a[2], 2); }},
    {"fnoise3", 3, [](std::span<const double> a) { return fnoise3(a[0], a[1], a[2]); }},
    {"min", -1, [](std::span<const double> a) {
         double r = a[0];
         for (double x : a) r = std::fmin(r, x);
         return r;
     }},
    {"max", -1, [](std::span<const double> a) {
         double r = a[0];
         for (double x : a) r = std::fmax(r, x);
         return r;
     }},
    // RADIANCE's rayinit.cal helpers.
    {"abs", 1, [](std::span<const double> a) { return std::fabs(a[0]); }},
    {"sgn", 1, [](std::span<const double> a) { return a[0] > 0 ? 1.0 : a[0] < 0 ? -1.0 : 0.0; }},
    {"sq", 1, [](std::span<const double> a) { return a[0] * a[0]; }},
    {"frac", 1, [](std::span<const double> a) { return a[0] - std::floor(a[0]); }},
    {"mod", 2, [](std::span<const double> a) { return a[0] - std::floor(a[0] / a[1]) * a[1]; }},
    {"tri", 2, [](std::span<const double> a) {
         const double m = (a[0] - a[1]) - std::floor((a[0] - a[1]) / (2 * a[1])) * (2 * a[1]);
         return std::fabs(a[1] - m);
     }},
    {"linterp", 3, [](std::span<const double> a) { return (1 - a[0]) * a[1] + a[0] * a[2]; }},
    {"bound", 3, [](std::span<const double> a) { return bound3(a[0], a[1], a[2]); }},
    {"inside", 3, [](std::span<const double> a) { return a[1] - a[0] > 0 ? a[2] - a[1] : a[1] - a[0]; }},
    {"Acos", 1, [](std::span<const double> a) { return std::acos(bound3(-1, a[0], 1)); }},
    {"Asin", 1, [](std::span<const double> a) { return std::asin(bound3(-1, a[0], 1)); }},
    {"Atan2", 2, [](std::span<const double> a) { return a[0] * a[0] + a[1] * a[1] > 0 ? std::atan2(a[0], a[1]) : 0.0; }},
    {"Exp", 1, [](std::span<const double> a) { return -a[0] - 100 > 0 ? 0.0 : std::exp(a[0]); }},
    {"Sqrt", 1, [](std::span<const double> a) { return a[0] > 0 ? std::sqrt(a[0]) : 0.0; }},
    {"and", 2, [](std::span<const double> a) { return a[0] > 0 ? a[1] : a[0]; }},
    {"or", 2, [](std::span<const double> a) { return a[0] > 0 ? a[0] : a[1]; }},
    {"not", 1, [](std::span<const double> a) { return a[0] > 0 ? -1.0 : 1.0; }},
    {"xor", 2, [](std::span<const double> a) { return a[0] > 0 ? (a[1] > 0 ? -1.0 : 1.0) : a[1]; }},
    {"noop", 1, [](std::span<const double> a) { return a[0]; }},
    {"clip", 1, [](std::span<const double> a) { return bound3(0, a[0], 1); }},
    {"noneg", 1, [](std::span<const double> a) { return std::fmax(a[0], 0.0); }},
    {"red", 3, [](std::span<const double> a) { return a[0] > 0 ? a[0] : 0.0; }},
    {"green", 3, [](std::span<const double> a) { return a[1] > 0 ? a[1] : 0.0; }},
    {"blue", 3, [](std::span<const double> a) { return a[2] > 0 ? a[2] : 0.0; }},
    {"grey", 3, [](std::span<const double> a) { return grey3(a[0], a[1], a[2]); }},
    {"clipgrey", 3, [](std::span<const double> a) { return std::fmin(grey3(a[0], a[1], a[2]), 1.0); }},
    {"clip_r", 3, [](std::span<const double> a) { return bound3(0, a[0], 1); }},
    {"clip_g", 3, [](std::span<const double> a) { return bound3(0, a[1], 1); }},
    {"clip_b", 3, [](std::span<const double> a) { return bound3(0, a[2], 1); }},
    // genrev's curve helpers (control values p0..p3, then t).
    {"hermite", 5, [](std::span<const double> a) {
         const double t = a[4];
         return a[0] * ((2 * t - 3) * t * t + 1) + a[1] * (-2 * t + 3) * t * t + a[2] * ((t - 2) * t + 1) * t + a[3] * (t - 1) * t * t;
     }},
    {"bezier", 5, [](std::span<const double> a) {
         const double t = a[4];
         return a[0] * (1 + t * (-3 + t * (3 - t))) + a[1] * 3 * t * (1 + t * (-2 + t)) + a[2] * 3 * t * t * (1 - t) + a[3] * t * t * t;
     }},
    {"bspline", 5, [](std::span<const double> a) {
         const double t = a[4];
         return a[0] * (1. / 6 + t * (-0.5 + t * (0.5 - t / 6))) + a[1] * (2. / 3 + t * t * (-1 + 0.5 * t)) +
                a[2] * (1. / 6 + t * (0.5 + t * (0.5 - 0.5 * t))) + a[3] * (t * t * t / 6);
     }},
};

const LibraryFunction* find_library(std::string_view name) {
    for (const LibraryFunction& f : kLibrary)
        if (f.name == name) return &f;
    return nullptr;
}

// Calls library function `f` (nullptr: unknown); `arity` says why not when the count is wrong.
std::optional<double> call_library(const LibraryFunction* f, std::span<const double> a, bool& known, std::string& arity) {
    known = f != nullptr;
    if (!f) return std::nullopt;
    if (f->arity < 0 ? a.empty() : a.size() != static_cast<size_t>(f->arity)) {
        arity = f->arity < 0 ? fmt::format("'{}' needs at least one argument", f->name)
                             : fmt::format("'{}' takes {} argument{}, got {}", f->name, f->arity, f->arity == 1 ? "" : "s", a.size());
        return std::nullopt;
    }
    return f->fn(a);
}

std::optional<double> library(const std::string& f, std::span<const double> a, bool& known, std::string& arity) {
    return call_library(find_library(f), a, known, arity);
}

std::optional<double> constant(const std::string& name) {
    constexpr double kPiValue = 3.14159265358979323846;
    if (name == "PI") return kPiValue;
    if (name == "DEGREE") return kPiValue / 180;
    if (name == "FTINY") return 1e-7;
    return std::nullopt;
}

bool lazy_builtin(const std::string& f) { return f == "if" || f == "select" || f == "arg"; }

constexpr int kMaxDepth = 2000;

// A function call's arguments, each evaluated (in the caller's frame) when first used and
// then kept: the language has no side effects, and RADIANCE's local frames (rayinit.cal's
// Ldx(...) of Idx of ...) use each argument many times.
struct Frame {
    const std::vector<NodePtr>* args = nullptr;
    const Frame* caller = nullptr;
    mutable std::array<double, 8> values{};
    mutable uint32_t known = 0;
};

class Evaluator {
public:
    Evaluator(const std::map<std::string, std::shared_ptr<Program::Definition>>& defs, const Environment& env, Error& error)
        : defs_(defs), env_(env), error_(error) {}

    std::optional<double> eval(const Node& n, const Frame& frame) {
        if (++depth_ > kMaxDepth) return fail(n, "recursion deeper than 2000 levels");
        std::optional<double> v = eval_node(n, frame);
        --depth_;
        if (v && !std::isfinite(*v)) return fail(n, "the value is not a finite number");
        return v;
    }

    std::optional<double> call(const std::string& name, const std::vector<NodePtr>& args, const Frame& args_frame, const Node& at) {
        const Program::Definition* def = nullptr;
        if (at.bound && &at.name == &name) {  // a call written as such (not a function passed as an argument)
            def = at.def;
        } else if (auto it = defs_.find(name); it != defs_.end()) {
            def = it->second.get();
        }
        const bool bound = at.bound && &at.name == &name;
        if (def && def->function) {
            const Program::Definition& d = *def;
            if (d.params.size() != args.size())
                return fail(at, fmt::format("'{}' takes {} arguments, got {}", name, d.params.size(), args.size()));
            Frame f{&args, &args_frame};
            return eval(*d.body, f);
        }
        if (bound ? at.lazy == Node::Lazy::kIf : name == "if") {
            if (args.size() != 3) return fail(at, fmt::format("'if' takes 3 arguments, got {}", args.size()));
            auto c = eval(*args[0], args_frame);
            if (!c) return c;
            return eval(*args[*c > 0 ? 1 : 2], args_frame);
        }
        if (bound ? at.lazy == Node::Lazy::kSelect : name == "select") {
            if (args.empty()) return fail(at, "'select' needs at least one argument");
            auto k = eval(*args[0], args_frame);
            if (!k) return k;
            const double i = std::floor(*k + 0.5);
            if (i == 0) return static_cast<double>(args.size() - 1);
            if (i < 1 || i >= static_cast<double>(args.size())) return fail(at, fmt::format("select({}, ...) is out of range", i));
            return eval(*args[static_cast<size_t>(i)], args_frame);
        }
        if (bound ? at.lazy == Node::Lazy::kArg : name == "arg") {
            if (args.size() != 1) return fail(at, "'arg' takes 1 argument");
            auto k = eval(*args[0], args_frame);
            if (!k) return k;
            const double i = std::floor(*k + 0.5);
            if (i == 0) return static_cast<double>(env_.args.size());
            if (i < 1 || i > static_cast<double>(env_.args.size()))
                return fail(at, fmt::format("arg({}) does not exist: the primitive has {} real arguments", i, env_.args.size()));
            return env_.args[static_cast<size_t>(i) - 1];
        }
        // The arguments on the stack (a library call at every evaluation must not allocate).
        double small[8];
        std::vector<double> large;
        if (args.size() > 8) large.resize(args.size());
        double* values = args.size() > 8 ? large.data() : small;
        for (size_t i = 0; i < args.size(); ++i) {
            auto v = eval(*args[i], args_frame);
            if (!v) return v;
            values[i] = *v;
        }
        bool known = false;
        std::string arity;
        const std::span<const double> given(values, args.size());
        std::optional<double> r = bound ? call_library(at.lib, given, known, arity) : library(name, given, known, arity);
        if (!known) return fail(at, fmt::format("unknown function '{}'", name));
        if (!r) return fail(at, arity);
        return r;
    }

private:
    std::optional<double> fail(const Node& n, const std::string& m) {
        if (error_.message.empty()) error_ = {m, n.offset};
        return std::nullopt;
    }

    std::optional<double> variable(const Node& n) {
        const Program::Definition* def = nullptr;
        if (n.bound) {
            def = n.def;
        } else if (auto it = defs_.find(n.name); it != defs_.end()) {
            def = it->second.get();
        }
        if (def) {
            if (def->function) return fail(n, fmt::format("'{}' is a function: give it arguments", n.name));
            // A variable has one value for the whole evaluation (the ray is fixed): kept.
            for (const auto& [d, v] : memo_)
                if (d == def) return v;
            auto v = eval(*def->body, Frame{});
            if (v && memo_.size() < kMaxMemo) memo_.emplace_back(def, *v);
            return v;
        }
        if (n.bound) {
            if (n.constant) return n.constant;
            if (n.argument == 0) return static_cast<double>(env_.args.size());
            if (n.argument > 0 && static_cast<size_t>(n.argument) <= env_.args.size()) return env_.args[static_cast<size_t>(n.argument) - 1];
        }
        if (env_.variable)
            if (auto v = env_.variable(n.name)) return v;
        if (auto c = constant(n.name)) return c;
        if (n.name.size() >= 2 && n.name[0] == 'A' && std::isdigit(static_cast<unsigned char>(n.name[1]))) {
            // A1, A2, ...: RADIANCE's names for arg(1), arg(2), ...
            size_t k = std::strtoul(n.name.c_str() + 1, nullptr, 10);
            if (n.name.find_first_not_of("0123456789", 1) == std::string::npos && k >= 1) {
                if (k > env_.args.size())
                    return fail(n, fmt::format("{} does not exist: the primitive has {} real arguments", n.name, env_.args.size()));
                return env_.args[k - 1];
            }
        }
        if (n.name == "AC") return static_cast<double>(env_.args.size());
        return fail(n, fmt::format("unknown variable '{}'", n.name));
    }

    std::optional<double> eval_node(const Node& n, const Frame& frame) {
        using K = Node::Kind;
        switch (n.kind) {
        case K::kNumber: return n.value;
        case K::kName: return variable(n);
        case K::kParam: {
            if (!frame.args || static_cast<size_t>(n.param) >= frame.args->size()) return fail(n, "parameter outside its function");
            const auto k = static_cast<size_t>(n.param);
            if (k < frame.values.size() && (frame.known >> k & 1)) return frame.values[k];
            auto v = eval(*(*frame.args)[k], frame.caller ? *frame.caller : Frame{});
            if (v && k < frame.values.size()) frame.values[k] = *v, frame.known |= 1u << k;
            return v;
        }
        case K::kCall: return call(n.name, n.kids, frame, n);
        case K::kCallParam: {
            // A function passed as an argument: the caller wrote its name there.
            if (!frame.args || static_cast<size_t>(n.param) >= frame.args->size()) return fail(n, "parameter outside its function");
            const Node& passed = *(*frame.args)[static_cast<size_t>(n.param)];
            if (passed.kind != K::kName) return fail(n, fmt::format("'{}' is called, but what was passed is not a function name", n.name));
            return call(passed.name, n.kids, frame, n);
        }
        case K::kNegate: {
            auto a = eval(*n.kids[0], frame);
            return a ? std::optional(-*a) : a;
        }
        default: break;
        }
        auto a = eval(*n.kids[0], frame);
        if (!a) return a;
        auto b = eval(*n.kids[1], frame);
        if (!b) return b;
        switch (n.kind) {
        case K::kAdd: return *a + *b;
        case K::kSubtract: return *a - *b;
        case K::kMultiply: return *a * *b;
        case K::kDivide:
            if (*b == 0) return fail(n, "division by zero");
            return *a / *b;
        default: return std::pow(*a, *b);
        }
    }

    static constexpr size_t kMaxMemo = 64;
    const std::map<std::string, std::shared_ptr<Program::Definition>>& defs_;
    const Environment& env_;
    Error& error_;
    int depth_ = 0;
    std::vector<std::pair<const Program::Definition*, double>> memo_;
};

}  // namespace

Program::Program() = default;
Program::~Program() = default;
Program::Program(Program&&) noexcept = default;
Program& Program::operator=(Program&&) noexcept = default;

bool Program::define(const std::string& text, Error& error) {
    if (bound_) {  // names may change meaning: resolve them again when asked to
        for (auto& [name, d] : defs_)
            if (d->body) unbind_node(*d->body);
        bound_ = false;
    }
    Parser p(text);
    while (!p.at_end()) {
        if (p.eat(';')) continue;
        std::string name;
        if (!p.name(name)) {
            p.fail(error, "expected a definition: name = expression;");
            return false;
        }
        auto d = std::make_shared<Definition>();
        if (p.eat('(')) {
            d->function = true;
            if (!p.eat(')')) {
                do {
                    std::string param;
                    if (!p.name(param)) {
                        p.fail(error, "expected a parameter name");
                        return false;
                    }
                    d->params.push_back(param);
                } while (p.eat(','));
                if (!p.eat(')')) {
                    p.fail(error, "expected ',' or ')' after a parameter");
                    return false;
                }
            }
        }
        if (!p.eat('=') && !p.eat(':')) {
            p.fail(error, fmt::format("expected '=' or ':' after '{}'", name));
            return false;
        }
        d->body = p.expression(error);
        if (!d->body) return false;
        if (!p.eat(';') && !p.at_end()) {
            p.fail(error, "expected ';' after the definition");
            return false;
        }
        bind_params(*d->body, d->params);
        if (auto old = defs_.find(name); old != defs_.end()) retired_.push_back(old->second);  // bound expressions may name it
        defs_[name] = d;
    }
    return true;
}

std::shared_ptr<const Node> Program::parse(const std::string& text, Error& error) const {
    Parser p(text);
    NodePtr n = p.expression(error);
    if (n && !p.at_end()) {
        p.fail(error, "unexpected text after the expression");
        return nullptr;
    }
    if (n && bound_) bind_node(*n);
    return n;
}

std::optional<double> Program::evaluate(const Node& expr, const Environment& env, Error& error) const {
    Evaluator e(defs_, env, error);
    return e.eval(expr, Frame{});
}

std::optional<double> Program::call(const std::string& name, const std::vector<double>& args, const Environment& env, Error& error) const {
    std::vector<NodePtr> nodes;
    for (double a : args) {
        auto n = std::make_shared<Node>();
        n->value = a;
        nodes.push_back(n);
    }
    Node at;
    at.name = name;
    Evaluator e(defs_, env, error);
    return e.call(name, nodes, Frame{}, at);
}

bool Program::has_function(const std::string& name) const {
    auto it = defs_.find(name);
    if (it != defs_.end()) return it->second->function;
    bool known = false;
    std::string arity;
    library(name, {}, known, arity);
    return known || lazy_builtin(name);
}

bool Program::has_variable(const std::string& name) const {
    auto it = defs_.find(name);
    return (it != defs_.end() && !it->second->function) || constant(name).has_value();
}

std::vector<std::string> Program::free_names(const Node& expr) const {
    std::set<std::string> out, seen_defs;
    std::function<void(const Node&)> walk = [&](const Node& n) {
        if (n.kind == Node::Kind::kName) {
            auto it = defs_.find(n.name);
            if (it != defs_.end() && !it->second->function) {
                if (seen_defs.insert(n.name).second) walk(*it->second->body);
            } else if (!constant(n.name)) {
                out.insert(n.name);
            }
        }
        if (n.kind == Node::Kind::kCall) {
            auto it = defs_.find(n.name);
            if (it != defs_.end() && it->second->function && seen_defs.insert(n.name + "()").second) walk(*it->second->body);
        }
        for (const auto& k : n.kids) walk(*k);
    };
    walk(expr);
    return {out.begin(), out.end()};
}

std::vector<std::string> Program::unknown_functions(const Node& expr) const {
    std::set<std::string> out, seen_defs;
    std::function<void(const Node&)> walk = [&](const Node& n) {
        if (n.kind == Node::Kind::kName) {
            auto it = defs_.find(n.name);
            if (it != defs_.end() && !it->second->function && seen_defs.insert(n.name).second) walk(*it->second->body);
        }
        if (n.kind == Node::Kind::kCall) {
            auto it = defs_.find(n.name);
            if (it != defs_.end() && it->second->function) {
                if (seen_defs.insert(n.name + "()").second) walk(*it->second->body);
            } else if (!has_function(n.name)) {
                out.insert(n.name);
            }
        }
        for (const auto& k : n.kids) walk(*k);
    };
    walk(expr);
    return {out.begin(), out.end()};
}

bool Program::takes(const std::string& name, size_t count) const {
    auto it = defs_.find(name);
    if (it != defs_.end()) return it->second->function && it->second->params.size() == count;
    bool known = false;
    std::string arity;
    const std::vector<double> values(count, 0.5);
    library(name, values, known, arity);
    return known && arity.empty();
}

void Program::bind_node(Node& n) const {
    if (n.kind == Node::Kind::kName || n.kind == Node::Kind::kCall) {
        auto it = defs_.find(n.name);
        n.def = it != defs_.end() ? it->second.get() : nullptr;
        if (n.kind == Node::Kind::kName && !n.def) {
            n.constant = constant(n.name);
            if (n.name == "AC") n.argument = 0;
            else if (n.name.size() >= 2 && n.name[0] == 'A' && n.name.find_first_not_of("0123456789", 1) == std::string::npos)
                n.argument = std::max(1, static_cast<int>(std::min<unsigned long>(std::strtoul(n.name.c_str() + 1, nullptr, 10), 1u << 20)));
        }
        if (n.kind == Node::Kind::kCall) {
            n.lib = find_library(n.name);
            n.lazy = n.name == "if" ? Node::Lazy::kIf : n.name == "select" ? Node::Lazy::kSelect : n.name == "arg" ? Node::Lazy::kArg : Node::Lazy::kNone;
        }
        n.bound = true;
    }
    for (const auto& k : n.kids) bind_node(*k);
}

void Program::unbind_node(Node& n) {
    n.bound = false;
    n.def = nullptr;
    n.lib = nullptr;
    n.lazy = Node::Lazy::kNone;
    n.constant.reset();
    n.argument = -1;
    for (const auto& k : n.kids) unbind_node(*k);
}

void Program::bind() {
    for (auto& [name, d] : defs_)
        if (d->body) bind_node(*d->body);
    bound_ = true;
}

}  // namespace crex::radiance::calc
