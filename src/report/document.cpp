#include "aggpack/report/document.hpp"

#include <algorithm>
#include <cctype>
#include <stdexcept>

#include <fmt/format.h>

#include "aggpack/core/overloaded.hpp"
#include "aggpack/core/xml_text.hpp"

namespace aggpack {

namespace {

std::string md_cell(const std::string& text) {
  std::string out;
  for (const char c : text) {
    if (c == '|') out += "\\|";
    else if (c != '\n') out += c;
  }
  return out;
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

std::string to_markdown(const Document& doc) {
  std::string out = "# " + doc.title + "\n";
  for (const Block& block : doc.blocks) {
    out += "\n";
    std::visit(Overloaded{
                   [&](const Heading& h) { out += std::string(static_cast<std::size_t>(h.level), '#') + " " + h.text + "\n"; },
                   [&](const Paragraph& p) { out += p.text + "\n"; },
                   [&](const Table& t) {
                     if (!t.caption.empty()) out += t.caption + "\n\n";
                     out += "|";
                     for (const auto& h : t.header) out.append(" ").append(md_cell(h)).append(" |");
                     out += "\n|";
                     for (std::size_t i = 0; i < t.header.size(); ++i) out += " --- |";
                     out += "\n";
                     for (const auto& row : t.rows) {
                       out += "|";
                       for (const auto& cell : row) out.append(" ").append(md_cell(cell)).append(" |");
                       out += "\n";
                     }
                   },
                   [&](const Figure& f) { out += "![" + f.file + "](" + f.file + ")\n\n*" + f.caption + "*\n"; },
               },
               block);
  }
  return out;
}

std::vector<bool> numeric_columns(const Table& table) {
  // A number's cell starts with a digit, a sign (ASCII or U+2212), "±" or "."; an empty cell
  // or a dash ("—", "-": nothing to report) goes with either kind.
  const auto starts_a_number = [](const std::string& cell) {
    return !cell.empty() && (std::isdigit(static_cast<unsigned char>(cell[0])) || cell[0] == '+' || cell[0] == '.' ||
                             (cell[0] == '-' && cell.size() > 1) || cell.starts_with("\u2212") || cell.starts_with("±"));
  };
  const auto is_blank = [](const std::string& cell) { return cell.empty() || cell == "-" || cell == "\u2014"; };
  std::size_t columns = table.header.size();
  for (const auto& row : table.rows) columns = std::max(columns, row.size());
  std::vector<bool> numeric(columns, false);
  for (std::size_t c = 0; c < columns; ++c) {
    bool any = false, all = true;
    for (const auto& row : table.rows) {
      if (c >= row.size() || is_blank(row[c])) continue;
      any = true;
      all = all && starts_a_number(row[c]);
    }
    numeric[c] = any && all;
  }
  return numeric;
}

std::string to_html(const Document& doc, const std::map<std::string, std::string>& figures) {
  std::string out = fmt::format(
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n<style>\n"
      "body {{ font-family: sans-serif; max-width: 980px; margin: 2em auto; padding: 0 1em; line-height: 1.45; }}\n"
      "table {{ border-collapse: collapse; margin: 0.5em 0 1.2em; font-size: 0.92em; }}\n"
      ".table-scroll {{ overflow-x: auto; max-width: 100%; }}\n"
      "th, td {{ border: 1px solid #bbb; padding: 0.25em 0.6em; text-align: left; }}\n"
      "th {{ background: #eee; }} th.num, td.num {{ text-align: right; white-space: nowrap; }}\n"
      "figure {{ margin: 1em 0; }} figcaption {{ font-size: 0.9em; color: #333; }}\n"
      "img, svg {{ max-width: 100%; height: auto; }}\n</style>\n</head>\n<body>\n<h1>{}</h1>\n",
      xml_escape(doc.title), xml_escape(doc.title));
  for (const Block& block : doc.blocks) {
    std::visit(Overloaded{
                   [&](const Heading& h) { out += fmt::format("<h{0}>{1}</h{0}>\n", h.level, xml_escape(h.text)); },
                   [&](const Paragraph& p) { out += "<p>" + xml_escape(p.text) + "</p>\n"; },
                   [&](const Table& t) {
                     // A wide table scrolls inside its box instead of running off a narrow page.
                     out += "<div class=\"table-scroll\">\n<table>\n";
                     if (!t.caption.empty()) out += "<caption>" + xml_escape(t.caption) + "</caption>\n";
                     const std::vector<bool> numeric = numeric_columns(t);
                     const auto cell_tag = [&](const char* tag, std::size_t column, const std::string& text) {
                       const bool num = column < numeric.size() && numeric[column];
                       return fmt::format("<{0}{1}>{2}</{0}>", tag, num ? " class=\"num\"" : "", xml_escape(text));
                     };
                     out += "<tr>";
                     for (std::size_t c = 0; c < t.header.size(); ++c) out += cell_tag("th", c, t.header[c]);
                     out += "</tr>\n";
                     for (const auto& row : t.rows) {
                       out += "<tr>";
                       for (std::size_t c = 0; c < row.size(); ++c) out += cell_tag("td", c, row[c]);
                       out += "</tr>\n";
                     }
                     out += "</table>\n</div>\n";
                   },
                   [&](const Figure& f) {
                     const auto it = figures.find(f.file);
                     if (it == figures.end()) throw std::logic_error("to_html: no content for figure " + f.file);
                     out += "<figure>\n";
                     if (ends_with(f.file, ".svg")) {
                       const auto start = it->second.find("<svg");
                       out += it->second.substr(start == std::string::npos ? 0 : start);
                     } else {
                       out += "<img alt=\"" + xml_escape(f.caption) + "\" src=\"data:image/png;base64," +
                              base64(it->second) + "\">\n";
                     }
                     out += "<figcaption>" + xml_escape(f.caption) + "</figcaption>\n</figure>\n";
                   },
               },
               block);
  }
  out += "</body>\n</html>\n";
  return out;
}

std::string base64(const std::string& bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const auto v = (static_cast<unsigned>(static_cast<unsigned char>(bytes[i])) << 16) |
                   (static_cast<unsigned>(static_cast<unsigned char>(bytes[i + 1])) << 8) |
                   static_cast<unsigned>(static_cast<unsigned char>(bytes[i + 2]));
    out += {kAlphabet[(v >> 18) & 63], kAlphabet[(v >> 12) & 63], kAlphabet[(v >> 6) & 63], kAlphabet[v & 63]};
  }
  if (i + 1 == bytes.size()) {
    const auto v = static_cast<unsigned>(static_cast<unsigned char>(bytes[i])) << 16;
    out += {kAlphabet[(v >> 18) & 63], kAlphabet[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == bytes.size()) {
    const auto v = (static_cast<unsigned>(static_cast<unsigned char>(bytes[i])) << 16) |
                   (static_cast<unsigned>(static_cast<unsigned char>(bytes[i + 1])) << 8);
    out += {kAlphabet[(v >> 18) & 63], kAlphabet[(v >> 12) & 63], kAlphabet[(v >> 6) & 63], '='};
  }
  return out;
}

}  // namespace aggpack
