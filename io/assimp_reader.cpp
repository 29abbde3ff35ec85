// Files read through assimp: static meshes (one frame) and animated files
// (glTF 2.0, FBX, Collada) evaluated by snag at each sampled time.
#include "io/assimp_reader.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <unordered_map>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "io/assimp_animation.hpp"
#include "libcd/core/error.hpp"

namespace snag::io {

namespace {

using assimp_detail::AnimationEvaluator;
using assimp_detail::Mat4;

[[noreturn]] void fail(const std::string& path, const std::string& message) {
  throw InputError(InputLocation{path}, message);
}

/// Loads a file with triangulation only: no vertex joining, so vertex order is the file's.
std::unique_ptr<Assimp::Importer> load(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) fail(path, "no such file");
  auto importer = std::make_unique<Assimp::Importer>();
  const aiScene* scene = importer->ReadFile(path, aiProcess_Triangulate);
  if (!scene) fail(path, std::string("cannot read through assimp: ") + importer->GetErrorString());
  if (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) fail(path, "assimp loaded an incomplete scene");
  if (!scene->mRootNode) fail(path, "no node hierarchy");
  return importer;
}

bool is_surface(const aiMesh& mesh) {
  return mesh.mPrimitiveTypes & (aiPrimitiveType_TRIANGLE | aiPrimitiveType_POLYGON);
}

/// One object: a mesh node and the surface meshes it places.
struct ObjectPart {
  std::string name;
  int node_id = -1;
  std::vector<unsigned> meshes;
};

/// The mesh nodes of a scene as objects, depth first, with unique names.
/// Checks each mesh: triangles only, some vertices, finite positions, bone
/// names resolvable.
std::vector<ObjectPart> object_parts(const std::string& path, const aiScene& scene,
                                     const AnimationEvaluator& evaluator) {
  std::vector<ObjectPart> parts;
  std::set<std::string> used;
  for (std::size_t id = 0; id < evaluator.nodes().size(); ++id) {
    const aiNode& node = *evaluator.nodes()[id];
    ObjectPart part;
    part.node_id = static_cast<int>(id);
    for (unsigned k = 0; k < node.mNumMeshes; ++k) {
      const unsigned m = node.mMeshes[k];
      if (m >= scene.mNumMeshes) fail(path, "node '" + std::string(node.mName.C_Str()) + "' names a missing mesh");
      const aiMesh& mesh = *scene.mMeshes[m];
      if (!is_surface(mesh)) continue;  // points and lines are not surfaces
      const std::string what = "mesh '" + std::string(mesh.mName.C_Str()) + "' of node '" + node.mName.C_Str() + "'";
      if (mesh.mNumVertices == 0 || mesh.mNumFaces == 0) fail(path, what + " is empty");
      for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
        const aiFace& face = mesh.mFaces[f];
        if (face.mNumIndices != 3)
          fail(path, what + ": face " + std::to_string(f) + " has " + std::to_string(face.mNumIndices) +
                         " vertices and could not be triangulated");
        for (unsigned c = 0; c < 3; ++c)
          if (face.mIndices[c] >= mesh.mNumVertices)
            fail(path, what + ": face " + std::to_string(f) + " uses a vertex out of range");
      }
      auto finite = [](const aiVector3D& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
      for (unsigned v = 0; v < mesh.mNumVertices; ++v)
        if (!finite(mesh.mVertices[v])) fail(path, what + ": vertex " + std::to_string(v) + " is not finite (NaN or infinity)");
      for (unsigned k = 0; k < mesh.mNumAnimMeshes; ++k) {
        const aiAnimMesh& target = *mesh.mAnimMeshes[k];
        for (unsigned v = 0; target.mVertices && v < target.mNumVertices; ++v)
          if (!finite(target.mVertices[v]))
            fail(path, what + ": morph target " + std::to_string(k) + " vertex " + std::to_string(v) + " is not finite");
      }
      for (unsigned b = 0; b < mesh.mNumBones; ++b)
        if (evaluator.node_index(mesh.mBones[b]->mName.C_Str()) < 0)
          fail(path, what + ": bone '" + mesh.mBones[b]->mName.C_Str() + "' has no node");
      part.meshes.push_back(m);
    }
    if (part.meshes.empty()) continue;
    std::string base = node.mName.length > 0 ? node.mName.C_Str() : "mesh" + std::to_string(parts.size());
    std::string name = base;
    for (int n = 1; used.count(name); ++n) name = base + "." + std::to_string(n);
    used.insert(name);
    part.name = name;
    parts.push_back(std::move(part));
  }
  if (parts.empty()) fail(path, "no triangle meshes");
  return parts;
}

/// Triangles of an object's meshes, with vertex ids local to the object.
std::vector<Triangle> part_triangles(const aiScene& scene, const ObjectPart& part, Index& vertex_count) {
  std::vector<Triangle> triangles;
  vertex_count = 0;
  for (unsigned m : part.meshes) {
    const aiMesh& mesh = *scene.mMeshes[m];
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const unsigned* ids = mesh.mFaces[f].mIndices;
      triangles.push_back({vertex_count + ids[0], vertex_count + ids[1], vertex_count + ids[2]});
    }
    vertex_count += mesh.mNumVertices;
  }
  return triangles;
}

void check_finite(const std::string& path, std::size_t frame, const std::vector<Vec3>& positions) {
  for (std::size_t v = 0; v < positions.size(); ++v) {
    const Vec3& p = positions[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      InputLocation where{path};
      where.frame = frame;
      throw InputError(where, "vertex " + std::to_string(v) + " is not finite (NaN or infinity)");
    }
  }
}

/// The animation's span in ticks: its first and last key over all channels
/// (or [0, mDuration] when it has no keys).
std::pair<double, double> key_range_ticks(const aiAnimation& animation) {
  double lo = INFINITY, hi = -INFINITY;
  auto take = [&](double t) {
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  };
  for (unsigned c = 0; c < animation.mNumChannels; ++c) {
    const aiNodeAnim& ch = *animation.mChannels[c];
    for (unsigned k = 0; k < ch.mNumPositionKeys; ++k) take(ch.mPositionKeys[k].mTime);
    for (unsigned k = 0; k < ch.mNumRotationKeys; ++k) take(ch.mRotationKeys[k].mTime);
    for (unsigned k = 0; k < ch.mNumScalingKeys; ++k) take(ch.mScalingKeys[k].mTime);
  }
  for (unsigned c = 0; c < animation.mNumMorphMeshChannels; ++c) {
    const aiMeshMorphAnim& ch = *animation.mMorphMeshChannels[c];
    for (unsigned k = 0; k < ch.mNumKeys; ++k) take(ch.mKeys[k].mTime);
  }
  if (lo > hi) return {0.0, animation.mDuration};
  return {lo, hi};
}

class AnimatedFileSource : public FrameSource {
 public:
  AnimatedFileSource(const InputSpec& input, const CacheOptions& options) : path_(input.path) {
    importer_ = load(path_);
    const aiScene& scene = *importer_->GetScene();
    const aiAnimation* animation = scene.mNumAnimations > 0 ? scene.mAnimations[0] : nullptr;
    evaluator_ = std::make_unique<AnimationEvaluator>(scene, animation);
    parts_ = object_parts(path_, scene, *evaluator_);

    std::vector<Object> objects;
    for (const ObjectPart& part : parts_) {
      Index vertex_count = 0;
      std::vector<Triangle> triangles = part_triangles(scene, part, vertex_count);
      std::string name = part.name;
      if (!input.name.empty()) name = parts_.size() == 1 ? input.name : input.name + "." + part.name;
      objects.push_back(make_object(name, vertex_count, std::move(triangles)));
    }
    scene_ = Scene(std::move(objects));

    ticks_per_second_ = animation && animation->mTicksPerSecond > 0 ? animation->mTicksPerSecond : 25.0;
    rate_ = 24.0;
    if (options.sample_rate) {
      if (!(*options.sample_rate > 0) || !std::isfinite(*options.sample_rate))
        throw UsageError("sample rate must be a positive number");
      rate_ = *options.sample_rate;
    } else if (animation && animation->mTicksPerSecond >= 10 && animation->mTicksPerSecond <= 120 &&
               animation->mTicksPerSecond == std::floor(animation->mTicksPerSecond)) {
      rate_ = animation->mTicksPerSecond;  // keys on a whole frame rate (FBX): sample on it
    }
    double start = 0.0, end = 0.0;
    if (animation) {
      const auto [lo, hi] = key_range_ticks(*animation);
      start = lo / ticks_per_second_;
      end = hi / ticks_per_second_;
    }
    if (options.start_time) start = *options.start_time;
    if (options.end_time) end = *options.end_time;
    if (!std::isfinite(start) || !std::isfinite(end) || end < start)
      throw UsageError("animation time range [" + std::to_string(start) + ", " + std::to_string(end) +
                       "] is empty");
    start_ = start;
    // One frame per 1/rate from start to end inclusive (a tiny slack keeps an
    // end that is a whole number of frames despite rounding).
    frame_count_ = animation || options.end_time ? static_cast<std::size_t>(std::floor((end - start) * rate_ + 1e-9)) + 1 : 1;
  }

  const Scene& scene() const override { return scene_; }
  std::size_t frame_count() const override { return frame_count_; }
  double frame_time(std::size_t i) const override { return seconds(i) * rate_; }

  void read_frame(std::size_t i, std::vector<Vec3>& positions) const override {
    if (i >= frame_count_) {
      InputLocation where{path_};
      where.frame = i;
      throw InputError(where, "frame out of range (the file has " + std::to_string(frame_count_) + ")");
    }
    const double ticks = seconds(i) * ticks_per_second_;
    const std::vector<Mat4> globals = evaluator_->node_globals(ticks);
    positions.clear();
    positions.reserve(scene_.vertex_count());
    for (const ObjectPart& part : parts_)
      for (unsigned m : part.meshes) evaluator_->mesh_positions(part.node_id, m, ticks, globals, positions);
    check_finite(path_, i, positions);
  }

  std::string description() const override {
    return "animated " + path_ + " (" + std::to_string(frame_count_) + " samples at " + std::to_string(rate_) +
           " per second)";
  }

  /// Time of sample i in seconds.
  double seconds(std::size_t i) const { return start_ + static_cast<double>(i) / rate_; }

 private:
  std::string path_;
  std::unique_ptr<Assimp::Importer> importer_;
  std::unique_ptr<AnimationEvaluator> evaluator_;
  std::vector<ObjectPart> parts_;
  Scene scene_;
  double ticks_per_second_ = 25.0;
  double rate_ = 24.0;
  double start_ = 0.0;
  std::size_t frame_count_ = 1;
};

}  // namespace

bool is_assimp_extension(const std::string& extension) {
  static const std::set<std::string> known = {"gltf", "glb", "fbx", "dae", "3ds", "blend", "x",   "lwo",
                                              "lws",  "ms3d", "ac", "ase", "off", "dxf",   "3mf", "ifc",
                                              "ogex", "x3d", "usd", "usda", "usdc", "smd", "md5mesh"};
  return known.count(extension) > 0;
}

bool is_animated_extension(const std::string& extension) {
  return extension == "gltf" || extension == "glb" || extension == "fbx" || extension == "dae";
}

MeshData read_mesh_with_assimp(const std::string& path) {
  std::unique_ptr<Assimp::Importer> importer = load(path);
  const aiScene& scene = *importer->GetScene();
  const AnimationEvaluator rest(scene, nullptr);
  const std::vector<ObjectPart> parts = object_parts(path, scene, rest);
  const std::vector<Mat4> globals = rest.node_globals(0.0);

  MeshData data;
  for (const ObjectPart& part : parts) {
    MeshObject object;
    object.name = part.name;
    const Index first = static_cast<Index>(data.positions.size());
    Index vertex_count = 0;
    object.triangles = part_triangles(scene, part, vertex_count);
    for (unsigned m : part.meshes) rest.mesh_positions(part.node_id, m, 0.0, globals, data.positions);
    object.vertices.resize(vertex_count);
    for (Index v = 0; v < vertex_count; ++v) object.vertices[v] = first + v;
    data.objects.push_back(std::move(object));
  }
  check_finite(path, static_cast<std::size_t>(-1), data.positions);
  return data;
}

std::unique_ptr<FrameSource> open_animated_file(const InputSpec& input, const CacheOptions& options) {
  return std::make_unique<AnimatedFileSource>(input, options);
}

}  // namespace snag::io
