#pragma once
// The points CSV of `volcomp eval --points`: the columns it reads through the one CSV reader of
// volcomp (config::CsvReader: `#` comments, any column order, unit suffixes, a line at most
// 1 MiB). Columns x,y,z (required, mm by default), tx,ty,tz (tool per point, together or not at
// all) and direction (per point); the columns of a measurement file and of eval's own output are
// accepted and not read, so that either can be evaluated again.

#include "volcomp/config/csv_table.hpp"

namespace volcomp::cli {

config::CsvSchema pointsSchema();

}  // namespace volcomp::cli
