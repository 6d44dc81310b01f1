#pragma once

namespace aggpack {

// std::visit with one lambda per alternative: std::visit(Overloaded{[](A&) {...}, [](B&) {...}}, v).
template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};
// The guide C++20 makes implicit; clang before 17 (the fuzz build's clang 14) still needs it.
template <class... F>
Overloaded(F...) -> Overloaded<F...>;

}  // namespace aggpack
