#include "gltf_builder.hpp"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

namespace snag::test {

namespace {

std::string base64(const std::vector<unsigned char>& in) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = (in[i] << 16) | (in[i + 1] << 8) | in[i + 2];
    out += {table[v >> 18], table[(v >> 12) & 63], table[(v >> 6) & 63], table[v & 63]};
  }
  if (i + 1 == in.size()) {
    const unsigned v = in[i] << 16;
    out += {table[v >> 18], table[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == in.size()) {
    const unsigned v = (in[i] << 16) | (in[i + 1] << 8);
    out += {table[v >> 18], table[(v >> 12) & 63], table[(v >> 6) & 63], '='};
  }
  return out;
}

constexpr int kFloat = 5126;
constexpr int kUnsignedShort = 5123;

}  // namespace

GltfBuilder::GltfBuilder() {
  doc_["asset"] = {{"version", "2.0"}};
  doc_["accessors"] = nlohmann::json::array();
  doc_["bufferViews"] = nlohmann::json::array();
}

int GltfBuilder::add(const void* data, std::size_t bytes, int component_type, const char* type, std::size_t count) {
  while (bytes_.size() % 4) bytes_.push_back(0);
  const std::size_t offset = bytes_.size();
  bytes_.resize(offset + bytes);
  std::memcpy(bytes_.data() + offset, data, bytes);
  const int view = static_cast<int>(doc_["bufferViews"].size());
  doc_["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}});
  doc_["accessors"].push_back({{"bufferView", view}, {"componentType", component_type}, {"count", count}, {"type", type}});
  return static_cast<int>(doc_["accessors"].size()) - 1;
}

int GltfBuilder::add_vec3(const std::vector<float>& xyz, bool with_bounds) {
  const int a = add(xyz.data(), xyz.size() * 4, kFloat, "VEC3", xyz.size() / 3);
  if (with_bounds) {
    std::vector<float> lo(3, 1e30f), hi(3, -1e30f);
    for (std::size_t i = 0; i < xyz.size(); ++i) {
      lo[i % 3] = std::min(lo[i % 3], xyz[i]);
      hi[i % 3] = std::max(hi[i % 3], xyz[i]);
    }
    doc_["accessors"][a]["min"] = lo;
    doc_["accessors"][a]["max"] = hi;
  }
  return a;
}

int GltfBuilder::add_vec4(const std::vector<float>& xyzw) {
  return add(xyzw.data(), xyzw.size() * 4, kFloat, "VEC4", xyzw.size() / 4);
}

int GltfBuilder::add_scalars(const std::vector<float>& values, bool with_bounds) {
  const int a = add(values.data(), values.size() * 4, kFloat, "SCALAR", values.size());
  if (with_bounds) {
    doc_["accessors"][a]["min"] = {*std::min_element(values.begin(), values.end())};
    doc_["accessors"][a]["max"] = {*std::max_element(values.begin(), values.end())};
  }
  return a;
}

int GltfBuilder::add_indices(const std::vector<std::uint16_t>& ids) {
  return add(ids.data(), ids.size() * 2, kUnsignedShort, "SCALAR", ids.size());
}

int GltfBuilder::add_joints(const std::vector<std::uint16_t>& ids) {
  return add(ids.data(), ids.size() * 2, kUnsignedShort, "VEC4", ids.size() / 4);
}

int GltfBuilder::add_mat4(const std::vector<float>& matrices) {
  return add(matrices.data(), matrices.size() * 4, kFloat, "MAT4", matrices.size() / 16);
}

void GltfBuilder::write(const std::string& path) {
  while (bytes_.size() % 4) bytes_.push_back(0);
  doc_["buffers"] = {{{"byteLength", bytes_.size()},
                      {"uri", "data:application/octet-stream;base64," + base64(bytes_)}}};
  std::ofstream(path) << doc_.dump(1);
}

std::string scratch_dir(const std::string& name) {
  // ctest runs each test in its own process, several at once: tests that write
  // the same file name must not share (and remove) one directory.
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string owner = test ? std::string(test->test_suite_name()) + "." + test->name() : "no-test";
  const std::filesystem::path dir = std::filesystem::path(SNAG_BINARY_DIR) / "test-scratch" / "io_assimp" /
                                    owner / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

}  // namespace snag::test
