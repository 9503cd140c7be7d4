#include "points_csv.hpp"

namespace volcomp::cli {

config::CsvSchema pointsSchema() {
  config::CsvSchema schema = config::positionsSchema();
  schema.ignore({"ex", "ey", "ez", "ea", "eb", "ec", "ox", "oy", "oz", "weight"});
  return schema;
}

}  // namespace volcomp::cli
