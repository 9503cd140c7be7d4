#include "volcomp/config/dbc_file.hpp"

#include <gtest/gtest.h>

#include "volcomp/config/config_error.hpp"

namespace volcomp::can {
namespace {

using config::parseDbc;
using config::readDbcFile;

// A small database in the shape CANdb++ writes: the NS_ block lists SIG_VALTYPE_ as a bare
// keyword, comments and attributes follow the messages.
constexpr const char* kDbc = R"(VERSION ""


NS_ :
	NS_DESC_
	CM_
	SIG_VALTYPE_

BS_:

BU_: PLC VOLCOMP

BO_ 256 Positions: 8 PLC
 SG_ X_Pos : 0|32@1- (0.0001,0) [-1000|1000] "mm" VOLCOMP
 SG_ Y_Pos : 32|32@1- (0.0001,0) [-1000|1000] "mm" VOLCOMP

BO_ 2147484160 Axes_Ext: 8 PLC
 SG_ Z_Pos : 7|32@0- (0.0001,-5) [0|0] "mm" VOLCOMP
 SG_ Enable : 32|1@1+ (1,0) [0|1] "" VOLCOMP
 SG_ Homed : 33|1@1+ (1,0) [0|1] "" VOLCOMP
 SG_ Seq : 56|8@1+ (1,0) [0|255] "" VOLCOMP

BO_ 768 Offsets: 8 VOLCOMP
 SG_ Off_X : 0|16@1- (0.001,0) [-0.5|0.5] "mm" PLC
 SG_ Status : 48|16@1+ (1,0) [0|65535] "" PLC

BO_ 1024 Misc: 64 PLC
 SG_ Temp : 0|32@1- (1,0) [0|0] "degC" VOLCOMP
 SG_ Mode M : 32|8@1+ (1,0) [0|0] "" VOLCOMP
 SG_ Seq : 40|8@1+ (1,0) [0|0] "" VOLCOMP
 SG_ Wide : 500|12@1+ (1E-3,+2.5) [0|0] "" VOLCOMP

BO_ 3221225472 VECTOR__INDEPENDENT_SIG_MSG: 0 Vector__XXX
 SG_ Orphan : 0|8@1+ (1,0) [0|0] "" Vector__XXX

CM_ SG_ 256 X_Pos "X axis position";
BA_DEF_ SG_  "GenSigStartValue" INT 0 10000;
SIG_VALTYPE_ 1024 Temp : 1;
)";

TEST(Dbc, ParsesMessagesAndSignals) {
  const DbcDatabase db = parseDbc(kDbc, "machine.dbc");
  ASSERT_EQ(db.messages.size(), 4u);  // the independent-signals pseudo-message is skipped

  const DbcMessage& positions = db.messages[0];
  EXPECT_EQ(positions.name, "Positions");
  EXPECT_EQ(positions.id, 256u);
  EXPECT_FALSE(positions.extended);
  EXPECT_EQ(positions.length, 8u);
  ASSERT_EQ(positions.signals.size(), 2u);
  const SignalSpec& x = positions.signals[0].spec;
  EXPECT_EQ(x.name, "X_Pos");
  EXPECT_EQ(x.frameId, 256u);
  EXPECT_EQ(x.startBit, 0u);
  EXPECT_EQ(x.length, 32u);
  EXPECT_EQ(x.byteOrder, ByteOrder::Intel);
  EXPECT_EQ(x.valueType, ValueType::Signed);
  EXPECT_DOUBLE_EQ(x.scale, 0.0001);
  EXPECT_DOUBLE_EQ(x.minimum, -1000.0);
  EXPECT_DOUBLE_EQ(x.maximum, 1000.0);
  EXPECT_EQ(x.unit, "mm");

  // 2147484160 = 0x80000200: bit 31 marks a 29-bit identifier 0x200.
  const DbcMessage& ext = db.messages[1];
  EXPECT_TRUE(ext.extended);
  EXPECT_EQ(ext.id, 0x200u);
  const SignalSpec& z = ext.signals[0].spec;
  EXPECT_EQ(z.byteOrder, ByteOrder::Motorola);
  EXPECT_EQ(z.startBit, 7u);
  EXPECT_DOUBLE_EQ(z.offset, -5.0);
  EXPECT_TRUE(z.extended);
  EXPECT_EQ(z.frameId, 0x200u);
  EXPECT_EQ(ext.signals[1].spec.valueType, ValueType::Unsigned);

  const DbcMessage& misc = db.messages[3];
  EXPECT_EQ(misc.length, 64u);
  EXPECT_EQ(misc.signals[0].spec.valueType, ValueType::Float32);
  EXPECT_EQ(misc.signals[1].multiplexer, "M");
  EXPECT_TRUE(misc.signals[0].multiplexer.empty());
  EXPECT_DOUBLE_EQ(misc.signals[3].spec.scale, 0.001);
  EXPECT_DOUBLE_EQ(misc.signals[3].spec.offset, 2.5);
}

TEST(Dbc, FindsSignalsByQualifiedOrBareName) {
  const DbcDatabase db = parseDbc(kDbc, "machine.dbc");
  ASSERT_EQ(db.find("X_Pos").size(), 1u);
  EXPECT_EQ(db.find("Positions.X_Pos").size(), 1u);
  EXPECT_EQ(db.find("Seq").size(), 2u);  // ambiguous: in Axes_Ext and Misc
  ASSERT_EQ(db.find("Misc.Seq").size(), 1u);
  EXPECT_EQ(db.find("Misc.Seq").front()->spec.startBit, 40u);
  EXPECT_TRUE(db.find("Orphan").empty());
  EXPECT_TRUE(db.find("Nope").empty());
  EXPECT_NE(db.message(0x200, true), nullptr);
  EXPECT_EQ(db.message(0x200, false), nullptr);
}

void expectError(const std::string& text, const std::string& keyPath, const std::string& part) {
  try {
    parseDbc(text, "bad.dbc");
    FAIL() << "no error for: " << text;
  } catch (const config::ConfigError& e) {
    EXPECT_EQ(e.file(), "bad.dbc");
    EXPECT_EQ(e.keyPath(), keyPath) << e.what();
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

TEST(Dbc, RejectsMalformedLinesWithTheirLineNumber) {
  expectError("BO_ 1 M: 8 N\n SG_ S : 0|65@1+ (1,0) [0|0] \"\" X\n", "line 2", "1..64");
  expectError("BO_ 1 M: 8 N\n SG_ S : 0|8@2+ (1,0) [0|0] \"\" X\n", "line 2", "byte order");
  expectError("BO_ 1 M: 8 N\n SG_ S : 0|8@1* (1,0) [0|0] \"\" X\n", "line 2", "sign");
  expectError("BO_ 1 M: 8 N\n SG_ S : 0|8@1+ (x,0) [0|0] \"\" X\n", "line 2", "scale");
  expectError("BO_ 1 M: 8 N\n SG_ S : 0|8@1+ (0,0) [0|0] \"\" X\n", "line 2", "non-zero");
  expectError("BO_ 1 M: 8 N\n SG_ S : 60|8@1+ (1,0) [0|0] \"\" X\n", "line 2", "beyond");
  expectError("BO_ 1 M: 8 N\n SG_ S : 0|8@1+ (1,0) [0|0] \"mm X\n", "line 2", "unterminated");
  expectError("\n SG_ S : 0|8@1+ (1,0) [0|0] \"\" X\n", "line 2", "before any BO_");
  expectError("BO_ 4096 M: 8 N\n", "line 1", "0x7FF");
  expectError("BO_ 1 M: 9 N\n", "line 1", "length");
  expectError("BO_ 1 M: 8 N\n SG_ S : 0|16@1+ (1,0) [0|0] \"\" X\nSIG_VALTYPE_ 1 S : 1;\n",
              "line 3", "32 bits");
  expectError("SIG_VALTYPE_ 1 S : 1;\n", "line 1", "unknown signal");
}

TEST(Dbc, MissingFileIsAConfigError) {
  EXPECT_THROW(readDbcFile("/nonexistent/volcomp.dbc"), config::ConfigError);
}

// A directory named as the DBC file is named as such (through the bounded file reader, which
// also refuses files larger than 64 MiB), not parsed as an empty database.
TEST(Dbc, ADirectoryIsNamedAsSuch) {
  try {
    readDbcFile(VOLCOMP_CAN_TEST_DATA);
    FAIL() << "a directory was read as a DBC file";
  } catch (const config::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("is a directory"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace volcomp::can
