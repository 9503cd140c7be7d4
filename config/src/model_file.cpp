#include "volcomp/config/model_file.hpp"

#include "model_file_parts.hpp"
#include "volcomp/config/model_finite.hpp"

namespace volcomp::config {

ModelDocument parseModel(const nlohmann::json& document, const std::string& file,
                         const ParseOptions& options) {
  const JsonReader root(document, file);
  if (!root.isObject()) root.failExpected("a JSON object (a volcomp-model/1 document)");
  const JsonReader format = root.at("format");
  if (!format.isString() || format.string() != "volcomp-model/1") {
    format.failExpected("\"volcomp-model/1\"");
  }
  ModelDocument doc;
  doc.file = file;
  if (root.has("chain")) {
    detail::parseChainDocument(root, options, doc);
  } else {
    detail::parseMachineDocument(root, options, doc);
  }
  // The file checks above report key paths; building the model as well makes sure that whatever
  // passed them is accepted by the library the daemon will run.
  try {
    if (const auto* spec = std::get_if<model::MachineModelSpec>(&doc.spec)) {
      const model::MachineModel check(*spec);
    } else {
      const model::DhChain check(std::get<model::DhChainSpec>(doc.spec));
    }
  } catch (const model::ModelError& e) {
    throw ConfigError(file, "", std::string("the model library rejected the model: ") + e.what());
  }
  checkModelFinite(doc);
  return doc;
}

ModelDocument loadModelFile(const std::string& path, const ParseOptions& options) {
  return parseModel(readJsonFile(path), path, options);
}

model::MachineModelSpec loadMachineModelFile(const std::string& path, const std::string& user) {
  ModelDocument document = loadModelFile(path);
  auto* spec = std::get_if<model::MachineModelSpec>(&document.spec);
  if (spec == nullptr) {
    throw ConfigError(path, "chain",
                      user +
                          " needs a 3-axis machine model (topology and components); a D-H "
                          "chain file cannot be used");
  }
  return std::move(*spec);
}

}  // namespace volcomp::config
