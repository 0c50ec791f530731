#include "base/components.h"

#include <string>

namespace crex {

std::string_view component_letters_spaced() {
    static const std::string letters = [] {
        std::string s;
        for (const auto& row : kComponentTable) {
            if (!s.empty()) s += ' ';
            s += row.letter;
        }
        return s;
    }();
    return letters;
}

}  // namespace crex
