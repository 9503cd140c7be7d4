#pragma once
/// The ISO 230-2 result as JSON ("format": "volcomp-iso230-2/1"), the document `volcomp iso230-2
/// --json` writes and `volcomp report` reads. Every length in mm, full double precision. The schema
/// is documented key by key in docs/iso230-2.md ("JSON output"); within format version 1 keys are
/// only ever added, never renamed or given another meaning.

#include <nlohmann/json.hpp>

#include "volcomp/metrology/iso230_2.hpp"

namespace volcomp::metrology {

/// Name of the format, the value of the "format" key.
inline constexpr const char* kIso230JsonFormat = "volcomp-iso230-2/1";

nlohmann::json toJson(const Iso230Result& result);

}  // namespace volcomp::metrology
