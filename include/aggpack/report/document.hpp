#pragma once
#include <filesystem>
#include <map>
#include <string>
#include <variant>
#include <vector>

namespace aggpack {

// A report as a list of blocks, written both as Markdown (figures as links to files) and as
// one self-contained HTML page (SVG inline, PNG as data URIs). Text is plain: no markup.
struct Heading {
  int level = 2;
  std::string text;
};
struct Paragraph {
  std::string text;
};
struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::string caption;
};
struct Figure {
  std::string file;     // relative to the report, e.g. "figures/fig4.svg"
  std::string caption;
};
using Block = std::variant<Heading, Paragraph, Table, Figure>;

struct Document {
  std::string title;
  std::vector<Block> blocks;
};

std::string to_markdown(const Document& doc);

// `figures` maps each Figure::file to its bytes (SVG text or PNG).
std::string to_html(const Document& doc, const std::map<std::string, std::string>& figures);
// Which of a table's columns hold numbers (every cell that is not blank or a dash starts as a
// number does): the HTML right-aligns them and keeps each on one line.
std::vector<bool> numeric_columns(const Table& table);

std::string base64(const std::string& bytes);

}  // namespace aggpack
