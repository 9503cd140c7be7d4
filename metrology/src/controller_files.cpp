#include "volcomp/metrology/controller_files.hpp"

#include <algorithm>
#include <charconv>
#include <ostream>
#include <stdexcept>

#include "volcomp/format/numbers.hpp"

namespace volcomp::metrology {
namespace {

/// Fixed-point text: LinuxCNC reads it with sscanf and Siemens part programs take decimals; 7
/// decimals of a mm are 0.1 nm, finer than either controller resolves. A value that rounds to zero
/// is written without its sign ("-0.000000" reads oddly).
std::string fixed(double value, int decimals = 7) {
  return format::fixedUnsignedZero(value, decimals);
}

/// Shortest text that reads back to the same double.
std::string shortest(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  std::string text(buffer, result.ptr);
  if (text.find_first_of(".e") == std::string::npos) text += ".0";
  return text;
}

void writeComments(std::ostream& out, const CommentLines& comments) {
  for (const std::string& line : comments) out << "; " << line << '\n';
}

}  // namespace

void writeLinuxCncCompFile(std::ostream& out, const AxisTable& forward, const AxisTable& reverse,
                           int type) {
  if (type != 0 && type != 1) throw std::invalid_argument("COMP_FILE_TYPE must be 0 or 1");
  if (forward.errorMm.size() != reverse.errorMm.size() || forward.errorMm.empty()) {
    throw std::invalid_argument("forward and reverse tables differ in size");
  }
  if (forward.errorMm.size() > kLinuxCncMaxPoints) {
    throw std::invalid_argument("LinuxCNC takes at most 256 points per joint");
  }
  for (std::size_t i = 0; i < forward.errorMm.size(); ++i) {
    const double nominal = forward.grid.positionMm(i);
    const double up = forward.errorMm[i];
    const double down = reverse.errorMm[i];
    out << fixed(nominal, 6) << ' ';
    if (type == 0) {
      out << fixed(nominal + up) << ' ' << fixed(nominal + down) << '\n';
    } else {
      out << fixed(-up) << ' ' << fixed(-down) << '\n';
    }
  }
}

void writeSiemensLec(std::ostream& out, const std::vector<AxisTable>& tables,
                     const std::array<std::string, 3>& axisNames, int encoder,
                     const CommentLines& comments) {
  out << "%_N_AX_EEC_INI\n";
  writeComments(out, comments);
  out << "CHANDATA(1)\n";
  const std::string e = std::to_string(encoder);
  for (const AxisTable& table : tables) {
    const std::string& axis = axisNames[static_cast<std::size_t>(table.input)];
    out << "; " << axisName(table.input) << " (" << axis << "): ";
    for (const std::string& c : table.components) out << c << ' ';
    out << "error e = actual - nominal, mm (a positive value moves the axis in -)\n";
    for (std::size_t i = 0; i < table.errorMm.size(); ++i) {
      out << "$AA_ENC_COMP[" << e << ',' << i << ',' << axis << "]=" << fixed(table.errorMm[i], 6)
          << '\n';
    }
    out << "$AA_ENC_COMP_STEP[" << e << ',' << axis << "]=" << shortest(table.grid.stepMm) << '\n'
        << "$AA_ENC_COMP_MIN[" << e << ',' << axis << "]=" << shortest(table.grid.startMm) << '\n'
        << "$AA_ENC_COMP_MAX[" << e << ',' << axis << "]=" << shortest(table.grid.endMm()) << '\n'
        << "$AA_ENC_COMP_IS_MODULO[" << e << ',' << axis << "]=0\n";
  }
  out << "M17\n";
}

void writeSiemensCec(std::ostream& out, const std::vector<AxisTable>& tables,
                     const std::array<std::string, 3>& axisNames, const CommentLines& comments) {
  out << "%_N_NC_CEC_INI\n";
  writeComments(out, comments);
  out << "CHANDATA(1)\n";
  for (std::size_t t = 0; t < tables.size(); ++t) {
    const AxisTable& table = tables[t];
    const std::string& input = axisNames[static_cast<std::size_t>(table.input)];
    const std::string& output = axisNames[static_cast<std::size_t>(table.output)];
    out << "; table " << t << ": ";
    for (const std::string& c : table.components) out << c << ' ';
    out << "- error of " << axisName(table.output) << " over " << axisName(table.input)
        << (table.direction > 0 ? ", moving +" : (table.direction < 0 ? ", moving -" : ""))
        << ", mm\n";
    for (std::size_t i = 0; i < table.errorMm.size(); ++i) {
      out << "$AN_CEC[" << t << ',' << i << "]=" << fixed(table.errorMm[i], 6) << '\n';
    }
    out << "$AN_CEC_INPUT_AXIS[" << t << "]=(" << input << ")\n"
        << "$AN_CEC_OUTPUT_AXIS[" << t << "]=(" << output << ")\n"
        << "$AN_CEC_STEP[" << t << "]=" << shortest(table.grid.stepMm) << '\n'
        << "$AN_CEC_MIN[" << t << "]=" << shortest(table.grid.startMm) << '\n'
        << "$AN_CEC_MAX[" << t << "]=" << shortest(table.grid.endMm()) << '\n'
        << "$AN_CEC_DIRECTION[" << t << "]=" << table.direction << '\n'
        << "$AN_CEC_MULT_BY_TABLE[" << t << "]=0\n"
        << "$AN_CEC_IS_MODULO[" << t << "]=0\n";
  }
  out << "M17\n";
}

void writeComponentCsv(std::ostream& out, const model::MachineModelSpec& spec,
                       const std::string& name, const AxisGrid& grid) {
  for (int index = 0; index < 18; ++index) {
    if (model::motionName(index) != name) continue;
    const model::ErrorFunction function(spec.motion[static_cast<std::size_t>(index)]);
    const bool angle = index % 6 >= 3;
    const double scale = angle ? 1e6 : 1e3;
    const char* unit = angle ? "urad" : "um";
    const bool both = function.isBidirectional();
    out << "position_mm,value_" << unit;
    if (both) out << ",value_negative_" << unit;
    out << '\n';
    // Beyond the travel the model holds the value at the travel's end; so does the table.
    const auto& travel = spec.travelMm[static_cast<std::size_t>(index / 6)];
    for (std::size_t i = 0; i < grid.count; ++i) {
      const double position = grid.positionMm(i);
      const double q = travel ? std::clamp(position, (*travel)[0], (*travel)[1]) : position;
      out << shortest(position) << ','
          << shortest(scale * function.value(q, both ? model::Direction::Positive
                                                     : model::Direction::Unknown));
      if (both) out << ',' << shortest(scale * function.value(q, model::Direction::Negative));
      out << '\n';
    }
    return;
  }
  for (int index = 0; index < 9; ++index) {
    if (model::locationName(index) != name) continue;
    out << "position_mm,value_urad\n";
    for (std::size_t i = 0; i < grid.count; ++i) {
      out << shortest(grid.positionMm(i)) << ','
          << shortest(1e6 * spec.locationRad[static_cast<std::size_t>(index)]) << '\n';
    }
    return;
  }
  throw std::invalid_argument("unknown component \"" + name + "\"");
}

}  // namespace volcomp::metrology
