// Evaluation of the animation data that assimp loads (it does not evaluate
// it): node transform keys, morph target weights and linear blend skinning, in
// double precision, at any time. Private to io/assimp_*.cpp.
//
// Conventions follow assimp's scene format: aiNodeAnim keys replace a node's
// local transform (T * R * S), position and scaling keys interpolate linearly,
// rotation keys by spherical linear interpolation (shortest arc); keys are
// clamped outside their range. Morph targets (aiAnimMesh) hold absolute
// positions: p = base + sum_k w_k (target_k - base). Skinning: a vertex's world
// position is sum_j w_j (G_j * O_j) p / sum_j w_j with G_j the bone node's
// animated global transform and O_j the bone's offset (inverse bind) matrix;
// as glTF 2.0 specifies, the skinned mesh node's own transform is not applied.
#pragma once

#include <array>
#include <string>
#include <unordered_map>
#include <vector>

#include <assimp/scene.h>

#include "libcd/geometry/vec3.hpp"

namespace snag::io::assimp_detail {

/// Row-major 4 x 4 affine matrix in double (assimp's convention: column vectors, m[row][col]).
struct Mat4 {
  std::array<std::array<double, 4>, 4> m{};
  static Mat4 identity();
};
Mat4 operator*(const Mat4& a, const Mat4& b);
/// Applies the affine matrix to a point (w = 1).
Vec3 transform_point(const Mat4& a, Vec3 p);
/// Widens assimp's float matrix to double.
Mat4 to_mat4(const aiMatrix4x4& a);

/// Unit quaternion, w first.
struct Quat {
  double w = 1, x = 0, y = 0, z = 0;
};
/// Spherical linear interpolation from a (s = 0) to b (s = 1) along the shorter arc.
Quat slerp(Quat a, Quat b, double s);
/// T * R * S as one matrix; `rotation` is normalised first.
Mat4 compose(Vec3 translation, Quat rotation, Vec3 scaling);
/// Splits an affine matrix without shear into translation, rotation, scaling.
void decompose(const Mat4& a, Vec3& translation, Quat& rotation, Vec3& scaling);

/// Node transforms, morph weights and skinned positions of one animation of
/// one scene at any time in ticks. Holds pointers into the scene, which must
/// outlive it. `animation` may be null (the rest pose at every time).
class AnimationEvaluator {
 public:
  AnimationEvaluator(const aiScene& scene, const aiAnimation* animation);

  /// Global transforms of every node at `ticks` (indexed as nodes()).
  std::vector<Mat4> node_globals(double ticks) const;
  /// Nodes in depth-first order (parents before children).
  const std::vector<const aiNode*>& nodes() const { return nodes_; }
  /// Index of a node in nodes(), or -1.
  int node_index(const std::string& name) const;

  /// Morph weights of mesh `mesh_index` (one per aiAnimMesh) at `ticks`, for
  /// the mesh as placed by node `node`: from the animation's morph channel
  /// named after the node (or the mesh), else each aiAnimMesh's mWeight.
  std::vector<double> morph_weights(const aiNode& node, unsigned mesh_index, double ticks) const;

  /// World positions of mesh `mesh_index` placed by node `node_id` (an index
  /// into nodes()) at `ticks`, given that time's node_globals(); appended to `out`.
  void mesh_positions(int node_id, unsigned mesh_index, double ticks, const std::vector<Mat4>& globals,
                      std::vector<Vec3>& out) const;

 private:
  void collect(const aiNode* node, int parent);
  Mat4 local_at(int node_id, double ticks) const;

  const aiScene& scene_;
  const aiAnimation* animation_;
  std::vector<const aiNode*> nodes_;
  std::vector<int> parent_;
  std::vector<const aiNodeAnim*> channel_;  ///< per node, or null
  std::unordered_map<std::string, int> index_of_name_;
  std::unordered_map<std::string, const aiMeshMorphAnim*> morph_channel_;
};

/// Linear interpolation of vector keys at `ticks`, clamped to the first/last key. Needs n > 0.
Vec3 interpolate_vector_keys(const aiVectorKey* keys, unsigned n, double ticks);
/// Slerp of rotation keys at `ticks`, clamped. Needs n > 0.
Quat interpolate_rotation_keys(const aiQuatKey* keys, unsigned n, double ticks);

}  // namespace snag::io::assimp_detail
