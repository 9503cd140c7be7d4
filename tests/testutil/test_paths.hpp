#pragma once
/// Paths of the source and build trees for tests, found at run time from the test executable's
/// own path, so that no absolute path of a checkout is compiled into a test: a fresh clone in
/// another folder then finds its objects in the compiler cache (tests/paths.cmake defines the
/// macros that call these, e.g. VOLCOMP_EXAMPLES_DIR, and force-includes this header).
///
/// VOLCOMP_TEST_BINARY_DIR is the executable's folder relative to the build tree's root, and
/// VOLCOMP_TEST_SOURCE_FROM_BUILD the source tree's root relative to the build tree's root.

#include <filesystem>
#include <string>
#include <string_view>

/// The build tree's root: this executable's folder, VOLCOMP_TEST_BINARY_DIR levels up.
inline const std::filesystem::path& volcomp_test_build_root() {
  static const std::filesystem::path root = [] {
    std::filesystem::path dir = std::filesystem::read_symlink("/proc/self/exe").parent_path();
    for (const auto& part : std::filesystem::path(VOLCOMP_TEST_BINARY_DIR)) {
      if (!part.empty() && part != ".") dir = dir.parent_path();
    }
    return dir;
  }();
  return root;
}

/// A file of the build tree, `relative` to its root, as an absolute path.
inline std::string volcomp_test_build_path(std::string_view relative) {
  return (volcomp_test_build_root() / relative).lexically_normal().string();
}

/// A file of the source tree, `relative` to its root, as an absolute path.
inline std::string volcomp_test_source_path(std::string_view relative) {
  return (volcomp_test_build_root() / VOLCOMP_TEST_SOURCE_FROM_BUILD / relative)
      .lexically_normal()
      .string();
}
