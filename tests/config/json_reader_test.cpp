#include "volcomp/config/json_reader.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "temp_files.hpp"

namespace volcomp::config {
namespace {

// Runs `f`, expects a ConfigError and returns it.
template <class F>
ConfigError errorOf(F&& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e;
  }
  ADD_FAILURE() << "no ConfigError thrown";
  return ConfigError("", "", "");
}

TEST(JsonText, SyntaxErrorNamesFileLineAndColumn) {
  const ConfigError e = errorOf([] { parseJsonText("{\n  \"a\": 1,\n  \"b\": x\n}", "f.json"); });
  EXPECT_EQ(e.file(), "f.json");
  EXPECT_NE(std::string(e.what()).find("f.json: invalid JSON"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("line 3, column"), std::string::npos) << e.what();
}

// The parser quotes what it read of the failing token, which may be a whole string of any
// length: the message keeps its end only, and stays one line under 300 characters.
TEST(JsonText, ALongTokenInASyntaxErrorIsCutToItsEnd) {
  const std::string text = "{\"log_level\": \"" + std::string(5000, 'x') + "\x01\"}";
  const ConfigError e = errorOf([&] { parseJsonText(text, "d.json"); });
  const std::string what = e.what();
  EXPECT_EQ(what.rfind("d.json: invalid JSON: parse error at line 1, column 5016: ", 0), 0u)
      << what;
  // The end of the token, where the parser stopped (the control character), and no more.
  EXPECT_NE(what.find("last read: '...xxxxxxxx"), std::string::npos) << what;
  EXPECT_EQ(what.find(std::string(100, 'x')), std::string::npos) << what;
  EXPECT_EQ(what.substr(what.size() - 9), "<U+0001>'") << what;
  EXPECT_LE(what.size(), 300u) << what;
}

TEST(JsonText, NonStandardNanLiteralIsASyntaxError) {
  const ConfigError e = errorOf([] { parseJsonText("{\"a\": [1, NaN]}", "f.json"); });
  EXPECT_NE(std::string(e.what()).find("line 1, column"), std::string::npos) << e.what();
}

TEST(JsonText, NumberOverflowNamesLineAndColumn) {
  const ConfigError e = errorOf([] { parseJsonText("{\n \"a\": [1,\n  -2e999]}", "f.json"); });
  EXPECT_NE(std::string(e.what()).find("line 3, column 3"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("-2e999"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("out of the range of a double"), std::string::npos);
}

TEST(JsonText, NumberOverflowIsLocatedAsAWholeNumberOutsideStrings) {
  // The same digits inside a string and as the tail of a finite number come first.
  const ConfigError e = errorOf(
      [] { parseJsonText("{\"s\": \"1e309\", \"a\": 0.1e309,\n \"b\": 1e309}", "f.json"); });
  EXPECT_NE(std::string(e.what()).find("line 2, column 7"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("1e309"), std::string::npos) << e.what();
}

TEST(JsonText, DuplicateKeyNamesItsPath) {
  const ConfigError e =
      errorOf([] { parseJsonText(R"({"a": {"b": [1, {"c": 1, "c": 2}]}})", "f.json"); });
  EXPECT_EQ(e.keyPath(), "a.b[1].c");
  EXPECT_NE(e.message().find("duplicate key"), std::string::npos);
}

TEST(JsonText, DuplicateKeysInSeparateObjectsAreFine) {
  const auto j = parseJsonText(R"({"a": {"x": 1}, "b": {"x": 2}, "c": [{"x": 1}, {"x": 2}]})", "f");
  EXPECT_EQ(j["c"][1]["x"], 2);
}

TEST(JsonText, MissingFileNamesIt) {
  testing::TempDir dir;
  const std::string path = (dir.path() / "absent.json").string();
  const ConfigError e = errorOf([&] { readJsonFile(path); });
  EXPECT_EQ(e.file(), path);
  EXPECT_NE(e.message().find("cannot open"), std::string::npos);
}

TEST(JsonReader, PathsOfMembersAndElements) {
  const auto j = nlohmann::json::parse(R"({"a": {"b": [10, 20]}})");
  const JsonReader root(j, "f.json");
  const auto elements = root.at("a").at("b").elements();
  ASSERT_EQ(elements.size(), 2u);
  EXPECT_EQ(elements[1].path(), "a.b[1]");
  EXPECT_EQ(elements[1].number(), 20.0);
}

TEST(JsonReader, UnknownKeyListsTheAllowedOnes) {
  const auto j = nlohmann::json::parse(R"({"port": 1, "prot": 2})");
  const ConfigError e = errorOf([&] { JsonReader(j, "d.json").allowOnly({"port", "host"}); });
  EXPECT_EQ(e.keyPath(), "prot");
  EXPECT_STREQ(e.what(), "d.json: prot: unknown key; expected one of: port, host");
}

// A long list of keys is not written out: the line names the closest key and where the list is,
// or, without such a place, the first keys and how many there are; under 300 characters either way.
TEST(JsonReader, UnknownKeyAmongManyNamesTheClosestAndWhereTheyAreListed) {
  std::vector<std::string> allowed;
  for (int i = 0; i < 30; ++i) allowed.push_back("setting_number_" + std::to_string(i) + "_ms");
  const auto j = nlohmann::json::parse(R"({"setting_nuber_7_ms": 1, "colour": 2})");
  const JsonReader r(j, "d.json");
  const ConfigError typo = errorOf([&] { r.allowOnly(allowed, "docs/d.md, Keys"); });
  EXPECT_EQ(typo.keyPath(), "colour");  // the first unknown key in key order
  EXPECT_STREQ(typo.what(),
               "d.json: colour: unknown key (the 30 keys allowed here: docs/d.md, Keys)");
  const auto k = nlohmann::json::parse(R"({"setting_nuber_7_ms": 1})");
  const ConfigError close =
      errorOf([&] { JsonReader(k, "d.json").allowOnly(allowed, "docs/d.md"); });
  EXPECT_STREQ(
      close.what(),
      "d.json: setting_nuber_7_ms: unknown key; did you mean \"setting_number_7_ms\"? (the "
      "30 keys allowed here: docs/d.md)");
  const ConfigError unlisted = errorOf([&] { JsonReader(k, "d.json").allowOnly(allowed); });
  const std::string what = unlisted.what();
  EXPECT_EQ(
      what.rfind("d.json: setting_nuber_7_ms: unknown key; did you mean \"setting_number_7_ms\"? "
                 "Expected one of: setting_number_0_ms, ",
                 0),
      0u)
      << what;
  EXPECT_NE(what.find(", ... (30 keys)"), std::string::npos) << what;
  EXPECT_LE(what.size(), 300u) << what;
}

TEST(JsonReader, MissingRequiredKey) {
  const auto j = nlohmann::json::parse(R"({"modbus": {}})");
  const ConfigError e = errorOf([&] { JsonReader(j, "d.json").at("modbus").at("port"); });
  EXPECT_STREQ(e.what(), "d.json: modbus.port: missing required key");
}

TEST(JsonReader, IntegerRange) {
  const auto j = nlohmann::json::parse(R"({"a": 70000, "b": 1.5, "c": 1e3, "d": 502})");
  const JsonReader r(j, "d.json");
  EXPECT_STREQ(errorOf([&] { r.at("a").integer(1, 65535); }).what(),
               "d.json: a: expected an integer in [1, 65535], got 70000");
  EXPECT_THROW(r.at("b").integer(0, 10), ConfigError);
  EXPECT_EQ(r.at("c").integer(0, 5000), 1000);
  EXPECT_EQ(r.at("d").integer(1, 65535), 502);
}

TEST(JsonReader, NonFiniteNumbersFromAProgramAreRejected) {
  nlohmann::json j;
  j["a"] = std::numeric_limits<double>::quiet_NaN();
  j["b"] = -std::numeric_limits<double>::infinity();
  const JsonReader r(j, "d.json");
  EXPECT_STREQ(errorOf([&] { r.at("a").number(); }).what(),
               "d.json: a: expected a finite number, got NaN");
  EXPECT_STREQ(errorOf([&] { r.at("b").number(); }).what(),
               "d.json: b: expected a finite number, got -infinity");
}

TEST(JsonReader, StringChoicesAndTypes) {
  const auto j = nlohmann::json::parse(R"({"m": "lin", "n": 3, "v": [1, "x"], "t": true})");
  const JsonReader r(j, "d.json");
  EXPECT_STREQ(errorOf([&] {
                 r.at("m").oneOf({"linear", "cubic"});
               }).what(),
               "d.json: m: expected one of \"linear\", \"cubic\", got \"lin\"");
  EXPECT_STREQ(errorOf([&] { r.at("n").string(); }).what(), "d.json: n: expected a string, got 3");
  EXPECT_STREQ(errorOf([&] { r.at("v").numbers(); }).what(),
               "d.json: v[1]: expected a number, got \"x\"");
  EXPECT_STREQ(errorOf([&] { r.at("v").numbers(3); }).what(),
               "d.json: v: expected an array of 3 elements, got an array of 2");
  EXPECT_TRUE(r.at("t").boolean());
  EXPECT_EQ(r.numberOr("absent", 2.5), 2.5);
  EXPECT_EQ(r.stringOr("absent", "x"), "x");
}

}  // namespace
}  // namespace volcomp::config
