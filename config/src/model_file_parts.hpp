#pragma once
// Pieces of model-file parsing shared between the .cpp files of config/src (not installed).

#include <array>
#include <optional>
#include <string>

#include "volcomp/config/json_reader.hpp"
#include "volcomp/config/model_file.hpp"

namespace volcomp::config::detail {

/// ISO 230-1 names: motion index axis * 6 + kind (EXX, EYX, EZX, EAX, EBX, ECX, EXY, ...), and
/// location index axis * 3 + rotation (EA0X, EB0X, EC0X, EA0Y, ...).
const std::array<std::string, 18>& motionNames();
const std::array<std::string, 9>& locationNames();

/// Fills doc.spec with a MachineModelSpec (and doc.units, doc.identify) from a 3-axis document.
void parseMachineDocument(const JsonReader& root, const ParseOptions& options, ModelDocument& doc);
/// Fills doc.spec with a DhChainSpec (and doc.identify) from a document holding "chain".
void parseChainDocument(const JsonReader& root, const ParseOptions& options, ModelDocument& doc);

/// What a parser of one document passes down to the readers of its parts.
struct Context {
  const ParseOptions& options;
  ModelDocument& doc;
};

/// In a calibration template a value may be {"identify": HOW, "start": VALUE}.
struct IdentifyBlock {
  std::optional<JsonReader> start;  ///< VALUE, when given (else the value starts at 0)
};
/// Returns nothing when `node` is not an object with "identify". Otherwise records HOW in
/// doc.identify under the node's key path and returns the block; without
/// options.allowIdentify the key is rejected (ConfigError naming where it is allowed, so that a
/// template loaded by mistake is recognised).
std::optional<IdentifyBlock> readIdentifyBlock(const JsonReader& node, const ParseOptions& options,
                                               ModelDocument& doc);

/// A strictly increasing array of at least `minCount` finite positions (mm).
std::vector<double> readIncreasing(const JsonReader& node, std::size_t minCount);

}  // namespace volcomp::config::detail
