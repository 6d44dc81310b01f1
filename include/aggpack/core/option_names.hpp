#pragma once
// How a caller's options are named in messages: the CLI's flags ("--ca-fa 0") or Python's
// keyword arguments ("ca_fa=0"), so that an error names what the caller typed.
#include <string>
#include <string_view>

namespace aggpack {

enum class OptionStyle { Cli, Keyword };

// `flag` as the CLI spells it ("--ca-fa"): itself, or Python's keyword ("ca_fa=").
inline std::string option_name(std::string_view flag, OptionStyle style) {
  if (style == OptionStyle::Cli) return std::string(flag);
  std::string keyword(flag.starts_with("--") ? flag.substr(2) : flag);
  for (char& c : keyword)
    if (c == '-') c = '_';
  return keyword + "=";
}

// The option with the value given: "--ca-fa 0", or "ca_fa=0".
inline std::string option_given(std::string_view flag, std::string_view value, OptionStyle style) {
  return option_name(flag, style) + (style == OptionStyle::Cli ? " " : "") + std::string(value);
}

}  // namespace aggpack
