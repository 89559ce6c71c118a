// The typed overrides studies build for their runs (case/overrides.hpp): each kind of value is
// written one way and read back by the case loader as the value meant; a key is named once, and
// every named key is one of the schema's (docs/case-schema.md).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "bagdem/case/case_reader.hpp"
#include "bagdem/case/overrides.hpp"
#include "bagdem/error.hpp"
#include "support.hpp"

using namespace bagdem;

TEST(Overrides, EachKindOfValueIsWrittenOneWay) {
  Overrides o({"simulation.duration=\"0.2 s\""});
  o.set(keys::timestep, 2.5e-7)
      .set(keys::attach, 0.3)
      .set(keys::seed, 12)
      .set(keys::bed_file, "a \"b\"\\c.data")
      .set(keys::cavity_max, Vec3(0.01, 0.02, 0.048))
      .set(keys::cavity_motion, "{kind=\"harmonic\", direction=[1, 0, 0]}")
      .set(keys::youngs_modulus("steel"), 2e11)
      .set(keys::friction("default"), 0);
  const std::vector<std::string> expected = {"simulation.duration=\"0.2 s\"",  // the given first, as given
                                             "simulation.timestep=2.5e-07",
                                             "primary.attach=\"0.3 m\"",
                                             "simulation.seed=12",
                                             "particles.bed.file='a \"b\"\\c.data'",  // toml_string: a literal string
                                             "cavity.max=[0.01, 0.02, 0.048]",
                                             "cavity.motion={kind=\"harmonic\", direction=[1, 0, 0]}",
                                             "materials.steel.youngs_modulus=2e+11",
                                             "interactions.default.friction=0"};
  EXPECT_EQ(o.sets(), expected);
}

TEST(Overrides, TheLoaderReadsBackWhatWasMeant) {
  bagdem::testing::TempDir t;
  t.write("case.toml", "[simulation]\nduration = \"1 s\"\n[particles.bed]\nfile = \"x\"\n[primary]\nattach = \"1 m\"\n");
  Overrides o;
  o.set(keys::duration, 0.123456789).set(keys::bed_file, "dir with 'quotes' and \\u0041/bed.data").set(keys::attach, 1.0 / 3.0);
  const CaseReader in((t.path / "case.toml").string(), o.sets());
  EXPECT_DOUBLE_EQ(in.quantity("simulation.duration", dim::time), 0.123456789);
  EXPECT_EQ(in.string("particles.bed.file"), "dir with 'quotes' and \\u0041/bed.data");
  EXPECT_NEAR(in.quantity("primary.attach", dim::length), 1.0 / 3.0, 1e-10);  // %.10g
}

TEST(Overrides, SetsKeyMatchesTheKeyOrAKeyInsideIt) {
  EXPECT_TRUE(sets_key("cavity.motion={kind=\"harmonic\"}", "cavity.motion"));
  EXPECT_TRUE(sets_key("cavity.motion.amplitude=\"1 mm\"", "cavity.motion"));
  EXPECT_TRUE(sets_key("simulation.duration = \"1 s\"", "simulation.duration"));
  EXPECT_TRUE(sets_key(" \tsimulation.seed\t= 5", "simulation.seed")) << "spaced as CaseReader reads it";
  EXPECT_FALSE(sets_key("cavity.motions=1", "cavity.motion"));
  EXPECT_FALSE(sets_key("simulation.durationx=1", "simulation.duration"));
  EXPECT_FALSE(sets_key("output.skip_cycles=1", "simulation.duration"));
}

// Each key the studies set is a key of the schema: its table is a section of docs/case-schema.md
// and its name a row or key there (a typo in keys:: fails here, not in a study's runs).
TEST(Overrides, EveryNamedKeyIsInTheSchema) {
  std::ifstream f(std::filesystem::path(BAGDEM_SOURCE_DIR) / "docs" / "case-schema.md");
  std::stringstream b;
  b << f.rdbuf();
  const std::string schema = b.str();
  ASSERT_GT(schema.size(), 1000u);
  for (const std::string& path : keys::all_paths()) {
    const std::string top = path.substr(0, path.find('.')), leaf = path.substr(path.rfind('.') + 1);
    EXPECT_NE(schema.find("[" + top), std::string::npos) << path << ": no section [" << top << "...] in docs/case-schema.md";
    EXPECT_TRUE(std::regex_search(schema, std::regex("(^|[^a-z_])" + leaf + "([^a-z_]|$)")))
        << path << ": '" << leaf << "' is not in docs/case-schema.md";
  }
  EXPECT_GE(keys::all_paths().size(), 25u);
}

// The defaults the reader offers (CaseReader::defaults, a map's damper record): each in SI as text,
// whether the key is given or not, and none for a key whose presence was asked (it alone may change
// the scene: a saved bag is moved only when bag.centre is given).
TEST(Overrides, TheReaderRecordsTheDefaultsItOffers) {
  bagdem::testing::TempDir t;
  t.write("case.toml", "[bag]\nshrink = 1\nname = \"4mm\"\n");
  const CaseReader in((t.path / "case.toml").string(), {});
  in.quantity("bag.shrink", dim::none, 1.0);
  in.quantity("bag.gap", dim::length, -0.0);
  in.string("bag.name", "4mm");
  in.vector("bag.axis", dim::none, Vec3(1, 0, -0.0));
  in.quantity_or_auto("bag.radius", dim::length);
  in.has("bag.centre");
  in.vector("bag.centre", dim::length, Vec3::Zero());
  const std::map<std::string, std::string> expected = {
      {"bag.axis", "[1, 0, 0]"}, {"bag.gap", "0"}, {"bag.name", "0.004"}, {"bag.radius", "auto"}, {"bag.shrink", "1"}};
  EXPECT_EQ(in.defaults(), expected) << "(a name default is unit-parsed here; the damper record keeps a material's name as written)";
}

// --set "key = value", spaced as a case file and a study's `set` write it, is key=value (the key's
// spaces were read as part of its name: "unknown key 'cavity.length '").
TEST(Overrides, ASpacedSetIsTheKeyAndTheValue) {
  bagdem::testing::TempDir t;
  t.write("case.toml", "[cavity]\nlength = \"70 mm\"\n");
  const CaseReader in((t.path / "case.toml").string(), {" cavity.length \t= \"80 mm\""});
  EXPECT_DOUBLE_EQ(in.quantity("cavity.length", dim::length), 0.08);
  EXPECT_NO_THROW(in.reject_unknown_keys());
  for (const std::string bad : {" = 1", "=1", "  "})
    EXPECT_THROW(CaseReader((t.path / "case.toml").string(), {bad}), InputError) << bad;
}
