#pragma once
#include <stdexcept>
#include <string>

namespace aggpack {

// Bad input from the user: a scenario, a particle file, a command-line value.
// The CLI maps it to exit code 2; anything else that escapes is an internal failure.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace aggpack
