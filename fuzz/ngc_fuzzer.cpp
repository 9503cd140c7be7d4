// RS274/NGC programs (`volcomp nc`, the subset reader and interpreter of nc/): the whole
// compensation of a program with the example model (nc_support.hpp for what is checked).

#include <cstddef>
#include <cstdint>

#include "nc_support.hpp"
#include "volcomp/nc/ngc_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace volcomp;
  const nc::WorkOffsets offsets;
  const nc::ToolTable tools;
  nc::NgcReader reader("fuzz.ngc", offsets, tools, fuzz::exampleStartMm(), fuzz::exampleDecimals());
  fuzz::compensate(reader, data, size);
  return 0;
}
