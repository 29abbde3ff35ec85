// The scene manifest (man/snag-manifest.5): a YAML file a pipeline keeps
// beside its caches, naming the inputs, the objects and the scan rules
// (collision groups, thickness per object, neighbourhood, allow-list, fail
// thresholds). Read with yaml-cpp; every problem is an InputError naming the
// file, the line and column, and what is wrong.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "io/open_cache.hpp"
#include "report/rules.hpp"

namespace snag::tools {

/// Manifests larger than this are refused before parsing.
constexpr std::size_t kMaxManifestBytes = 1 << 20;
/// The most topological rings `neighbourhood` may name (manifest and command line).
constexpr unsigned kMaxNeighbourhood = 64;

/// A manifest as read: the inputs (paths made relative to the manifest's
/// directory already resolved) and the rules, by object name.
struct Manifest {
  std::string path;                     ///< the manifest file
  /// One input per object, in order, each with its name; empty when the
  /// manifest's objects name no inputs (the command line gives them).
  std::vector<io::InputSpec> inputs;
  std::optional<std::string> frames;    ///< as --frames (A:B, A:B:S, A:)
  std::optional<std::string> weld;      ///< as --weld
  std::optional<double> thickness;      ///< default contact thickness, scene units
  std::optional<double> fps;            ///< as --fps
  report::ScanRules rules;
};

/// Reads the manifest at `path`. Throws InputError (file, line, column,
/// problem) for an unreadable, oversized, malformed or invalid manifest.
Manifest read_manifest(const std::string& path);

/// Parses manifest text; `path` names it in errors and its directory anchors
/// relative input paths. Throws InputError.
Manifest parse_manifest(const std::string& text, const std::string& path);

}  // namespace snag::tools
