// Bad files give an InputError that names the file, from both entry points.
#include <filesystem>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>

#include "gltf_builder.hpp"
#include "io/assimp_reader.hpp"
#include "libcd/core/error.hpp"

namespace snag::io {
namespace {

void expect_input_error_naming(const std::string& path, const std::string& detail = "") {
  for (int entry = 0; entry < 2; ++entry) {
    try {
      if (entry == 0)
        read_mesh_with_assimp(path);
      else
        open_animated_file(InputSpec{path, "", ""}, CacheOptions{});
      ADD_FAILURE() << "no InputError for " << path << " (entry " << entry << ")";
    } catch (const InputError& e) {
      EXPECT_EQ(e.where().file, path);
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      if (!detail.empty()) EXPECT_NE(std::string(e.what()).find(detail), std::string::npos) << e.what();
    }
  }
}

std::string valid_triangle_file(const std::string& dir, float x0 = 0) {
  test::GltfBuilder b;
  const int pos = b.add_vec3({x0, 0, 0, 1, 0, 0, 0, 1, 0}, x0 == x0);
  const int ids = b.add_indices({0, 1, 2});
  auto& d = b.doc();
  d["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", pos}}}, {"indices", ids}}}}}};
  d["nodes"] = {{{"name", "tri"}, {"mesh", 0}}};
  d["scenes"] = {{{"nodes", {0}}}};
  d["scene"] = 0;
  const std::string path = dir + "/tri.gltf";
  b.write(path);
  return path;
}

TEST(MalformedAssimpFile, RejectsMissingFile) {
  expect_input_error_naming(test::scratch_dir("missing") + "/nothing.gltf", "no such file");
}

TEST(MalformedAssimpFile, RejectsTruncatedGltf) {
  const std::string dir = test::scratch_dir("truncated");
  const std::string path = valid_triangle_file(dir);
  const auto size = std::filesystem::file_size(path);
  std::filesystem::resize_file(path, size / 2);
  expect_input_error_naming(path);
}

TEST(MalformedAssimpFile, RejectsBadJson) {
  const std::string path = test::scratch_dir("bad_json") + "/bad.gltf";
  std::ofstream(path) << "{ \"asset\": { \"version\": \"2.0\" }, \"nodes\": [ { \"name\": ";
  expect_input_error_naming(path);
}

TEST(MalformedAssimpFile, RejectsFileWithoutMeshes) {
  const std::string path = test::scratch_dir("no_mesh") + "/empty.gltf";
  std::ofstream(path) << R"({"asset": {"version": "2.0"}, "nodes": [{"name": "lonely"}],
                             "scenes": [{"nodes": [0]}], "scene": 0})";
  expect_input_error_naming(path);
}

TEST(MalformedAssimpFile, RejectsNonFinitePosition) {
  const std::string path = valid_triangle_file(test::scratch_dir("nan"), std::numeric_limits<float>::quiet_NaN());
  expect_input_error_naming(path);
}

TEST(MalformedAssimpFile, ValidFileIsAccepted) {
  const std::string path = valid_triangle_file(test::scratch_dir("valid"));
  EXPECT_EQ(read_mesh_with_assimp(path).positions.size(), 3u);
}

}  // namespace
}  // namespace snag::io
