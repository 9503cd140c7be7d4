// Every model file in config/examples loads and validates (daemon or transport configuration
// files there are recognised by their "format" and skipped).

#include <gtest/gtest.h>

#include <filesystem>

#include "volcomp/config/json_reader.hpp"
#include "volcomp/config/model_file.hpp"

namespace volcomp::config {
namespace {

bool containsIdentify(const nlohmann::json& j) {
  if (j.is_object()) {
    if (j.contains("identify")) return true;
    for (const auto& item : j.items()) {
      if (containsIdentify(item.value())) return true;
    }
  } else if (j.is_array()) {
    for (const auto& item : j) {
      if (containsIdentify(item)) return true;
    }
  }
  return false;
}

TEST(ModelFileExamples, EveryExampleModelLoads) {
  const std::filesystem::path dir = VOLCOMP_EXAMPLES_DIR;
  ASSERT_TRUE(std::filesystem::is_directory(dir)) << dir << " does not exist";
  int models = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir)) {
    if (!entry.is_regular_file() || entry.path().extension() != ".json") continue;
    const std::string path = entry.path().string();
    SCOPED_TRACE(path);
    nlohmann::json doc;
    ASSERT_NO_THROW(doc = readJsonFile(path));
    const auto format = doc.find("format");
    if (format == doc.end() || !format->is_string() ||
        format->get<std::string>().rfind("volcomp-model", 0) != 0) {
      continue;
    }
    ParseOptions options;
    options.allowIdentify = containsIdentify(doc);
    try {
      const ModelDocument model = loadModelFile(path, options);
      EXPECT_EQ(model.file, path);
    } catch (const ConfigError& e) {
      ADD_FAILURE() << e.what();
    }
    ++models;
  }
  ASSERT_GE(models, 4) << "model files in " << dir;  // the four example models at least
  RecordProperty("models", models);
}

}  // namespace
}  // namespace volcomp::config
