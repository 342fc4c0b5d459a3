// Requirements on case files: typed keys with messages that name the file, the key and
// what was expected; --set overrides any key; unknown sections and keys are refused.
// A --set key may quote its parts as TOML's dotted keys do (bar."elements") and carry
// spaces around them; a message echoes at most 200 characters of a key.
#include <gtest/gtest.h>

#include "gradmpm/app/BarCase.hpp"
#include "gradmpm/app/CaseKeys.hpp"
#include "gradmpm/core/Errors.hpp"

using namespace gradmpm;

namespace {
const char* kBar = R"(
[bar]
length = 10
elements = 80
split = 0.5
young = [1000.0, 5000]
end_displacement = 0.1
[gradient]
variant = "u-RA"
length_scale = 2.0
)";

std::string error_of(const std::vector<std::string>& overrides, const char* text = kBar) {
  try {
    CaseFile cf = CaseFile::parse(text, "case.toml", overrides);
    BarOutputOptions out;
    read_bar_config(cf, out);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(CaseFile, ReadsTypedKeysAndAcceptsIntegersAsNumbers) {
  CaseFile cf = CaseFile::parse(kBar, "case.toml");
  BarOutputOptions out;
  const BarConfig c = read_bar_config(cf, out);
  EXPECT_EQ(c.length, 10.0);
  EXPECT_EQ(c.elements, 80);
  EXPECT_EQ(c.young_right, 5000.0);
  EXPECT_EQ(c.variant, GradientVariant::U_RA);
  EXPECT_TRUE(out.plot);
}

TEST(CaseFile, SetOverridesAnyKey) {
  CaseFile cf = CaseFile::parse(kBar, "case.toml",
                                {"bar.elements=160", "gradient.variant=e-RA", "gradient.length_scale=1",
                                 "bar.young=[2e3, 4e3]", "output.plot=false"});
  BarOutputOptions out;
  const BarConfig c = read_bar_config(cf, out);
  EXPECT_EQ(c.elements, 160);
  EXPECT_EQ(c.variant, GradientVariant::E_RA);
  EXPECT_EQ(c.length_scale, 1.0);
  EXPECT_EQ(c.young_left, 2000.0);
  EXPECT_FALSE(out.plot);
}

TEST(CaseFile, MessagesNameFileKeyAndExpectation) {
  EXPECT_EQ(error_of({"bar.length=-1"}), "case.toml: bar.length (from --set): expected a length > 0, got -1");
  EXPECT_EQ(error_of({"bar.elements=0"}),
            "case.toml: bar.elements (from --set): expected an integer from 1 to 5000000, got 0");
  EXPECT_EQ(error_of({"bar.elements=8.5"}), "case.toml: bar.elements (from --set): expected an integer, got 8.5");
  EXPECT_EQ(error_of({"bar.length=ten"}), "case.toml: bar.length (from --set): expected a number, got \"ten\"");
  EXPECT_EQ(error_of({"gradient.length_scale=-0.5"}),
            "case.toml: gradient.length_scale (from --set): expected a length scale l >= 0, got -0.5");
  for (const char* s : {"bar.split=0", "bar.split=1", "bar.split=1.5", "bar.split=-0.2"})
    EXPECT_NE(error_of({s}).find("expected a fraction of the length strictly between 0 and 1"), std::string::npos) << s;
  EXPECT_EQ(error_of({"bar.young=[1000.0]"}),
            "case.toml: bar.young (from --set): expected an array of 2 numbers, got [ 1000.0 ]");
  EXPECT_NE(error_of({"bar.young=[1000.0, -5]"}).find("two Young's moduli > 0"), std::string::npos);
  EXPECT_NE(
      error_of({"gradient.variant=x-RA"}).find("expected one of \"u-RA\", \"e-RA\", \"s-RA\", \"none\", got \"x-RA\""),
      std::string::npos);
  EXPECT_NE(
      error_of({"bar.lenght=3"}).find("case.toml: bar.lenght (from --set): unknown key (valid keys in [bar]: length,"),
      std::string::npos);
  EXPECT_NE(error_of({"mesh.size=3"}).find("case.toml: unknown section [mesh]"), std::string::npos);
}

TEST(CaseFile, MissingKeysAndSectionsAreNamed) {
  EXPECT_EQ(error_of({}, "[bar]\nlength = 1.0\n[gradient]\nvariant = \"none\"\n"),
            "case.toml: bar.elements: missing key; expected an integer");
  EXPECT_NE(error_of({}, "[bar]\nlength = 1.0\n").find("case.toml: missing section [gradient]"), std::string::npos);
  EXPECT_EQ(error_of({}, R"([bar]
length = 10
elements = 8
split = 0.5
young = [1.0, 2.0]
end_displacement = 0.1
[gradient]
variant = "e-RA"
)"),
            "case.toml: gradient.length_scale: missing key; expected a number");
}

TEST(CaseFile, SyntaxErrorsGiveLineAndColumn) {
  EXPECT_NE(error_of({}, "[bar]\nlength = = 3\n").find("case.toml:2:"), std::string::npos);
}

TEST(CaseFile, MalformedOverridesAreRefused) {
  EXPECT_NE(error_of({"elements"}).find("--set 'elements': expected section.key=value"), std::string::npos);
  EXPECT_NE(error_of({"elements=3"}).find("--set 'elements=3': expected section.key=value"), std::string::npos);
  EXPECT_NE(error_of({"bar=3"}).find("expected section.key=value"), std::string::npos);
  EXPECT_NE(error_of({"bar.length.x=3"}).find("'length' is not a section"), std::string::npos);
}

TEST(CaseFile, HugeArrayIndicesAndCountsAreInputErrors) {
  // Issue 12: an index past stol's range used to escape as std::out_of_range (exit 1),
  // and output.vtk_every = 4294967297 wrapped to 1 when cast to int.
  const std::string mpm = "[grid]\norigin=[0.0]\ncell_size=1.0\ncells=[2]\n[[bodies]]\nmaterial=\"a\"\n";
  try {
    CaseFile::parse(mpm, "m.toml", {"bodies[99999999999999999999].material=soil"});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bodies has no entry [99999999999999999999]"), std::string::npos) << e.what();
  }
  const SectionSpec& out = mpm_section("output");
  CaseFile cf = CaseFile::parse("[output]\nvtk_every = 4294967297\n", "m.toml");
  EXPECT_THROW(read_integer(cf, "output", out.key("vtk_every")), InputError);
}

TEST(CaseFile, SetKeysMayQuoteTheirPartsAndCarrySpaces) {
  CaseFile cf = CaseFile::parse(kBar, "case.toml", {"\"bar\".\"elements\"=160", "bar.split =0.25", " bar . length=4"});
  BarOutputOptions out;
  const BarConfig c = read_bar_config(cf, out);
  EXPECT_EQ(c.elements, 160);
  EXPECT_EQ(c.split, 0.25);
  EXPECT_EQ(c.length, 4.0);
}

TEST(CaseFile, AMessageEchoesAtMostTwoHundredCharactersOfAKey) {
  const std::string e = error_of({"bar." + std::string(100000, 'k') + "=1"});
  EXPECT_NE(e.find("unknown key"), std::string::npos) << e.substr(0, 300);
  EXPECT_LT(e.size(), 600u) << e.substr(0, 300);
  EXPECT_NE(e.find(std::string(190, 'k') + "..."), std::string::npos);
}
