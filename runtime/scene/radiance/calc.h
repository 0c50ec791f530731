/// \file calc.h
/// RADIANCE's expression language (the language of its function files, `.cal`) as far as
/// crex evaluates it while loading a scene: genrev's curves, and mappings evaluated ahead of
/// rendering. Definitions `x = expr;`, constants `x : expr;`, functions `f(a, b) = expr;`
/// (recursive, and taking functions as arguments), `{ nested comments }`, the operators
/// + - * / ^ and unary -, and the library every RADIANCE expression may use (if, select, min,
/// max, the math functions, PI, and the helpers of RADIANCE's rayinit.cal: abs, sq, mod,
/// bound, Acos, Sqrt, and, or, ...). Arguments are evaluated lazily, as RADIANCE does, so
/// `if` only evaluates the branch it takes.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace crex::radiance::calc {

struct Node;

/// A problem with an expression: what, and where (byte offset in the text it came from).
struct Error {
    std::string message;
    size_t offset = 0;
};

/// Values the caller supplies: variables such as Dx or Px, and arg(i).
struct Environment {
    std::function<std::optional<double>(const std::string&)> variable;
    std::vector<double> args;  ///< arg(1) .. arg(n); arg(0) is their count
};

class Program {
public:
    Program();
    ~Program();
    Program(Program&&) noexcept;
    Program& operator=(Program&&) noexcept;

    /// Adds the definitions in `text` (later ones replace earlier ones of the same name).
    bool define(const std::string& text, Error& error);
    /// Parses one expression (no trailing `;` needed).
    std::shared_ptr<const Node> parse(const std::string& text, Error& error) const;

    /// Evaluates; nullopt with `error` for an unknown name, a wrong number of arguments, a
    /// recursion too deep or a value that is not finite.
    std::optional<double> evaluate(const Node& expr, const Environment& env, Error& error) const;
    /// Calls the function `name` with numeric arguments.
    std::optional<double> call(const std::string& name, const std::vector<double>& args, const Environment& env, Error& error) const;

    bool has_function(const std::string& name) const;
    bool has_variable(const std::string& name) const;
    /// Names the expression refers to that neither it, this program nor the library defines
    /// (the variables the caller must supply).
    std::vector<std::string> free_names(const Node& expr) const;
    /// Functions the expression (or a definition it uses) calls that nothing defines.
    std::vector<std::string> unknown_functions(const Node& expr) const;
    /// True when `name` is a function that takes `count` arguments (a definition's parameter
    /// count, or a library function's).
    bool takes(const std::string& name, size_t count) const;

    /// Resolves every name once, for evaluating many times: after it, each definition's
    /// names and every expression parse() returns name their definitions directly. A
    /// define() after it undoes it for the definitions (names may change meaning);
    /// expressions parsed while bound keep the definitions they were bound to.
    void bind();

    struct Definition;

private:
    void bind_node(Node& n) const;
    static void unbind_node(Node& n);
    bool bound_ = false;
    std::vector<std::shared_ptr<Definition>> retired_;  ///< replaced definitions bound nodes may still name
    std::map<std::string, std::shared_ptr<Definition>> defs_;
};

}  // namespace crex::radiance::calc
