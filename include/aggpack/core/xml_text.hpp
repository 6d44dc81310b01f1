#pragma once
#include <string>
#include <string_view>

namespace aggpack {

// Text made safe inside XML/HTML elements and attribute values.
inline std::string xml_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

// Text made safe inside an XML comment, where "--" may not appear and the text may not end
// in "-" (entities are not expanded there): each '-' that follows a '-' becomes '=' and a
// trailing '-' gets a space, so a path such as "my--runs/a.toml" stays readable.
inline std::string xml_comment_text(std::string_view text) {
  std::string out(text);
  for (std::size_t i = 1; i < out.size(); ++i)
    if (out[i] == '-' && out[i - 1] == '-') out[i] = '=';
  if (!out.empty() && out.back() == '-') out += ' ';
  return out;
}

}  // namespace aggpack
