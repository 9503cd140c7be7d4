// LinuxCNC canonical commands (`rs274 -g` output, `volcomp nc --input canon`): the whole
// compensation of such a listing with the example model (nc_support.hpp for what is checked).

#include <cstddef>
#include <cstdint>

#include "nc_support.hpp"
#include "volcomp/nc/canon_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace volcomp;
  nc::CanonReader reader("fuzz.canon", fuzz::exampleStartMm(), fuzz::exampleDecimals());
  fuzz::compensate(reader, data, size);
  return 0;
}
