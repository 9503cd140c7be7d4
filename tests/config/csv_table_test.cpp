// The one CSV reader (config::CsvReader): comments, any column order, unit suffixes, quoted
// fields, column groups, and messages that name file, line and column.

#include <gtest/gtest.h>

#include <numbers>
#include <sstream>

#include "volcomp/config/csv_table.hpp"

namespace volcomp::config {
namespace {

CsvSchema pointsSchema() {
  CsvSchema schema;
  schema.add({"x", "y", "z"}, CsvQuantity::Length, true)
      .addGroup({"tx", "ty", "tz"}, CsvQuantity::Length)
      .add({"ea"}, CsvQuantity::Angle)
      .add({"weight"}, CsvQuantity::Number)
      .add({"direction"}, CsvQuantity::Direction)
      .ignore({"ox"});
  return schema;
}

// The ConfigError message of reading `text` to its end, or "" when it reads.
std::string readError(const std::string& text) {
  std::istringstream input(text);
  try {
    CsvReader csv(input, "in.csv", pointsSchema());
    while (csv.next()) {
      for (const char* name : {"x", "y", "z"}) csv.number(name);
      if (csv.has("direction")) csv.directions(csv.column("direction"));
    }
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), "in.csv");
    return e.what();
  }
  return {};
}

TEST(CsvReader, CommentsOrderCaseBomAndLineEnds) {
  std::istringstream input(
      "\xEF\xBB\xBF# exported by a tracer\r\n"
      "\r\n"
      " Z , weight,y,X\r\n"
      "# a comment between rows\n"
      "-30, 2, 20 ,+10\r\n"
      "\n"
      "1e2,1,0,-0.5\n");
  CsvReader csv(input, "in.csv", pointsSchema());
  EXPECT_EQ(csv.headerText(), "Z,weight,y,X");
  EXPECT_FALSE(csv.has("tx"));
  ASSERT_TRUE(csv.next());
  EXPECT_EQ(csv.line(), 5u);
  EXPECT_EQ(csv.number("x"), 10.0);
  EXPECT_EQ(csv.number("y"), 20.0);
  EXPECT_EQ(csv.number("z"), -30.0);
  EXPECT_EQ(csv.number("weight"), 2.0);
  ASSERT_TRUE(csv.next());
  EXPECT_EQ(csv.line(), 7u);
  EXPECT_EQ(csv.number("z"), 100.0);
  EXPECT_FALSE(csv.next());
}

TEST(CsvReader, UnitSuffixesConvertToMillimetresAndRadians) {
  // The bare names are mm and rad; suffixes state other units, the micro sign included.
  std::istringstream input(
      "x_mm,y_um,z_nm,ea_urad,tx_\xC2\xB5m,ty,tz\n"
      "1,2000,3000000,5,100,0,0\n");
  CsvReader csv(input, "in.csv", pointsSchema());
  ASSERT_TRUE(csv.next());
  EXPECT_DOUBLE_EQ(csv.number("x"), 1.0);
  EXPECT_DOUBLE_EQ(csv.number("y"), 2.0);
  EXPECT_DOUBLE_EQ(csv.number("z"), 3.0);
  EXPECT_DOUBLE_EQ(csv.number("ea"), 5e-6);
  EXPECT_DOUBLE_EQ(csv.number("tx"), 0.1);
  std::istringstream arcsec("x,y,z,ea_arcsec\n0,0,0,1\n");
  CsvReader seconds(arcsec, "in.csv", pointsSchema());
  ASSERT_TRUE(seconds.next());
  EXPECT_DOUBLE_EQ(seconds.number("ea"), std::numbers::pi / 648000.0);
}

TEST(CsvReader, DirectionsInOneFieldQuotedOrCompact) {
  std::istringstream input("x,y,z,direction\n1,2,3,+-0\n1,2,3,\"+,-,+\"\n1,2,3,- ? +\n");
  CsvReader csv(input, "in.csv", pointsSchema());
  const int column = csv.column("direction");
  using model::Direction;
  ASSERT_TRUE(csv.next());
  EXPECT_EQ(csv.directions(column),
            (model::Directions{Direction::Positive, Direction::Negative, Direction::Unknown}));
  ASSERT_TRUE(csv.next());
  EXPECT_EQ(csv.directions(column),
            (model::Directions{Direction::Positive, Direction::Negative, Direction::Positive}));
  ASSERT_TRUE(csv.next());
  EXPECT_EQ(csv.directions(column),
            (model::Directions{Direction::Negative, Direction::Unknown, Direction::Positive}));
}

TEST(CsvReader, IgnoredColumnsAreAcceptedAndNotRead) {
  std::istringstream input("x,ox,y,z,OX_mm\n1,zzz,2,3,4\n");
  EXPECT_THROW(CsvReader(input, "in.csv", pointsSchema()), ConfigError)
      << "ox twice (once with a suffix) is a duplicate";
  std::istringstream once("x,ox,y,z\n1,zzz,2,3\n");
  CsvReader csv(once, "in.csv", pointsSchema());
  ASSERT_TRUE(csv.next());
  EXPECT_EQ(csv.number("y"), 2.0);
}

TEST(CsvReader, RejectionsNameFileLineAndColumn) {
  const auto has = [](const std::string& message, const std::string& part) {
    return message.find(part) != std::string::npos;
  };
  std::string e = readError("");
  EXPECT_TRUE(has(e, "empty file")) << e;
  e = readError("# only a comment\n");
  EXPECT_TRUE(has(e, "empty file")) << e;
  e = readError("x,y\n1,2\n");
  EXPECT_TRUE(has(e, "in.csv: line 1: missing column \"z\"")) << e;
  e = readError("x,y,z,w\n");
  EXPECT_TRUE(has(e, "line 1: unknown column \"w\"")) << e;
  EXPECT_TRUE(has(e, "x,y,z and optionally")) << e;
  e = readError("x,y,z,x_um\n");
  EXPECT_TRUE(has(e, "column \"x\" appears twice")) << e;
  e = readError("x,y,z,tx\n");
  EXPECT_TRUE(has(e, "give all of tx,ty,tz or none")) << e;
  e = readError("x,y,z_furlong\n");
  EXPECT_TRUE(has(e, "line 1, column z_furlong: expected a length unit")) << e;
  e = readError("x,y,z,weight_um\n");
  EXPECT_TRUE(has(e, "column \"weight\" takes no unit suffix")) << e;
  e = readError("x,y,z\n1,2,3\n# fine\n1,2\n");
  EXPECT_TRUE(has(e, "in.csv: line 4: expected 3 fields (x,y,z), got 2")) << e;
  e = readError("x,y,z\n1,two,3\n");
  EXPECT_TRUE(has(e, "in.csv: line 2, column y: expected a finite number, got \"two\"")) << e;
  for (const char* bad : {"nan", "inf", "", "1e999", "0x10", "1,5"}) {
    e = readError(std::string("x,y,z\n1,2,\"") + bad + "\"\n");
    EXPECT_TRUE(has(e, "line 2, column z: expected a finite number")) << bad << ": " << e;
  }
  e = readError("x,y,z,direction\n1,2,3,+-\n");
  EXPECT_TRUE(has(e, "line 2, column direction: expected one direction per axis")) << e;
  e = readError("x,y,z\n1,2,\"3\n");
  EXPECT_TRUE(has(e, "line 2: a quoted field is not closed")) << e;
  EXPECT_EQ(readError("x,y,z\n1,2,\"3\"\n"), "");
}

TEST(CsvReader, MissingFile) {
  try {
    CsvReader::open("/nonexistent/in.csv");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("/nonexistent/in.csv: cannot open file", 0), 0u)
        << e.what();
  }
}

// The unit may be written in the header as name_unit, "name [unit]", "name (unit)" or
// "name unit", for every schema; blanks and hyphens inside a name read as '_'.
TEST(CsvReader, UnitInTheHeaderInEveryForm) {
  std::istringstream input(
      "X [mm], y (\xC2\xB5m), z um, ea [deg], tx_in, ty (m), tz micron\n"
      "1, 2, 3, 180, 1, 0.5, 7\n");
  CsvReader csv(input, "in.csv", pointsSchema());
  ASSERT_TRUE(csv.next());
  EXPECT_EQ(csv.number("x"), 1.0);
  EXPECT_DOUBLE_EQ(csv.number("y"), 0.002);
  EXPECT_DOUBLE_EQ(csv.number("z"), 0.003);
  EXPECT_DOUBLE_EQ(csv.number("ea"), std::numbers::pi);
  EXPECT_DOUBLE_EQ(csv.number("tx"), 25.4);
  EXPECT_DOUBLE_EQ(csv.number("ty"), 500.0);
  EXPECT_DOUBLE_EQ(csv.number("tz"), 0.007);
  std::istringstream badUnit("x [furlong],y,z\n");
  try {
    CsvReader bad(badUnit, "in.csv", pointsSchema());
    ADD_FAILURE() << "furlong accepted";
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(),
                 "in.csv: line 1, column x [furlong]: expected a length unit \"mm\", \"um\", "
                 "\"nm\", \"m\" or \"in\", got \"furlong\"");
  }
  std::istringstream numberUnit("x,y,z,weight [kg]\n");
  EXPECT_THROW(CsvReader(numberUnit, "in.csv", pointsSchema()), ConfigError);
}

TEST(CsvReader, SemicolonsWithDecimalCommas) {
  std::istringstream input("x_mm;y;z;direction\n1,5;-2,25;3.5;\"+,-,+\"\n");
  CsvReader csv(input, "in.csv", pointsSchema());
  EXPECT_EQ(csv.headerText(), "x_mm;y;z;direction");
  ASSERT_TRUE(csv.next());
  EXPECT_EQ(csv.number("x"), 1.5);
  EXPECT_EQ(csv.number("y"), -2.25);
  EXPECT_EQ(csv.number("z"), 3.5);
  EXPECT_EQ(csv.directions(csv.column("direction"))[1], model::Direction::Negative);
  // A header with commas keeps commas as delimiters: "1,5" is then two fields.
  EXPECT_NE(readError("x,y,z\n1;5,2,3\n").find("line 2, column x: expected a finite number"),
            std::string::npos);
  // The decimal comma is read only in semicolon files, and the message shows the field as written.
  std::istringstream bad("x;y;z\n1,5;2;3,x\n");
  CsvReader badCsv(bad, "in.csv", pointsSchema());
  ASSERT_TRUE(badCsv.next());
  try {
    badCsv.number("z");
    ADD_FAILURE() << "3,x read";
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "in.csv: line 2, column z: expected a finite number, got \"3,x\"");
  }
}

CsvSchema instrumentSchema() {
  CsvSchema schema;
  schema.add({"target"}, CsvQuantity::Length)
      .add({"run"}, CsvQuantity::Number)
      .add({"label"}, CsvQuantity::Text)
      .alias("target", {"nominal", "target_position"})
      .alias("run", {"run_number", "cycle"});
  schema.lengthUnitRequired = true;
  schema.acceptOtherColumns = true;
  return schema;
}

TEST(CsvReader, AliasesRequiredUnitsAndOtherColumns) {
  std::istringstream input(
      "Run Number, Nominal Position [mm], Temp_C, target-position_x, Label, \n"
      "3, 12.5, 20.1, 9, first axis, , extra\n");
  CsvReader csv(input, "in.csv", instrumentSchema());
  EXPECT_EQ(csv.otherColumns(),
            (std::vector<std::string>{"Nominal Position [mm]", "Temp_C", "target-position_x"}))
      << "nominal_position is no alias, an unknown suffix makes another column";
  EXPECT_FALSE(csv.has("target"));

  std::istringstream aliased("cycle, Nominal (um), label\n2, 1500, a, b\n");
  CsvReader ok(aliased, "in.csv", instrumentSchema());
  EXPECT_TRUE(ok.otherColumns().empty());
  ASSERT_TRUE(ok.next()) << "more fields than the header are other columns";
  EXPECT_EQ(ok.number("run"), 2.0);
  EXPECT_DOUBLE_EQ(ok.number("target"), 1.5);
  EXPECT_EQ(ok.field(ok.column("label")), "a");
  EXPECT_EQ(ok.headerName(ok.column("target")), "Nominal (um)");

  const auto error = [](const std::string& text) -> std::string {
    std::istringstream in(text);
    try {
      CsvReader reader(in, "in.csv", instrumentSchema());
      while (reader.next()) reader.number("target");
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "(no error)";
  };
  EXPECT_EQ(error("run,target\n"),
            "in.csv: line 1, column target: a length column needs its unit in the header, e.g. "
            "\"target_mm\" (units: nm, um, mm, m, in)");
  EXPECT_EQ(error("nominal_mm,target_position [um]\n"),
            "in.csv: line 1: column \"target\" appears twice");
  EXPECT_EQ(error("target [parsec]\n"),
            "in.csv: line 1, column target [parsec]: expected a length unit \"mm\", \"um\", "
            "\"nm\", \"m\" or \"in\", got \"parsec\"");
  EXPECT_EQ(error("target_mm,run,label\n1,2\n"),
            "in.csv: line 2: expected 3 fields (target_mm,run,label), got 2");
  std::istringstream empty("# nothing\n\n");
  EXPECT_THROW(CsvReader(empty, "in.csv", instrumentSchema()), CsvNoHeader);
}

}  // namespace
}  // namespace volcomp::config
