// Evaluation of assimp's animation data in double precision.
// Slerp: K. Shoemake, "Animating rotation with quaternion curves", SIGGRAPH 1985.
// Linear blend skinning and morph targets as in the glTF 2.0 specification
// (Khronos, 2021), sections 3.7.3 (morph targets) and 3.7.3.3 (skins).
#include "io/assimp_animation.hpp"

#include <algorithm>
#include <cmath>

namespace snag::io::assimp_detail {

Mat4 Mat4::identity() {
  Mat4 a;
  for (int i = 0; i < 4; ++i) a.m[i][i] = 1.0;
  return a;
}

Mat4 operator*(const Mat4& a, const Mat4& b) {
  Mat4 c;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += a.m[i][k] * b.m[k][j];
      c.m[i][j] = s;
    }
  return c;
}

Vec3 transform_point(const Mat4& a, Vec3 p) {
  return {a.m[0][0] * p.x + a.m[0][1] * p.y + a.m[0][2] * p.z + a.m[0][3],
          a.m[1][0] * p.x + a.m[1][1] * p.y + a.m[1][2] * p.z + a.m[1][3],
          a.m[2][0] * p.x + a.m[2][1] * p.y + a.m[2][2] * p.z + a.m[2][3]};
}

Mat4 to_mat4(const aiMatrix4x4& a) {
  Mat4 r;
  const ai_real* row[4] = {&a.a1, &a.b1, &a.c1, &a.d1};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) r.m[i][j] = static_cast<double>(row[i][j]);
  return r;
}

Quat slerp(Quat a, Quat b, double s) {
  double cosine = a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
  if (cosine < 0) {  // the shorter arc
    cosine = -cosine;
    b = {-b.w, -b.x, -b.y, -b.z};
  }
  double wa = 1.0 - s, wb = s;
  if (cosine < 1.0 - 1e-12) {
    const double angle = std::acos(cosine);
    const double sine = std::sin(angle);
    wa = std::sin((1.0 - s) * angle) / sine;
    wb = std::sin(s * angle) / sine;
  }
  return {wa * a.w + wb * b.w, wa * a.x + wb * b.x, wa * a.y + wb * b.y, wa * a.z + wb * b.z};
}

Mat4 compose(Vec3 translation, Quat q, Vec3 scaling) {
  const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  if (n > 0 && n != 1.0) q = {q.w / n, q.x / n, q.y / n, q.z / n};
  const double r[3][3] = {
      {1 - 2 * (q.y * q.y + q.z * q.z), 2 * (q.x * q.y - q.z * q.w), 2 * (q.x * q.z + q.y * q.w)},
      {2 * (q.x * q.y + q.z * q.w), 1 - 2 * (q.x * q.x + q.z * q.z), 2 * (q.y * q.z - q.x * q.w)},
      {2 * (q.x * q.z - q.y * q.w), 2 * (q.y * q.z + q.x * q.w), 1 - 2 * (q.x * q.x + q.y * q.y)}};
  Mat4 a = Mat4::identity();
  for (int i = 0; i < 3; ++i) {
    a.m[i][0] = r[i][0] * scaling.x;
    a.m[i][1] = r[i][1] * scaling.y;
    a.m[i][2] = r[i][2] * scaling.z;
    a.m[i][3] = translation[i];
  }
  return a;
}

void decompose(const Mat4& a, Vec3& translation, Quat& rotation, Vec3& scaling) {
  translation = {a.m[0][3], a.m[1][3], a.m[2][3]};
  double r[3][3];
  for (int j = 0; j < 3; ++j) {
    const double s = std::sqrt(a.m[0][j] * a.m[0][j] + a.m[1][j] * a.m[1][j] + a.m[2][j] * a.m[2][j]);
    scaling[j] = s;
    for (int i = 0; i < 3; ++i) r[i][j] = s > 0 ? a.m[i][j] / s : (i == j ? 1.0 : 0.0);
  }
  // A reflection is carried by a negative x scale.
  const double det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) -
                     r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
                     r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
  if (det < 0) {
    scaling.x = -scaling.x;
    for (int i = 0; i < 3; ++i) r[i][0] = -r[i][0];
  }
  // Shepperd's method: the largest of w, x, y, z first.
  const double trace = r[0][0] + r[1][1] + r[2][2];
  Quat q;
  if (trace > 0) {
    const double s = 2.0 * std::sqrt(1.0 + trace);
    q = {0.25 * s, (r[2][1] - r[1][2]) / s, (r[0][2] - r[2][0]) / s, (r[1][0] - r[0][1]) / s};
  } else if (r[0][0] > r[1][1] && r[0][0] > r[2][2]) {
    const double s = 2.0 * std::sqrt(1.0 + r[0][0] - r[1][1] - r[2][2]);
    q = {(r[2][1] - r[1][2]) / s, 0.25 * s, (r[0][1] + r[1][0]) / s, (r[0][2] + r[2][0]) / s};
  } else if (r[1][1] > r[2][2]) {
    const double s = 2.0 * std::sqrt(1.0 + r[1][1] - r[0][0] - r[2][2]);
    q = {(r[0][2] - r[2][0]) / s, (r[0][1] + r[1][0]) / s, 0.25 * s, (r[1][2] + r[2][1]) / s};
  } else {
    const double s = 2.0 * std::sqrt(1.0 + r[2][2] - r[0][0] - r[1][1]);
    q = {(r[1][0] - r[0][1]) / s, (r[0][2] + r[2][0]) / s, (r[1][2] + r[2][1]) / s, 0.25 * s};
  }
  rotation = q;
}

namespace {

/// Index k of the key interval [k, k+1] holding `ticks`, and the fraction in it;
/// clamped: before the first key gives (0, 0), after the last (n-1, 0).
template <typename Key>
std::pair<unsigned, double> bracket(const Key* keys, unsigned n, double ticks) {
  if (n == 1 || ticks <= keys[0].mTime) return {0, 0.0};
  if (ticks >= keys[n - 1].mTime) return {n - 1, 0.0};
  const Key* after = std::upper_bound(keys, keys + n, ticks, [](double t, const Key& k) { return t < k.mTime; });
  const unsigned k = static_cast<unsigned>(after - keys) - 1;
  const double span = keys[k + 1].mTime - keys[k].mTime;
  return {k, span > 0 ? (ticks - keys[k].mTime) / span : 0.0};
}

Vec3 to_vec3(const aiVector3D& v) { return {v.x, v.y, v.z}; }

}  // namespace

Vec3 interpolate_vector_keys(const aiVectorKey* keys, unsigned n, double ticks) {
  const auto [k, s] = bracket(keys, n, ticks);
  if (s == 0.0) return to_vec3(keys[k].mValue);
  return lerp(to_vec3(keys[k].mValue), to_vec3(keys[k + 1].mValue), s);
}

Quat interpolate_rotation_keys(const aiQuatKey* keys, unsigned n, double ticks) {
  const auto [k, s] = bracket(keys, n, ticks);
  const aiQuaternion& a = keys[k].mValue;
  if (s == 0.0) return {a.w, a.x, a.y, a.z};
  const aiQuaternion& b = keys[k + 1].mValue;
  return slerp({a.w, a.x, a.y, a.z}, {b.w, b.x, b.y, b.z}, s);
}

AnimationEvaluator::AnimationEvaluator(const aiScene& scene, const aiAnimation* animation)
    : scene_(scene), animation_(animation) {
  if (scene.mRootNode) collect(scene.mRootNode, -1);
  channel_.assign(nodes_.size(), nullptr);
  if (!animation_) return;
  for (unsigned c = 0; c < animation_->mNumChannels; ++c) {
    const aiNodeAnim* channel = animation_->mChannels[c];
    const int id = node_index(channel->mNodeName.C_Str());
    if (id >= 0) channel_[id] = channel;
  }
  for (unsigned c = 0; c < animation_->mNumMorphMeshChannels; ++c) {
    const aiMeshMorphAnim* channel = animation_->mMorphMeshChannels[c];
    morph_channel_[channel->mName.C_Str()] = channel;
  }
}

void AnimationEvaluator::collect(const aiNode* node, int parent) {
  const int id = static_cast<int>(nodes_.size());
  nodes_.push_back(node);
  parent_.push_back(parent);
  index_of_name_.emplace(node->mName.C_Str(), id);  // the first of equal names wins
  for (unsigned c = 0; c < node->mNumChildren; ++c) collect(node->mChildren[c], id);
}

int AnimationEvaluator::node_index(const std::string& name) const {
  const auto it = index_of_name_.find(name);
  return it == index_of_name_.end() ? -1 : it->second;
}

Mat4 AnimationEvaluator::local_at(int node_id, double ticks) const {
  const Mat4 rest = to_mat4(nodes_[node_id]->mTransformation);
  const aiNodeAnim* channel = channel_[node_id];
  if (!channel) return rest;
  Vec3 translation, scaling;
  Quat rotation;
  decompose(rest, translation, rotation, scaling);
  if (channel->mNumPositionKeys > 0)
    translation = interpolate_vector_keys(channel->mPositionKeys, channel->mNumPositionKeys, ticks);
  if (channel->mNumRotationKeys > 0)
    rotation = interpolate_rotation_keys(channel->mRotationKeys, channel->mNumRotationKeys, ticks);
  if (channel->mNumScalingKeys > 0)
    scaling = interpolate_vector_keys(channel->mScalingKeys, channel->mNumScalingKeys, ticks);
  return compose(translation, rotation, scaling);
}

std::vector<Mat4> AnimationEvaluator::node_globals(double ticks) const {
  std::vector<Mat4> globals(nodes_.size());
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const Mat4 local = local_at(static_cast<int>(i), ticks);
    globals[i] = parent_[i] < 0 ? local : globals[parent_[i]] * local;
  }
  return globals;
}

std::vector<double> AnimationEvaluator::morph_weights(const aiNode& node, unsigned mesh_index, double ticks) const {
  const aiMesh& mesh = *scene_.mMeshes[mesh_index];
  std::vector<double> weights(mesh.mNumAnimMeshes);
  for (unsigned k = 0; k < mesh.mNumAnimMeshes; ++k) weights[k] = mesh.mAnimMeshes[k]->mWeight;
  auto it = morph_channel_.find(node.mName.C_Str());
  if (it == morph_channel_.end()) it = morph_channel_.find(mesh.mName.C_Str());
  if (it == morph_channel_.end() || it->second->mNumKeys == 0) return weights;
  const aiMeshMorphAnim& channel = *it->second;
  const auto [k, s] = bracket(channel.mKeys, channel.mNumKeys, ticks);
  std::fill(weights.begin(), weights.end(), 0.0);
  auto add_key = [&](const aiMeshMorphKey& key, double factor) {
    for (unsigned j = 0; j < key.mNumValuesAndWeights; ++j)
      if (key.mValues[j] < weights.size()) weights[key.mValues[j]] += factor * key.mWeights[j];
  };
  add_key(channel.mKeys[k], 1.0 - s);
  if (s != 0.0) add_key(channel.mKeys[k + 1], s);
  return weights;
}

void AnimationEvaluator::mesh_positions(int node_id, unsigned mesh_index, double ticks,
                                        const std::vector<Mat4>& globals, std::vector<Vec3>& out) const {
  const aiNode& node = *nodes_[node_id];
  const aiMesh& mesh = *scene_.mMeshes[mesh_index];
  const std::size_t first = out.size();
  for (unsigned v = 0; v < mesh.mNumVertices; ++v) out.push_back(to_vec3(mesh.mVertices[v]));
  Vec3* p = out.data() + first;

  if (mesh.mNumAnimMeshes > 0) {
    const std::vector<double> weights = morph_weights(node, mesh_index, ticks);
    std::vector<Vec3> base(p, p + mesh.mNumVertices);
    for (unsigned k = 0; k < mesh.mNumAnimMeshes; ++k) {
      const aiAnimMesh& target = *mesh.mAnimMeshes[k];
      if (weights[k] == 0.0 || !target.mVertices || target.mNumVertices != mesh.mNumVertices) continue;
      for (unsigned v = 0; v < mesh.mNumVertices; ++v)
        p[v] = p[v] + weights[k] * (to_vec3(target.mVertices[v]) - base[v]);
    }
  }

  if (mesh.mNumBones == 0) {
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) p[v] = transform_point(globals[node_id], p[v]);
    return;
  }
  std::vector<Vec3> sum(mesh.mNumVertices, Vec3{});
  std::vector<double> total(mesh.mNumVertices, 0.0);
  for (unsigned b = 0; b < mesh.mNumBones; ++b) {
    const aiBone& bone = *mesh.mBones[b];
    const int bone_node = node_index(bone.mName.C_Str());
    const Mat4 skin = (bone_node >= 0 ? globals[bone_node] : Mat4::identity()) * to_mat4(bone.mOffsetMatrix);
    for (unsigned w = 0; w < bone.mNumWeights; ++w) {
      const aiVertexWeight& weight = bone.mWeights[w];
      if (weight.mVertexId >= mesh.mNumVertices || weight.mWeight == 0.0f) continue;
      sum[weight.mVertexId] = sum[weight.mVertexId] + static_cast<double>(weight.mWeight) *
                                                           transform_point(skin, p[weight.mVertexId]);
      total[weight.mVertexId] += weight.mWeight;
    }
  }
  for (unsigned v = 0; v < mesh.mNumVertices; ++v)
    p[v] = total[v] > 0 ? (total[v] == 1.0 ? sum[v] : sum[v] / total[v]) : transform_point(globals[node_id], p[v]);
}

}  // namespace snag::io::assimp_detail
