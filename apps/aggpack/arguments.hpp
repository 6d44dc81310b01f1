#pragma once
// The command line's own values (lengths, seeds, counts, lists), read with messages that name
// the option and say what it expects; each throws aggpack::InputError (exit code 2).
#include <cstdint>
#include <string>
#include <vector>

#include "aggpack/core/box.hpp"

// A length given on the command line; a bare number is in `bare_unit` (metres per unit).
double length_argument(const std::string& text, const std::string& option, long double bare_unit = 1.0L);
// A seed in the range a scenario's `seed` takes, 0 to 2^63 - 1: never wrapped or saturated.
std::uint64_t seed_argument(const std::string& text);
// A number above 0.
double positive_argument(const std::string& text, const std::string& option);
// A count of 1 or more, such as a number of seeds.
int count_argument(const std::string& text, const std::string& option);
// A wall-clock interval in seconds, >= 0, as the TOML value of output.checkpoint_every.
std::string seconds_argument(const std::string& text);
// The parts of "a,b,c", each as typed (without blanks around it).
std::vector<std::string> list_parts(const std::string& text);
// "a,b,c" as lengths (bare numbers in `bare_unit` metres), naming `option` in errors.
std::vector<double> lengths_argument(const std::string& text, const std::string& option, long double bare_unit = 1.0L);
// --box xmin,ymin,zmin,xmax,ymax,zmax (bare numbers in `bare_unit` metres).
aggpack::Box box_argument(const std::string& text, long double bare_unit);
