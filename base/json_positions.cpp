#include "base/json_positions.h"

#include <fmt/format.h>

#include <cmath>
#include <iterator>
#include <set>
#include <vector>

namespace crex {
namespace {

// An input iterator over the text that counts how far the JSON lexer has read.
struct CountingIterator {
    using iterator_category = std::input_iterator_tag;
    using value_type = char;
    using difference_type = std::ptrdiff_t;
    using pointer = const char*;
    using reference = const char&;

    const char* p = nullptr;
    size_t* consumed = nullptr;

    reference operator*() const { return *p; }
    CountingIterator& operator++() {
        ++p;
        ++*consumed;
        return *this;
    }
    CountingIterator operator++(int) {
        CountingIterator old = *this;
        ++*this;
        return old;
    }
    bool operator==(const CountingIterator& o) const { return p == o.p; }
    bool operator!=(const CountingIterator& o) const { return p != o.p; }
};

}  // namespace

std::string escape_pointer_token(const std::string& key) {
    std::string out;
    for (char c : key) {
        if (c == '~') out += "~0";
        else if (c == '/') out += "~1";
        else out += c;
    }
    return out;
}

namespace {

constexpr size_t kMaxJsonDepth = 64;

class PositionSax {
public:
    PositionSax(const SourceFile& file, PositionedJson& out, DiagnosticSink& sink, const char* code)
        : file_(file), out_(out), sink_(sink), code_(code), dom_(out.value, false) {}

    size_t consumed = 0;

    bool null() { scalar(); return dom_.null(); }
    bool boolean(bool v) { scalar(); return dom_.boolean(v); }
    bool number_integer(nlohmann::json::number_integer_t v) { scalar(); return dom_.number_integer(v); }
    bool number_unsigned(nlohmann::json::number_unsigned_t v) { scalar(); return dom_.number_unsigned(v); }
    bool number_float(nlohmann::json::number_float_t v, const std::string& s) {
        std::string ptr = scalar();
        if (!std::isfinite(v)) {
            sink_.report(code_, out_.value_spans[ptr], fmt::format("{}: number {} is out of range",
                                                                   readable_json_path(ptr), s));
            ok_ = false;
        }
        return dom_.number_float(v, s);
    }
    bool string(std::string& v) { scalar(); return dom_.string(v); }
    bool binary(nlohmann::json::binary_t& v) { scalar(); return dom_.binary(v); }

    bool start_object(std::size_t n) {
        if (!open(false)) return false;
        return dom_.start_object(n);
    }
    bool key(std::string& k) {
        Frame& f = frames_.back();
        SourceSpan span = token_span(true);
        std::string ptr = f.pointer + "/" + escape_pointer_token(k);
        if (!f.keys.insert(k).second) {
            Diagnostic& d = sink_.report(code_, span, fmt::format("{}: duplicate key '{}'", readable_json_path(ptr), k));
            d.notes.push_back({out_.key_spans[ptr], "first given here"});
            ok_ = false;
        } else {
            out_.key_spans[ptr] = span;
        }
        f.key = k;
        return dom_.key(k);
    }
    bool end_object() { close(); return dom_.end_object(); }
    bool start_array(std::size_t n) {
        if (!open(true)) return false;
        return dom_.start_array(n);
    }
    bool end_array() { close(); return dom_.end_array(); }

    bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& ex) {
        std::string msg = ex.what();
        size_t at = msg.find("syntax error");
        if (at != std::string::npos) msg = msg.substr(at);
        else if ((at = msg.find("] ")) != std::string::npos) msg = msg.substr(at + 2);
        uint32_t offset = static_cast<uint32_t>(std::min(position > 0 ? position - 1 : 0, file_.text().size()));
        uint32_t end = std::min<uint32_t>(offset + 1, static_cast<uint32_t>(file_.text().size()));
        sink_.report(code_, {&file_, offset, end}, fmt::format("malformed JSON: {}", msg));
        ok_ = false;
        return false;
    }

    bool ok() const { return ok_; }

private:
    struct Frame {
        bool array = false;
        size_t next_index = 0;
        std::string key;
        std::string pointer;
        uint32_t begin = 0;
        std::set<std::string> keys;
    };

    std::string next_pointer() {
        if (frames_.empty()) return "";
        Frame& f = frames_.back();
        if (f.array) return f.pointer + "/" + std::to_string(f.next_index++);
        return f.pointer + "/" + escape_pointer_token(f.key);
    }

    // The token that ends at `consumed` (less trailing delimiters the lexer looked ahead at).
    SourceSpan token_span(bool is_string) {
        const std::string& t = file_.text();
        size_t end = std::min(consumed, t.size());
        while (end > 0 && std::string_view(" \t\r\n,:]}").find(t[end - 1]) != std::string_view::npos &&
               !(is_string && t[end - 1] == '"'))
            --end;
        size_t begin = end;
        if (end > 0 && t[end - 1] == '"') {
            begin = end - 1;
            while (begin > 0) {
                --begin;
                if (t[begin] != '"') continue;
                size_t slashes = 0;
                while (begin >= slashes + 1 && t[begin - slashes - 1] == '\\') ++slashes;
                if (slashes % 2 == 0) break;
            }
        } else {
            while (begin > 0 && (std::isalnum(static_cast<unsigned char>(t[begin - 1])) || t[begin - 1] == '.' ||
                                 t[begin - 1] == '-' || t[begin - 1] == '+'))
                --begin;
        }
        return {&file_, static_cast<uint32_t>(begin), static_cast<uint32_t>(end)};
    }

    std::string scalar() {
        std::string ptr = next_pointer();
        SourceSpan span = token_span(!frames_.empty() || true);
        out_.value_spans[ptr] = span;
        return ptr;
    }

    // Scenes and plans nest a few levels; a limit keeps the pointers (each as long as its
    // depth) linear in the file and every reader's recursion off the end of the stack (a
    // 20,000-deep plan crashed after 31 s, 60 KB of '[' 30,000 deep took 955 MB).
    bool open(bool array) {
        if (frames_.size() >= kMaxJsonDepth) {
            uint32_t at = static_cast<uint32_t>(consumed > 0 ? consumed - 1 : 0);
            sink_.report(code_, {&file_, at, at + 1}, fmt::format("JSON nested more than {} deep", kMaxJsonDepth));
            ok_ = false;
            return false;
        }
        std::string ptr = next_pointer();
        Frame f;
        f.array = array;
        f.pointer = ptr;
        f.begin = static_cast<uint32_t>(consumed > 0 ? consumed - 1 : 0);
        frames_.push_back(std::move(f));
        return true;
    }

    void close() {
        Frame& f = frames_.back();
        out_.value_spans[f.pointer] = {&file_, f.begin, static_cast<uint32_t>(std::min(consumed, file_.text().size()))};
        frames_.pop_back();
    }

    const SourceFile& file_;
    PositionedJson& out_;
    DiagnosticSink& sink_;
    const char* code_;
    nlohmann::detail::json_sax_dom_parser<nlohmann::json> dom_;
    std::vector<Frame> frames_;
    bool ok_ = true;
};

}  // namespace

SourceSpan PositionedJson::span(const std::string& pointer) const {
    std::string p = pointer;
    for (;;) {
        if (auto it = value_spans.find(p); it != value_spans.end()) return it->second;
        if (auto it = key_spans.find(p); it != key_spans.end()) return it->second;
        if (p.empty()) return {};
        p = p.substr(0, p.rfind('/'));
    }
}

SourceSpan PositionedJson::key_span(const std::string& pointer) const {
    if (auto it = key_spans.find(pointer); it != key_spans.end()) return it->second;
    return span(pointer);
}

bool parse_json_with_positions(const SourceFile& file, PositionedJson& out, DiagnosticSink& sink,
                               const char* syntax_code) {
    PositionSax sax(file, out, sink, syntax_code);
    const char* begin = file.text().data();
    CountingIterator first{begin, &sax.consumed};
    CountingIterator last{begin + file.text().size(), &sax.consumed};
    bool parsed = nlohmann::json::sax_parse(first, last, &sax, nlohmann::json::input_format_t::json, true,
                                              /*ignore_comments=*/true);
    return parsed && sax.ok();
}

std::string readable_json_path(const std::string& pointer) {
    std::string out;
    size_t i = 0;
    while (i < pointer.size()) {
        size_t next = pointer.find('/', i + 1);
        std::string token = pointer.substr(i + 1, next == std::string::npos ? std::string::npos : next - i - 1);
        bool index = !token.empty() && token.find_first_not_of("0123456789") == std::string::npos;
        if (index) out += "[" + token + "]";
        else out += (out.empty() ? "" : ".") + token;
        if (next == std::string::npos) break;
        i = next;
    }
    return out.empty() ? "(document)" : out;
}

}  // namespace crex
