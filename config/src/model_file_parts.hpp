#pragma once
// Pieces of model-file parsing shared between the .cpp files of config/src (not installed).

#include <array>
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

/// A strictly increasing array of at least `minCount` finite positions (mm).
std::vector<double> readIncreasing(const JsonReader& node, std::size_t minCount);

}  // namespace volcomp::config::detail
