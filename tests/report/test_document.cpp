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

TEST(Base64, KnownVectors) {
  EXPECT_EQ(base64(""), "");
  EXPECT_EQ(base64("f"), "Zg==");
  EXPECT_EQ(base64("fo"), "Zm8=");
  EXPECT_EQ(base64("foo"), "Zm9v");
  EXPECT_EQ(base64("foobar"), "Zm9vYmFy");
}

}  // namespace
}  // namespace aggpack
