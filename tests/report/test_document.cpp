#include <gtest/gtest.h>

#include "aggpack/report/document.hpp"

namespace aggpack {
namespace {

Document sample() {
  Document doc;
  doc.title = "T & t";
  doc.blocks.emplace_back(Heading{2, "Part"});
  doc.blocks.emplace_back(Paragraph{"a < b"});
  doc.blocks.emplace_back(Table{{"case", "value"}, {{"x|y", "0.5"}}, "caption"});
  doc.blocks.emplace_back(Figure{"figures/a.svg", "an svg"});
  doc.blocks.emplace_back(Figure{"figures/b.png", "a png"});
  return doc;
}

TEST(Document, MarkdownHasTablesAndFigureLinks) {
  const std::string md = to_markdown(sample());
  EXPECT_EQ(md.rfind("# T & t\n", 0), 0u);
  EXPECT_NE(md.find("## Part\n"), std::string::npos);
  EXPECT_NE(md.find("| case | value |\n| --- | --- |\n| x\\|y | 0.5 |\n"), std::string::npos);
  EXPECT_NE(md.find("![figures/a.svg](figures/a.svg)\n\n*an svg*"), std::string::npos);
}

TEST(Document, HtmlIsSelfContained) {
  const std::map<std::string, std::string> figures{{"figures/a.svg", "<?xml version=\"1.0\"?>\n<svg id=\"x\"></svg>"},
                                                   {"figures/b.png", "abc"}};
  const std::string html = to_html(sample(), figures);
  EXPECT_NE(html.find("<h1>T &amp; t</h1>"), std::string::npos);
  EXPECT_NE(html.find("<p>a &lt; b</p>"), std::string::npos);
  EXPECT_NE(html.find("<td>x|y</td>"), std::string::npos);
  EXPECT_NE(html.find("<svg id=\"x\"></svg>"), std::string::npos);
  EXPECT_EQ(html.find("<?xml"), std::string::npos);
  EXPECT_NE(html.find("src=\"data:image/png;base64,YWJj\""), std::string::npos);
  EXPECT_EQ(html.find("figures/"), std::string::npos);  // nothing links out
  EXPECT_THROW(to_html(sample(), {}), std::logic_error);
}

// At 700 px the report's summary table ran off the page: every table scrolls in its own box.
TEST(Document, HtmlTablesScrollSidewaysInsteadOfRunningOffThePage) {
  Document doc = sample();
  doc.blocks.emplace_back(Table{{"a", "b"}, {{"1", "2"}}, ""});
  const std::string html = to_html(doc, {{"figures/a.svg", "<svg></svg>"}, {"figures/b.png", "abc"}});
  std::size_t tables = 0;
  for (auto at = html.find("<table>"); at != std::string::npos; at = html.find("<table>", at + 1), ++tables)
    EXPECT_EQ(html.rfind("<div class=\"table-scroll\">\n", at), at - std::string("<div class=\"table-scroll\">\n").size());
  EXPECT_EQ(tables, 2u);
  EXPECT_NE(html.find(".table-scroll { overflow-x: auto; max-width: 100%; }"), std::string::npos);
}

// Text columns were right-aligned like numbers, and "0.612 (-2.2 %)" broke inside its cell:
// a column of numbers is right-aligned and kept on one line, any other is text, left-aligned.
TEST(Document, NumbersAlignRightOnOneLineAndTextAlignsLeft) {
  Document doc;
  doc.blocks.emplace_back(Table{{"mix", "protocol", "density", "ours − experiment"},
                                {{"3", "drop-and-roll, then DEM", "0.612 (-2.2 %)", "−0.014"},
                                 {"4", "pour", "—", "+0.003"},
                                 {"5", "experiment", "0.6600", ""}},
                                ""});
  EXPECT_EQ(numeric_columns(std::get<Table>(doc.blocks.front())), (std::vector<bool>{true, false, true, true}));
  const std::string html = to_html(doc, {});
  EXPECT_NE(html.find("<td class=\"num\">0.612 (-2.2 %)</td>"), std::string::npos) << html;
  EXPECT_NE(html.find("<td>drop-and-roll, then DEM</td>"), std::string::npos) << html;
  EXPECT_NE(html.find("<th class=\"num\">ours − experiment</th>"), std::string::npos) << html;
  EXPECT_NE(html.find("th.num, td.num { text-align: right; white-space: nowrap; }"), std::string::npos);
  EXPECT_NE(html.find("th, td { border: 1px solid #bbb; padding: 0.25em 0.6em; text-align: left; }"), std::string::npos);
}

TEST(Base64, KnownVectors) {
  EXPECT_EQ(base64(""), "");
  EXPECT_EQ(base64("f"), "Zg==");
  EXPECT_EQ(base64("fo"), "Zm8=");
  EXPECT_EQ(base64("foo"), "Zm9v");
  EXPECT_EQ(base64("foobar"), "Zm9vYmFy");
}

}  // namespace
}  // namespace aggpack
