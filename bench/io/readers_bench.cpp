// Reader throughput on a generated ~100k-vertex grid (200k triangles): OBJ
// text, binary and ASCII PLY, binary STL, and a 50-frame PC2 read through
// open_cache; and a later frame of two-frame OBJ and binary PLY sequences,
// as a scan reads it (its topology checked against the first frame's). With
// assimp, its OBJ import of the same file is the baseline.
// Files are written once to a temporary directory; reads hit the page cache.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "io/obj_reader.hpp"
#include "io/open_cache.hpp"
#include "io/ply_reader.hpp"
#include "io/stl_reader.hpp"
#include "snag/config.hpp"

#if SNAG_HAVE_ASSIMP
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#endif

namespace {

constexpr int kGrid = 317;  // 317 × 317 = 100,489 vertices
constexpr int kPc2Frames = 50;

struct Files {
  std::filesystem::path dir;
  std::string obj, ply_binary, ply_ascii, stl, pc2;
  std::string obj_sequence, ply_sequence;  ///< printf patterns of two frames, the second moved
  std::vector<float> xyz;          // grid positions
  std::vector<int> triangles;      // 3 per triangle

  Files() {
    dir = std::filesystem::temp_directory_path() / ("snag-bench-readers-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    for (int j = 0; j < kGrid; ++j) {
      for (int i = 0; i < kGrid; ++i) {
        xyz.push_back(static_cast<float>(i * 0.0123456));
        xyz.push_back(static_cast<float>(0.05 * std::sin(i * 0.1) * std::cos(j * 0.13)));
        xyz.push_back(static_cast<float>(j * 0.0123456));
      }
    }
    for (int j = 0; j + 1 < kGrid; ++j) {
      for (int i = 0; i + 1 < kGrid; ++i) {
        const int a = j * kGrid + i, b = a + 1, c = a + kGrid, d = c + 1;
        triangles.insert(triangles.end(), {a, b, d, a, d, c});
      }
    }
    obj = write_obj("grid.obj", 0);
    ply_binary = write_ply("grid_binary.ply", true, 0);
    ply_ascii = write_ply("grid_ascii.ply", false, 0);
    write_stl();
    write_pc2();
    for (int frame = 0; frame < 2; ++frame) {
      const std::string number = "_000" + std::to_string(frame);
      write_obj("walk" + number + ".obj", 0.01f * frame);
      write_ply("walk" + number + ".ply", true, 0.01f * frame);
    }
    obj_sequence = (dir / "walk_%04d.obj").string();
    ply_sequence = (dir / "walk_%04d.ply").string();
  }
  ~Files() { std::filesystem::remove_all(dir); }

  /// Writes the grid, raised by `lift`, to `name` in the directory; returns its path.
  std::string write_obj(const std::string& name, float lift) {
    const std::string path = (dir / name).string();
    FILE* out = std::fopen(path.c_str(), "w");
    std::fprintf(out, "# grid\no Grid\n");
    for (std::size_t k = 0; k < xyz.size(); k += 3)
      std::fprintf(out, "v %.6f %.6f %.6f\n", xyz[k], xyz[k + 1] + lift, xyz[k + 2]);
    for (std::size_t k = 0; k < triangles.size(); k += 3) {
      std::fprintf(out, "f %d %d %d\n", triangles[k] + 1, triangles[k + 1] + 1, triangles[k + 2] + 1);
    }
    std::fclose(out);
    return path;
  }
  /// As write_obj, a PLY file.
  std::string write_ply(const std::string& name, bool binary, float lift) {
    const std::string path = (dir / name).string();
    std::vector<float> lifted = xyz;
    for (std::size_t k = 1; k < lifted.size(); k += 3) lifted[k] += lift;
    FILE* out = std::fopen(path.c_str(), "wb");
    std::fprintf(out, "ply\nformat %s 1.0\nelement vertex %zu\nproperty float x\nproperty float y\nproperty float z\n"
                 "element face %zu\nproperty list uchar int vertex_indices\nend_header\n",
                 binary ? "binary_little_endian" : "ascii", xyz.size() / 3, triangles.size() / 3);
    if (binary) {
      std::fwrite(lifted.data(), sizeof(float), lifted.size(), out);
      for (std::size_t k = 0; k < triangles.size(); k += 3) {
        const unsigned char three = 3;
        std::fwrite(&three, 1, 1, out);
        std::fwrite(&triangles[k], sizeof(int), 3, out);
      }
    } else {
      for (std::size_t k = 0; k < lifted.size(); k += 3)
        std::fprintf(out, "%.9g %.9g %.9g\n", lifted[k], lifted[k + 1], lifted[k + 2]);
      for (std::size_t k = 0; k < triangles.size(); k += 3) {
        std::fprintf(out, "3 %d %d %d\n", triangles[k], triangles[k + 1], triangles[k + 2]);
      }
    }
    std::fclose(out);
    return path;
  }
  void write_stl() {
    stl = (dir / "grid.stl").string();
    FILE* out = std::fopen(stl.c_str(), "wb");
    char header[80] = "grid";
    std::fwrite(header, 1, 80, out);
    const std::uint32_t count = static_cast<std::uint32_t>(triangles.size() / 3);
    std::fwrite(&count, 4, 1, out);
    for (std::size_t k = 0; k < triangles.size(); k += 3) {
      const float normal[3] = {0, 1, 0};
      std::fwrite(normal, 4, 3, out);
      for (int c = 0; c < 3; ++c) std::fwrite(&xyz[3 * static_cast<std::size_t>(triangles[k + c])], 4, 3, out);
      const std::uint16_t attributes = 0;
      std::fwrite(&attributes, 2, 1, out);
    }
    std::fclose(out);
  }
  void write_pc2() {
    pc2 = (dir / "grid.pc2").string();
    FILE* out = std::fopen(pc2.c_str(), "wb");
    std::fwrite("POINTCACHE2", 1, 12, out);
    const std::int32_t version = 1, points = static_cast<std::int32_t>(xyz.size() / 3), frames = kPc2Frames;
    const float start = 1, rate = 1;
    std::fwrite(&version, 4, 1, out);
    std::fwrite(&points, 4, 1, out);
    std::fwrite(&start, 4, 1, out);
    std::fwrite(&rate, 4, 1, out);
    std::fwrite(&frames, 4, 1, out);
    std::vector<float> frame = xyz;
    for (int f = 0; f < kPc2Frames; ++f) {
      for (std::size_t k = 1; k < frame.size(); k += 3) frame[k] = xyz[k] + 0.001f * static_cast<float>(f);
      std::fwrite(frame.data(), 4, frame.size(), out);
    }
    std::fclose(out);
  }
};

Files& files() {
  static Files instance;
  return instance;
}

template <typename Read>
void run_reader(benchmark::State& state, const std::string& path, Read read) {
  const auto bytes = static_cast<std::int64_t>(std::filesystem::file_size(path));
  for (auto _ : state) {
    auto mesh = read(path);
    benchmark::DoNotOptimize(mesh);
  }
  state.SetBytesProcessed(state.iterations() * bytes);
  state.counters["file_MB"] = static_cast<double>(bytes) / 1e6;
}

void ReadObj(benchmark::State& state) { run_reader(state, files().obj, snag::io::read_obj); }
void ReadPlyBinary(benchmark::State& state) { run_reader(state, files().ply_binary, snag::io::read_ply); }
void ReadPlyAscii(benchmark::State& state) { run_reader(state, files().ply_ascii, snag::io::read_ply); }
void ReadStlBinary(benchmark::State& state) { run_reader(state, files().stl, snag::io::read_stl); }

/// All 50 frames of the PC2 through open_cache, as a scan reads them.
void ReadPc2Frames(benchmark::State& state) {
  snag::io::CacheOptions options;
  options.inputs.push_back({files().pc2, files().ply_binary, ""});
  const auto source = snag::io::open_cache(options);
  std::vector<snag::Vec3> positions;
  for (auto _ : state) {
    for (std::size_t i = 0; i < source->frame_count(); ++i) {
      source->read_frame(i, positions);
      benchmark::DoNotOptimize(positions.data());
    }
  }
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(std::filesystem::file_size(files().pc2)));
}

/// The second frame of a two-frame sequence through open_cache, as a scan
/// reads it: the file read, its topology checked against the first frame's,
/// its positions gathered.
void read_second_frame(benchmark::State& state, const std::string& pattern) {
  snag::io::CacheOptions options;
  options.inputs.push_back({pattern, "", ""});
  const auto source = snag::io::open_cache(options);
  std::vector<snag::Vec3> positions;
  for (auto _ : state) {
    source->read_frame(1, positions);
    benchmark::DoNotOptimize(positions.data());
  }
  char second[4096];
  std::snprintf(second, sizeof second, pattern.c_str(), 1);
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(std::filesystem::file_size(second)));
}
void ReadObjSequenceFrame(benchmark::State& state) { read_second_frame(state, files().obj_sequence); }
void ReadPlySequenceFrame(benchmark::State& state) { read_second_frame(state, files().ply_sequence); }

#if SNAG_HAVE_ASSIMP
/// Baseline: assimp's OBJ import with triangulation and no welding (vertices
/// as listed, like snag's reader), of the same file.
void AssimpReadObj(benchmark::State& state) {
  run_reader(state, files().obj, [](const std::string& path) {
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(path, aiProcess_Triangulate);
    if (!scene || scene->mNumMeshes == 0) std::abort();
    return scene->mMeshes[0]->mNumVertices;
  });
}
BENCHMARK(AssimpReadObj)->Unit(benchmark::kMillisecond);
#endif

BENCHMARK(ReadObj)->Unit(benchmark::kMillisecond);
BENCHMARK(ReadPlyBinary)->Unit(benchmark::kMillisecond);
BENCHMARK(ReadPlyAscii)->Unit(benchmark::kMillisecond);
BENCHMARK(ReadStlBinary)->Unit(benchmark::kMillisecond);
BENCHMARK(ReadPc2Frames)->Unit(benchmark::kMillisecond);
BENCHMARK(ReadObjSequenceFrame)->Unit(benchmark::kMillisecond);
BENCHMARK(ReadPlySequenceFrame)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
