/// \file name_table.h
/// Enumerations with names, both ways, from one table of (value, name) pairs.
#pragma once

#include <optional>
#include <string_view>
#include <utility>

namespace crex {

template <class Table, class E>
std::string_view name_in(const Table& table, E value) {
    for (const auto& [v, name] : table)
        if (v == value) return name;
    return table[0].second;
}

template <class Table>
auto value_in(const Table& table, std::string_view name) -> std::optional<decltype(table[0].first)> {
    for (const auto& [v, n] : table)
        if (n == name) return v;
    return std::nullopt;
}

}  // namespace crex
