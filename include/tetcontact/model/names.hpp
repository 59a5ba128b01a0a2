// Names of enumerations as a case file and a summary spell them: one table per enum, written
// beside the enum, read by the case parser (text → value, and the list an error offers) and by
// whatever writes the value back out (value → text). No other place spells them.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace tc {

template <class E>
struct Named {
  E value;
  std::string_view name;
};

template <class E, std::size_t N>
using NameTable = std::array<Named<E>, N>;

/// The name of `value` in `table` ("" when the table lacks it).
template <class E, std::size_t N>
constexpr std::string_view name_of(const NameTable<E, N>& table, E value) {
  for (const Named<E>& n : table)
    if (n.value == value) return n.name;
  return {};
}

/// The value named `name`, if the table has it.
template <class E, std::size_t N>
constexpr std::optional<E> value_of(const NameTable<E, N>& table, std::string_view name) {
  for (const Named<E>& n : table)
    if (n.name == name) return n.value;
  return std::nullopt;
}

/// "a, b or c": the names in table order, for a message.
template <class E, std::size_t N>
std::string name_list(const NameTable<E, N>& table) {
  std::string out;
  for (std::size_t i = 0; i < N; ++i)
    out += std::string(i == 0 ? "" : (i + 1 == N ? " or " : ", ")) + std::string(table[i].name);
  return out;
}

}  // namespace tc
