#pragma once

namespace aggpack {

// std::visit with one lambda per alternative: std::visit(Overloaded{[](A&) {...}, [](B&) {...}}, v).
template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};

}  // namespace aggpack
