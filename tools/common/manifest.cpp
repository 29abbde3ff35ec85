#include "tools/common/manifest.hpp"

#include <yaml-cpp/yaml.h>

#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <utility>

#include "io/vertex_weld.hpp"
#include "libcd/core/error.hpp"

namespace snag::tools {

namespace {

namespace fs = std::filesystem;

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext.empty() ? ext : ext.substr(1);
}

// Walks the YAML tree with the schema of man/snag-manifest.5. Every check
// throws InputError at the node it looked at: "FILE:LINE: column C: problem".
class ManifestParser {
 public:
  explicit ManifestParser(const std::string& path) : path_(path), directory_(fs::path(path).parent_path()) {}

  Manifest parse(const std::string& text) {
    try {
      const YAML::Node root = YAML::Load(text);
      if (!root.IsMap()) fail(root, "expected a map of keys (version, objects, pairs, allow, fail ...), found " +
                                        found(root));
      return parse_root(root);
    } catch (const YAML::Exception& error) {
      fail(error.mark, error.msg);
    }
  }

 private:
  using Entries = std::vector<std::pair<std::string, YAML::Node>>;

  [[noreturn]] void fail(const YAML::Mark& at, const std::string& problem) const {
    const bool known = at.line >= 0;
    InputLocation where{path_};
    if (known) where.line = static_cast<std::size_t>(at.line) + 1;
    throw InputError(where, known ? "column " + std::to_string(at.column + 1) + ": " + problem : problem);
  }
  [[noreturn]] void fail(const YAML::Node& at, const std::string& problem) const { fail(at.Mark(), problem); }

  static std::string found(const YAML::Node& node) {
    switch (node.Type()) {
      case YAML::NodeType::Map:
        return "a map";
      case YAML::NodeType::Sequence:
        return node.size() == 1 ? "a list of 1 item" : "a list of " + std::to_string(node.size()) + " items";
      case YAML::NodeType::Scalar:
        return "'" + node.Scalar() + "'";
      default:
        return "nothing";
    }
  }

  // The entries of a map, in order; unknown and repeated keys are errors.
  Entries entries(const YAML::Node& map, const std::string& what, std::initializer_list<const char*> allowed) const {
    if (!map.IsMap()) fail(map, what + ": expected a map, found " + found(map));
    Entries result;
    for (auto it = map.begin(); it != map.end(); ++it) {
      const YAML::Node key = it->first;  // a copy: it-> returns a temporary proxy
      if (!key.IsScalar()) fail(key, what + ": a key must be a plain name, found " + found(key));
      const std::string name = key.Scalar();
      bool known = false;
      for (const char* a : allowed) known = known || name == a;
      if (!known) {
        std::string list;
        for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
        fail(key, what + ": unknown key '" + name + "' (known: " + list + ")");
      }
      for (const auto& [seen, value] : result) {
        if (seen == name) fail(key, what + ": key '" + name + "' is given twice");
      }
      result.emplace_back(name, it->second);
    }
    return result;
  }

  std::string text(const YAML::Node& node, const std::string& what) const {
    if (!node.IsScalar()) fail(node, what + ": expected a string, found " + found(node));
    return node.Scalar();
  }

  std::string name(const YAML::Node& node, const std::string& what) const {
    std::string value = text(node, what);
    if (value.empty()) fail(node, what + ": an object name cannot be empty");
    return value;
  }

  double number(const YAML::Node& node, const std::string& what) const {
    if (!node.IsScalar()) fail(node, what + ": expected a number, found " + found(node));
    const std::string& s = node.Scalar();
    char* end = nullptr;
    errno = 0;
    const double value = std::strtod(s.c_str(), &end);
    if (s.empty() || end != s.c_str() + s.size() || errno == ERANGE || !std::isfinite(value)) {
      fail(node, what + ": expected a finite number, found '" + s + "'");
    }
    return value;
  }

  double non_negative(const YAML::Node& node, const std::string& what) const {
    const double value = number(node, what);
    if (value < 0) fail(node, what + ": must be 0 or more, found '" + node.Scalar() + "'");
    return value;
  }

  std::size_t count(const YAML::Node& node, const std::string& what) const {
    if (!node.IsScalar()) fail(node, what + ": expected a whole number >= 0, found " + found(node));
    const std::string& s = node.Scalar();
    bool digits = !s.empty() && s.size() <= 19;
    for (char c : s) digits = digits && c >= '0' && c <= '9';
    if (!digits) fail(node, what + ": expected a whole number >= 0, found '" + s + "'");
    return static_cast<std::size_t>(std::strtoull(s.c_str(), nullptr, 10));
  }

  bool flag(const YAML::Node& node, const std::string& what) const {
    if (node.IsScalar() && node.Scalar() == "true") return true;
    if (node.IsScalar() && node.Scalar() == "false") return false;
    fail(node, what + ": expected true or false, found " + found(node));
  }

  const YAML::Node& list(const YAML::Node& node, const std::string& what) const {
    if (!node.IsSequence()) fail(node, what + ": expected a list, found " + found(node));
    return node;
  }

  // A path as written, relative to the manifest's directory unless absolute.
  std::string input_path(const YAML::Node& node, const std::string& what) const {
    const std::string value = text(node, what);
    if (value.empty()) fail(node, what + ": a path cannot be empty");
    const fs::path p(value);
    return p.is_absolute() || directory_.empty() ? value : (directory_ / p).string();
  }

  std::array<Vec3, 2> box(const YAML::Node& node, const std::string& what) const {
    const std::string shape = what + ": expected two corners [[x0, y0, z0], [x1, y1, z1]]";
    if (!node.IsSequence() || node.size() != 2) fail(node, shape + ", found " + found(node));
    std::array<Vec3, 2> corners;
    for (std::size_t c = 0; c < 2; ++c) {
      const YAML::Node corner = node[c];
      if (!corner.IsSequence() || corner.size() != 3) fail(corner, shape + ", found " + found(corner));
      for (std::size_t k = 0; k < 3; ++k) corners[c][static_cast<int>(k)] = number(corner[k], what);
    }
    for (int k = 0; k < 3; ++k) {
      if (corners[0][k] > corners[1][k]) fail(node, what + ": the first corner must be the low one on every axis");
    }
    return corners;
  }

  Manifest parse_root(const YAML::Node& root) {
    Manifest manifest;
    manifest.path = path_;
    bool has_version = false;
    const Entries top = entries(root, "manifest", {"version", "objects", "pairs", "neighbourhood", "frames", "weld",
                                                   "thickness", "fps", "allow", "fail"});
    for (const auto& [key, value] : top) {
      if (key == "version") {
        has_version = true;
        if (!value.IsScalar() || value.Scalar() != "1") {
          fail(value, "version: this snag reads manifest version 1, found " + found(value));
        }
      } else if (key == "objects") {
        parse_objects(value, manifest);
      } else if (key == "pairs") {
        for (const YAML::Node& pair : list(value, "pairs")) {
          if (!pair.IsSequence() || pair.size() != 2) {
            fail(pair, "pairs: each pair is a list of two object names, found " + found(pair));
          }
          const std::string a = name(pair[0], "pairs"), b = name(pair[1], "pairs");
          if (a == b) fail(pair, "pairs: '" + a + "' twice: a pair is of two objects (self-collision is per object)");
          manifest.rules.pairs.emplace_back(a, b);
        }
      } else if (key == "neighbourhood") {
        const std::size_t k = count(value, "neighbourhood");
        if (k > kMaxNeighbourhood) {
          fail(value, "neighbourhood: at most " + std::to_string(kMaxNeighbourhood) + " rings, found " + found(value));
        }
        manifest.rules.neighbourhood = static_cast<unsigned>(k);
      } else if (key == "frames") {
        const std::string frames = text(value, "frames");
        try {
          io::parse_frame_selection(frames);
        } catch (const UsageError& error) {
          fail(value, std::string("frames: ") + error.what());
        }
        manifest.frames = frames;
      } else if (key == "weld") {
        const std::string weld = text(value, "weld");
        try {
          io::parse_weld(weld);
        } catch (const UsageError&) {
          fail(value, "weld: expected auto, none, exact or a distance >= 0, found " + found(value));
        }
        manifest.weld = weld;
      } else if (key == "thickness") {
        manifest.thickness = non_negative(value, "thickness");
      } else if (key == "fps") {
        manifest.fps = number(value, "fps");
        if (*manifest.fps <= 0) fail(value, "fps: must be more than 0, found " + found(value));
      } else if (key == "allow") {
        for (const YAML::Node& rule : list(value, "allow")) manifest.rules.allow.push_back(parse_allow(rule));
      } else if (key == "fail") {
        parse_fail(value, manifest.rules.fail);
      }
    }
    if (!has_version) fail(root, "missing 'version: 1' (the manifest's format version)");
    return manifest;
  }

  void parse_objects(const YAML::Node& objects, Manifest& manifest) {
    std::vector<std::string> names;
    std::size_t with_input = 0;
    for (const YAML::Node& object : list(objects, "objects")) {
      const Entries keys = entries(object, "objects", {"name", "input", "files", "topology", "thickness", "self"});
      io::InputSpec spec;
      const YAML::Node* input = nullptr;
      const YAML::Node* topology = nullptr;
      for (const auto& [key, value] : keys) {
        if (key == "name") {
          spec.name = name(value, "objects: name");
        } else if (key == "input") {
          input = &value;
          spec.path = input_path(value, "objects: input");
        } else if (key == "files") {
          if (list(value, "objects: files").size() == 0) fail(value, "objects: files: the list is empty");
          for (const YAML::Node& file : value) spec.frame_files.push_back(input_path(file, "objects: files"));
          spec.path = spec.frame_files.front();
        } else if (key == "topology") {
          topology = &value;
          spec.topology = input_path(value, "objects: topology");
        }
      }
      if (spec.name.empty()) fail(object, "objects: every object needs a 'name'");
      for (const std::string& seen : names) {
        if (seen == spec.name) fail(object, "objects: name '" + spec.name + "' is given twice");
      }
      names.push_back(spec.name);
      for (const auto& [key, value] : keys) {
        if (key == "thickness") manifest.rules.thickness.emplace_back(spec.name, non_negative(value, "objects: thickness"));
        if (key == "self" && !flag(value, "objects: self")) manifest.rules.no_self.push_back(spec.name);
      }
      if (input != nullptr && !spec.frame_files.empty()) {
        fail(object, "objects: '" + spec.name + "' has both 'input' and 'files': give one");
      }
      const bool point_cache = input != nullptr && (lower_extension(spec.path) == "pc2" || lower_extension(spec.path) == "mdd");
      if (point_cache && topology == nullptr) {
        fail(*input, "objects: '" + spec.name + "': a point cache (.pc2, .mdd) needs a 'topology' mesh");
      }
      if (!point_cache && topology != nullptr) {
        fail(*topology, "objects: '" + spec.name + "': 'topology' goes with a point cache input (.pc2, .mdd)");
      }
      const bool named_input = input != nullptr || !spec.frame_files.empty();
      with_input += named_input;
      if (with_input != 0 && with_input != names.size()) {
        fail(object, "objects: '" + spec.name + "'" + (named_input ? " has" : " has no") +
                         " input but an earlier object " + (named_input ? "has none" : "has one") +
                         ": name the inputs of every object or of none");
      }
      if (named_input) manifest.inputs.push_back(std::move(spec));
    }
  }

  report::AllowRule parse_allow(const YAML::Node& node) {
    report::AllowRule rule;
    for (const auto& [key, value] : entries(node, "allow", {"objects", "kind", "frames", "box", "note"})) {
      if (key == "objects") {
        if (!value.IsSequence() || value.size() < 1 || value.size() > 2) {
          fail(value, "allow: objects: expected one or two object names ('*' = any), found " + found(value));
        }
        const std::string a = name(value[0], "allow: objects");
        const std::string b = value.size() == 2 ? name(value[1], "allow: objects") : "*";
        rule.object_a = a == "*" ? "" : a;
        rule.object_b = b == "*" ? "" : b;
      } else if (key == "kind") {
        const std::string kind = text(value, "allow: kind");
        if (kind == "collision") {
          rule.kind = EventKind::kCollision;
        } else if (kind == "intersection") {
          rule.kind = EventKind::kIntersection;
        } else if (kind != "any") {
          fail(value, "allow: kind: expected collision, intersection or any, found " + found(value));
        }
      } else if (key == "frames") {
        if (value.IsScalar()) {
          rule.first_frame = rule.last_frame = count(value, "allow: frames");
        } else if (value.IsSequence() && value.size() == 2) {
          rule.first_frame = count(value[0], "allow: frames");
          const bool open = value[1].IsScalar() && value[1].Scalar() == "end";
          rule.last_frame = open ? static_cast<std::size_t>(-1) : count(value[1], "allow: frames");
          if (rule.first_frame > rule.last_frame) fail(value, "allow: frames: the first frame is after the last");
        } else {
          fail(value, "allow: frames: expected a frame N or a range [FIRST, LAST] or [FIRST, end], found " +
                          found(value));
        }
      } else if (key == "box") {
        rule.box = box(value, "allow: box");
      } else if (key == "note") {
        rule.note = text(value, "allow: note");
      }
    }
    return rule;
  }

  void parse_fail(const YAML::Node& node, report::FailThresholds& fail_at) {
    for (const auto& [key, value] : entries(node, "fail", {"events", "collisions", "intersections", "regions", "tracks"})) {
      const std::size_t n = count(value, "fail: " + key);
      if (key == "events") fail_at.events = n;
      if (key == "collisions") fail_at.collisions = n;
      if (key == "intersections") fail_at.intersections = n;
      if (key == "regions") fail_at.regions = n;
      if (key == "tracks") fail_at.tracks = n;
    }
  }

  std::string path_;
  fs::path directory_;
};

}  // namespace

Manifest parse_manifest(const std::string& text, const std::string& path) { return ManifestParser(path).parse(text); }

Manifest read_manifest(const std::string& path) {
  std::error_code error;
  if (fs::is_directory(path, error)) throw InputError({path}, "is a folder, not a manifest file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError({path}, "cannot open the manifest");
  // Read at most one byte past the limit, so that a device or pipe cannot make us read without end.
  std::string text(kMaxManifestBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (in.bad()) throw InputError({path}, "read error");
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.size() > kMaxManifestBytes) {
    throw InputError({path}, "larger than " + std::to_string(kMaxManifestBytes >> 20) + " MiB: not a manifest");
  }
  return parse_manifest(text, path);
}

}  // namespace snag::tools
