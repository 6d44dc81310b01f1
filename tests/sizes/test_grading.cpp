#include "aggpack/sizes/grading.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "aggpack/core/error.hpp"

namespace aggpack {
namespace {

constexpr double kIn = 0.0254;

TEST(NamedGradings, EqualThePublishedTables) {
  const Grading t1 = *named_grading("fu2003_table1_coarse");
  ASSERT_EQ(t1.sieves.size(), 11u);
  EXPECT_EQ(t1.sieves[5].name, "#8");
  EXPECT_DOUBLE_EQ(t1.sieves[5].percent_passing, 2.7);
  EXPECT_DOUBLE_EQ(t1.sieves[8].opening, 12.5e-3);  // the paper's 0.5 in is the 12.5 mm sieve
  EXPECT_DOUBLE_EQ(t1.sieves[8].percent_passing, 45.4);
  EXPECT_DOUBLE_EQ(t1.sieves[9].percent_passing, 90.4);
  const Grading mid = *named_grading("astm_c33_fine_mid");
  EXPECT_DOUBLE_EQ(percent_passing_at(mid, 1.18e-3), 67.5);  // #16: (50 + 85) / 2
  EXPECT_DOUBLE_EQ(percent_passing_at(*named_grading("astm_c33_fine_min"), 0.600e-3), 25.0);
  EXPECT_DOUBLE_EQ(percent_passing_at(*named_grading("astm_c33_57_max"), 12.5e-3), 60.0);
  EXPECT_DOUBLE_EQ(percent_passing_at(*named_grading("astm_c33_67_min"), 19.0e-3), 90.0);
  for (const auto& name : named_grading_names()) EXPECT_TRUE(named_grading(name)) << name;
  EXPECT_FALSE(named_grading("astm_c33_99_mid"));
}

// Tables converted from inches put the #16 sieve at 1.245 mm and the metric ones at 1.18 mm:
// a blend of the two showed "#16" twice.
TEST(Grading, OpeningsNearAStandardSieveAreTakenAsItAndSaidSo) {
  const Grading t1 = *named_grading("fu2003_table1_coarse");
  ASSERT_EQ(t1.snapped.size(), 11u);
  EXPECT_EQ(t1.snapped[4].name, "#16");
  EXPECT_DOUBLE_EQ(t1.snapped[4].given, 0.049 * kIn);
  EXPECT_DOUBLE_EQ(t1.snapped[4].standard, 1.18e-3);
  EXPECT_DOUBLE_EQ(t1.sieves[4].opening, 1.18e-3);
  EXPECT_DOUBLE_EQ(t1.largest(), 25.0e-3);  // 1 in is the 25.0 mm sieve
  EXPECT_TRUE(named_grading("astm_c33_fine_mid")->snapped.empty());  // already standard

  // Unnamed sieves get the standard name; openings far from the series (EN 933-2's 1, 2 and
  // 4 mm, 15 % away) stay as given.
  Grading g = make_grading("g", {{"", 1.0e-3, 10}, {"", 2.0e-3, 30}, {"", 4.0e-3, 60}, {"", 9.3e-3, 100}}, "t", {});
  ASSERT_EQ(g.snapped.size(), 1u);
  EXPECT_EQ(g.sieves[3].name, "3/8in");
  EXPECT_DOUBLE_EQ(g.sieves[3].opening, 9.5e-3);
  EXPECT_DOUBLE_EQ(g.sieves[0].opening, 1.0e-3);
  // Two openings that would land on one sieve are both kept as given, not merged.
  g = make_grading("g", {{"", 4.6e-3, 40}, {"", 4.9e-3, 50}, {"", 9.5e-3, 100}}, "t", {});
  EXPECT_TRUE(g.snapped.empty());
  EXPECT_DOUBLE_EQ(g.sieves[0].opening, 4.6e-3);
  EXPECT_DOUBLE_EQ(g.sieves[1].opening, 4.9e-3);
}

TEST(Grading, FinenessModulusOfTheC33MidBand) {
  // Retained: #100 95, #50 82.5, #30 57.5, #16 32.5, #8 10, #4 2.5 -> 2.80.
  EXPECT_NEAR(fineness_modulus(*named_grading("astm_c33_fine_mid")), 2.80, 1e-12);
}

TEST(Grading, MaximumAndNominalMaximumSizesOfASieveAnalysis) {
  // C33 No. 67 mid-band: 100 % through 1 in, 95 % through 3/4 in: maximum 25 mm, nominal 19 mm.
  const Grading no67 = *named_grading("astm_c33_67_mid");
  EXPECT_DOUBLE_EQ(maximum_size(no67), 0.025);
  EXPECT_DOUBLE_EQ(nominal_maximum_size(no67), 0.019);
  // 89 % through 3/4 in retains more than 10 % there: the nominal maximum size is one sieve up.
  const Grading coarse = make_grading("g", {{"1in", 0.025, 100}, {"3/4in", 0.019, 89}, {"#4", 0.00475, 0}}, "t", {});
  EXPECT_DOUBLE_EQ(nominal_maximum_size(coarse), 0.025);
  // Exactly 90 % passes: permitted (C33's 90 to 100 %).
  const Grading edge = make_grading("g", {{"1in", 0.025, 100}, {"3/4in", 0.019, 90}, {"#4", 0.00475, 0}}, "t", {});
  EXPECT_DOUBLE_EQ(nominal_maximum_size(edge), 0.019);
  // A grading whose top sieve alone passes 100 %: both sizes are that sieve.
  const Grading top = make_grading("g", {{"1in", 0.025, 100}, {"3/4in", 0.019, 50}}, "t", {});
  EXPECT_DOUBLE_EQ(maximum_size(top), 0.025);
  EXPECT_DOUBLE_EQ(nominal_maximum_size(top), 0.025);
}

TEST(Grading, InterpolatesLinearlyInLogOpening) {
  const Grading g = make_grading("g", {{"a", 1.0, 0.0}, {"b", 4.0, 100.0}}, "test", {});
  EXPECT_NEAR(percent_passing_at(g, 2.0), 50.0, 1e-12);
  EXPECT_NEAR(opening_at_percent(g, 50.0), 2.0, 1e-12);
  EXPECT_EQ(percent_passing_at(g, 5.0), 100.0);
}

TEST(Bands, FlagAGradingThatLeavesTheBandAtTheRightSieves) {
  const Band band = *named_band("astm_c33_fine");
  EXPECT_TRUE(check_against_band(*named_grading("astm_c33_fine_mid"), band).all_inside());
  Grading g = *named_grading("astm_c33_fine_mid");
  for (Sieve& s : g.sieves) {
    if (s.name == "#50") s.percent_passing = 35.0;  // above the 30 % limit
    if (s.name == "#16") s.percent_passing = 45.0;  // below the 50 % limit
  }
  const BandCheck check = check_against_band(g, band);
  EXPECT_FALSE(check.all_inside());
  for (const BandCheckRow& row : check.rows)
    EXPECT_EQ(row.inside, row.sieve.name != "#50" && row.sieve.name != "#16") << row.sieve.name;
  // The paper's coarse grading lies inside the No. 57 band.
  EXPECT_TRUE(check_against_band(*named_grading("fu2003_table1_coarse"), *named_band("astm_c33_57")).all_inside());
}

TEST(GradingLaws, FullerAndModifiedAndreasen) {
  const GradingLaw fuller{GradingLawKind::Fuller, 0.0254, 0.5, 0.0};
  EXPECT_NEAR(law_percent_passing(fuller, 0.0254 / 4), 50.0, 1e-12);
  const Grading g = grading_from_law(fuller);
  EXPECT_EQ(g.sieves.back().percent_passing, 100.0);
  EXPECT_NEAR(percent_passing_at(g, 4.75e-3), 100.0 * std::sqrt(4.75e-3 / 0.0254), 1e-9);
  const GradingLaw da{GradingLawKind::ModifiedAndreasen, 0.0254, 0.37, 0.075e-3};
  EXPECT_NEAR(law_percent_passing(da, 0.075e-3), 0.0, 1e-12);
  EXPECT_NEAR(law_percent_passing(GradingLaw{GradingLawKind::Power045, 1.0, 0.5, 0.0}, 0.5),
              100.0 * std::pow(0.5, 0.45), 1e-12);
  EXPECT_THROW(grading_from_law({GradingLawKind::ModifiedAndreasen, 0.0254, 0.37, 0.03}), InputError);
}

struct Bad {
  const char* name;
  std::vector<Sieve> sieves;
  std::vector<std::string> expected;
};

TEST(Grading, BadGradingsAreRefusedNamingTheRow) {
  const std::vector<std::string> rows{"row 1", "row 2", "row 3"};
  const std::vector<Bad> cases = {
      {"decreasing", {{"a", 1, 10}, {"b", 2, 5}, {"c", 3, 100}}, {"row 2", "must not decrease"}},
      {"above 100", {{"a", 1, 10}, {"b", 2, 120}, {"c", 3, 100}}, {"row 2", "between 0 and 100"}},
      {"negative percent", {{"a", 1, -1}, {"b", 2, 100}}, {"row 1", "between 0 and 100"}},
      {"one sieve", {{"a", 1, 100}}, {"at least two"}},
      {"no 100", {{"a", 1, 10}, {"b", 2, 90}}, {"row 2", "passes 100 %"}},
      {"duplicate", {{"a", 1, 10}, {"b", 1, 20}, {"c", 3, 100}}, {"row 1", "row 2", "duplicate"}},
      {"negative size", {{"a", -1, 10}, {"b", 2, 100}}, {"row 1", "positive length"}},
  };
  for (const Bad& c : cases) {
    try {
      make_grading("g", c.sieves, "grading.csv", rows);
      ADD_FAILURE() << c.name << ": accepted";
    } catch (const InputError& e) {
      for (const auto& part : c.expected)
        EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << c.name << ": " << e.what();
    }
  }
}

TEST(Grading, ReadsCsvFilesAndNamesTheLineOfABadValue) {
  const auto dir = std::filesystem::temp_directory_path() / "aggpack_grading_test";
  std::filesystem::create_directories(dir);
  const auto good = (dir / "sand.csv").string();
  std::ofstream(good) << "# a sand\nsieve,opening_mm,percent_passing\n#4,4.75,100\n#16,1.18,60\n#100,0.15,5\n";
  const Grading g = read_grading_csv(good);
  ASSERT_EQ(g.sieves.size(), 3u);
  EXPECT_DOUBLE_EQ(g.sieves[0].opening, 0.15e-3);
  EXPECT_EQ(g.sieves[1].name, "#16");
  const auto bad = (dir / "bad.csv").string();
  std::ofstream(bad) << "sieve,opening_mm,percent_passing\n#4,4.75,100\n#16,,60\n";
  try {
    read_grading_csv(bad);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.csv:3: missing sieve opening"), std::string::npos) << e.what();
  }
  std::ofstream(bad) << "sieve,opening_mm,percent_passing\n#4,4.75,100\n#16,1.18,110\n";
  try {
    read_grading_csv(bad);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("line 3"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

// The message of the InputError `f` throws; a failure if it throws none.
template <class F>
std::string refusal(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted";
  return {};
}

// A sand in millimetres under a bare `opening` header was read in inches, 25.4 times too
// coarse (issue 34): a bare number has no unit, so the column is refused showing both readings.
TEST(Grading, ABareOpeningColumnNeedsAUnitAndItsRefusalShowsBothReadings) {
  const std::string sand = "sieve,opening,percent_passing\n#200,0.075,1.5\n#100,0.150,4\n#16,1.18,66\n"
                           "#4,4.75,97\n3/8in,9.5,100\n";
  const std::string why = refusal([&] { (void)parse_grading_csv(sand, "sand.csv"); });
  for (const char* part : {"sand.csv:1", "'opening'", "line 2", "0.075 mm", "1.905 mm", "opening_mm", "opening_in",
                           "length_unit", "#200 is 0.075 mm"})
    EXPECT_NE(why.find(part), std::string::npos) << part << " in: " << why;
  // With its unit, from the header, from the caller (a scenario's length_unit) or in the
  // values, the same sand is the same grading.
  std::string in_mm = sand;
  in_mm.replace(in_mm.find("opening"), 7, "opening_mm");
  const Grading g = parse_grading_csv(in_mm, "sand.csv");
  EXPECT_DOUBLE_EQ(g.smallest(), 0.075e-3);
  EXPECT_DOUBLE_EQ(fineness_modulus(parse_grading_csv(sand, "sand.csv", 1e-3)), fineness_modulus(g));
  const Grading with_units = parse_grading_csv(
      "opening,percent_passing\n0.075 mm,1.5\n0.15 mm,4\n1.18mm,66\n4.75 mm,97\n0.375 in,100\n", "sand.csv");
  EXPECT_DOUBLE_EQ(fineness_modulus(with_units), fineness_modulus(g));
  // Other unit suffixes on the header, as the units a scenario knows.
  EXPECT_DOUBLE_EQ(parse_grading_csv("opening_cm,percent_passing\n0.475,10\n0.95,100\n", "c.csv").smallest(),
                   4.75e-3);
  // A value with no unit among ones with a unit is refused in the same way.
  EXPECT_NE(refusal([] { (void)parse_grading_csv("opening,percent_passing\n4.75 mm,10\n9.5,100\n", "m.csv"); })
                .find("line 3: 9.5 is 9.5 mm"),
            std::string::npos);
}

// A designation and an opening that contradict each other (a #200 given as 0.075 in) cannot
// both be right: refused naming the row, the designation's opening and the one given.
TEST(Grading, ASieveDesignationThatContradictsItsOpeningIsRefused) {
  const std::string inches = "sieve,opening_in,percent_passing\n#200,0.075,1.5\n#4,4.75,97\n3/8in,9.5,100\n";
  const std::string why = refusal([&] { (void)parse_grading_csv(inches, "sand.csv"); });
  for (const char* part : {"sand.csv", "line 2", "#200", "0.075 mm", "1.905 mm", "0.075 in"})
    EXPECT_NE(why.find(part), std::string::npos) << part << " in: " << why;
  // Inline sieves of a scenario, and the usual spellings of a designation.
  for (const char* name : {"#4", "No. 4", "no4", "4.75 mm", "4.75mm"})
    EXPECT_NE(refusal([&] {
                (void)make_grading("g", {{name, 4.75 * kIn, 50}, {"", 9.5 * kIn, 100}}, "t",
                                   {"sieves[0]", "sieves[1]"});
              }).find("sieves[0]"),
              std::string::npos)
        << name;
  for (const char* name : {"3/8in", "3/8\"", "3/8 in", "0.375 in"})
    EXPECT_NE(refusal([&] { (void)make_grading("g", {{"", 0.3e-3, 50}, {name, 9.5e-6, 100}}, "t", {}); }).find(name),
              std::string::npos)
        << name;
  EXPECT_NE(refusal([] { (void)make_grading("g", {{"", 1e-3, 50}, {"1 1/2in", 37.5e-6, 100}}, "t", {}); })
                .find("1 1/2in"),
            std::string::npos);
  // Within the snapping tolerance they agree: an inch table's #16 (0.049 in = 1.245 mm), and
  // names that are no designation (EN 933-2's sieves named by number, "pan") are not checked.
  EXPECT_NO_THROW((void)parse_grading_csv(
      "sieve,opening_in,percent_passing\n#16,0.049,40\n#4,0.187,90\n3/8in,0.375,100\n", "t.csv"));
  EXPECT_NO_THROW((void)make_grading("g", {{"pan", 0.01e-3, 0}, {"2", 2e-3, 40}, {"No. 4", 4.75e-3, 100}}, "t", {}));
}

}  // namespace
}  // namespace aggpack
