#include "points_csv.hpp"

namespace volcomp::cli {

config::CsvSchema pointsSchema() {
  using config::CsvQuantity;
  config::CsvSchema schema;
  schema.add({"x", "y", "z"}, CsvQuantity::Length, true)
      .addGroup({"tx", "ty", "tz"}, CsvQuantity::Length)
      .add({"direction"}, CsvQuantity::Direction)
      .ignore({"ex", "ey", "ez", "ea", "eb", "ec", "ox", "oy", "oz", "weight"});
  return schema;
}

}  // namespace volcomp::cli
