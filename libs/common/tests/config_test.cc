#include "hmt/common/config.h"

#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "hmt/common/error.h"

namespace hmt {
namespace {

TEST(Config, ReadsValuesAndDefaults) {
  Config c = Config::from_string(
      "; comment\n[a]\nx = 1.5  ; trailing\nn = 3\nflag = true\nname = hi\n",
      "t.ini");
  EXPECT_DOUBLE_EQ(c.get_double("a", "x", 0), 1.5);
  EXPECT_EQ(c.get_int("a", "n", 0), 3);
  EXPECT_TRUE(c.get_bool("a", "flag", false));
  EXPECT_EQ(c.get_string("a", "name", ""), "hi");
  EXPECT_EQ(c.get_int("a", "missing", 9), 9);
  EXPECT_NO_THROW(c.check_all_used());
  EXPECT_NE(c.effective_ini().find("missing = 9"), std::string::npos);
}

TEST(Config, UnknownKeyIsAnErrorNamingKeyAndFile) {
  Config c = Config::from_string("[a]\nx = 1\nparticels = 30\n", "my.ini");
  c.get_double("a", "x", 0);
  try {
    c.check_all_used();
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("particels"), std::string::npos) << m;
    EXPECT_NE(m.find("my.ini"), std::string::npos) << m;
  }
}

TEST(Config, MalformedValuesAreErrors) {
  Config c = Config::from_string("[a]\nx = 1.5abc\nn = 2.5\nb = maybe\nz = nan\n", "t.ini");
  EXPECT_THROW(c.get_double("a", "x", 0), ConfigError);
  EXPECT_THROW(c.get_int("a", "n", 0), ConfigError);
  EXPECT_THROW(c.get_bool("a", "b", false), ConfigError);
  EXPECT_THROW(c.get_double("a", "z", 0), ConfigError);
}

TEST(Config, MalformedLinesAreErrors) {
  EXPECT_THROW(Config::from_string("[a\nx=1\n", "t"), ConfigError);
  EXPECT_THROW(Config::from_string("[a]\njust words\n", "t"), ConfigError);
  EXPECT_THROW(Config::from_string("x = 1\n", "t"), ConfigError);
  EXPECT_THROW(Config::from_string("[a]\nx=1\nx=2\n", "t"), ConfigError);
}

TEST(Config, OverrideWinsAndIsChecked) {
  Config c = Config::from_string("[a]\nx = 1\n", "t");
  c.apply_override("a.x=2");
  c.apply_override("b.y = 3");
  EXPECT_DOUBLE_EQ(c.get_double("a", "x", 0), 2.0);
  EXPECT_THROW(c.check_all_used(), ConfigError);  // b.y never read
  EXPECT_THROW(c.apply_override("novalue"), ConfigError);
}

// The effective configuration a run writes (effective_ini) must read back
// as the values it ran with: values an INI file cannot hold are refused
// where they come in. Found by fuzz_config (testdata/fuzz/): "J =#..." made
// [a] J the value "#...", written back as "J = #...", a comment.
TEST(Config, ValuesAnIniFileCannotHoldAreRefused) {
  auto message = [](const std::function<void()>& fn) {
    try {
      fn();
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no ConfigError");
  };
  const std::string found = std::string(HMT_SOURCE_DIR) +
                            "/libs/common/tests/testdata/fuzz/config-value-starts-with-comment.ini";
  const std::string m = message([&] { Config::from_file(found); });
  EXPECT_NE(m.find(found + ":6: [a] J = '#"), std::string::npos) << m;
  EXPECT_NE(m.find("holds '#' where it would start a comment"), std::string::npos) << m;
  EXPECT_NE(message([] { Config::from_string("[a]\nx =;1\n", "t"); }).find("t:2: [a] x"),
            std::string::npos);

  Config c = Config::from_string("[a]\nx = 1 ; a comment\ny = a;b#c\n", "t");
  EXPECT_EQ(c.get_string("a", "x", ""), "1");
  EXPECT_EQ(c.get_string("a", "y", ""), "a;b#c");  // no blank before: not a comment
  const std::string s = message([&] { c.apply_override("a.x=2 ;comment"); });
  EXPECT_NE(s.find("--set 'a.x=2 ;comment': the value holds ';'"), std::string::npos) << s;
  EXPECT_NE(message([&] { c.apply_override("a.x=2\n[b]"); }).find("line break"), std::string::npos);
  EXPECT_NE(message([&] { c.apply_override("a.x=#2"); }).find("holds '#'"), std::string::npos);
  c.apply_override("a.x=2;3");
  EXPECT_EQ(c.get_string("a", "x", ""), "2;3");
  Config back = Config::from_string(c.effective_ini(), "effective");
  EXPECT_EQ(back.get_string("a", "x", ""), "2;3");
}

TEST(Config, MissingFileIsConfigError) {
  EXPECT_THROW(Config::from_file("/nonexistent/x.ini"), ConfigError);
}

TEST(Config, DoubleOrAutoTakesEitherAndRecordsIt) {
  Config cfg = Config::from_string("[s]\na = auto\nb = 2.5\nc = far\n", "t.ini");
  double a = 1.0, b = 1.0, c = 1.0, d = 7.0, e = 8.0;
  bool a_auto = false, b_auto = true, c_auto = true, d_auto = true, e_auto = false;
  cfg.get_double_or_auto("s", "a", &a, &a_auto);
  EXPECT_TRUE(a_auto);
  EXPECT_EQ(a, 1.0);
  cfg.get_double_or_auto("s", "b", &b, &b_auto);
  EXPECT_FALSE(b_auto);
  EXPECT_EQ(b, 2.5);
  cfg.get_double_or_auto("s", "d", &d, &d_auto);  // absent: the default, auto
  EXPECT_TRUE(d_auto);
  cfg.get_double_or_auto("s", "e", &e, &e_auto);  // absent: the default, a number
  EXPECT_FALSE(e_auto);
  EXPECT_EQ(e, 8.0);
  const std::string eff = cfg.effective_ini();
  EXPECT_NE(eff.find("a = auto"), std::string::npos) << eff;
  EXPECT_NE(eff.find("d = auto"), std::string::npos) << eff;
  EXPECT_NE(eff.find("e = 8"), std::string::npos) << eff;
  EXPECT_THROW(cfg.get_double_or_auto("s", "c", &c, &c_auto), ConfigError);
}

}  // namespace
}  // namespace hmt
