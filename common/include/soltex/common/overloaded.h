#pragma once

namespace soltex {

// Builds one visitor for std::visit from several lambdas.
template <class... Ts>
struct Overloaded : Ts... {
  using Ts::operator()...;
};
// Spelled out: clang 14 does not yet deduce template arguments of aggregates by itself.
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;

}  // namespace soltex
