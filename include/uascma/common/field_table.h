#pragma once
// What the field tables of configuration files share (campaign/config_fields.h, sim/scenario_fields.h): a key is
// a dotted path ("mission.cruise_speed_mps": section "mission", leaf "cruise_speed_mps"), and a row's member is a
// std::variant of pointers visited with one lambda per member type (Overloaded).
#include <string_view>

namespace uascma {

// "mission" of "mission.cruise_speed_mps"; "" for a top-level key.
constexpr std::string_view KeySection(std::string_view key) {
  const auto dot = key.rfind('.');
  return dot == std::string_view::npos ? std::string_view() : key.substr(0, dot);
}

// "cruise_speed_mps" of "mission.cruise_speed_mps".
constexpr std::string_view KeyLeaf(std::string_view key) {
  const auto dot = key.rfind('.');
  return dot == std::string_view::npos ? key : key.substr(dot + 1);
}

// std::visit(Overloaded{[](double* v) {…}, [](auto* v) {…}}, member).
template <typename... F>
struct Overloaded : F... {
  using F::operator()...;
};
// The deduction guide C++20 makes implicit for aggregates; clang 14 (the fuzz and sanitizer builds) still needs it.
template <typename... F>
Overloaded(F...) -> Overloaded<F...>;

}  // namespace uascma
