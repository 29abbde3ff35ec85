#include "tools/common/rule_options.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "libcd/core/error.hpp"
#include "tools/common/manifest.hpp"

namespace snag::tools {

namespace {

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts{""};
  for (char c : text) {
    if (c == separator) {
      parts.emplace_back();
    } else {
      parts.back() += c;
    }
  }
  return parts;
}

bool parse_double(const std::string& text, double& value) {
  char* end = nullptr;
  errno = 0;
  value = std::strtod(text.c_str(), &end);
  return !text.empty() && end == text.c_str() + text.size() && errno != ERANGE && std::isfinite(value);
}

bool parse_count(const std::string& text, std::size_t& value) {
  if (text.empty() || text.size() > 19) return false;
  for (char c : text) {
    if (c < '0' || c > '9') return false;
  }
  value = static_cast<std::size_t>(std::strtoull(text.c_str(), nullptr, 10));
  return true;
}

std::pair<std::string, std::string> parse_pair(const std::string& text) {
  const std::vector<std::string> names = split(text, ',');
  if (names.size() != 2 || names[0].empty() || names[1].empty()) {
    throw UsageError("--pair '" + text + "': expected two object names A,B");
  }
  if (names[0] == names[1]) {
    throw UsageError("--pair '" + text + "': a pair is of two objects (self-collision is on unless --no-self)");
  }
  return {names[0], names[1]};
}

std::pair<std::string, double> parse_object_thickness(const std::string& text) {
  const std::size_t equals = text.find_last_of('=');
  double value = 0;
  if (equals == std::string::npos || equals == 0 || !parse_double(text.substr(equals + 1), value) || value < 0) {
    throw UsageError("--object-thickness '" + text + "': expected NAME=T with a thickness T >= 0");
  }
  return {text.substr(0, equals), value};
}

}  // namespace

void add_rule_options(CLI::App& app, RuleArguments& arguments) {
  if (CLI::Option* inputs = app.get_option_no_throw("inputs")) inputs->required(false);
  app.add_option("--manifest", arguments.manifest,
                 "Scene manifest (YAML, see snag-manifest(5)): inputs, objects and rules; options given\n"
                 "here add to its lists and override its values");
  app.add_option("--pair", arguments.pairs,
                 "Check objects A and B against each other (A,B; repeatable). Once any pair is given,\n"
                 "pairs of different objects not given are not checked")
      ->allow_extra_args(false);
  app.add_option("--no-self", arguments.no_self, "Do not check object NAME against itself (repeatable)")
      ->allow_extra_args(false);
  app.add_option("--object-thickness", arguments.object_thickness,
                 "Contact thickness of object NAME (NAME=T, repeatable); a pair's thickness is the mean of\n"
                 "its two objects'")
      ->allow_extra_args(false);
  app.add_option("--neighbourhood", arguments.neighbourhood,
                 "Ignore pairs of one object within K topological rings of each other (0 = off)")
      ->check(CLI::Range(0u, kMaxNeighbourhood));
  app.add_option("--allow", arguments.allow,
                 "A known contact that does not fail the scan (counted and listed; repeatable, first match\n"
                 "wins): OBJECTS[:FIELD]..., OBJECTS = A or A,B ('*' = any object, either order), FIELD =\n"
                 "collision | intersection | any, frames N, A-B or A- (inclusive), box=X0,Y0,Z0,X1,Y1,Z1\n"
                 "(the event's position inside), note=TEXT (last). E.g. cloth,body:collision:10-20")
      ->allow_extra_args(false);
  app.add_option("--fail-on", arguments.fail_on, "Exit 1 when at least N checked events are found (default 1; 0 = never)");
  app.add_option("--fail-on-collisions", arguments.fail_on_collisions,
                 "Exit 1 when at least N checked collisions are found (default 0 = never)");
  app.add_option("--fail-on-intersections", arguments.fail_on_intersections,
                 "Exit 1 when at least N checked intersections are found (default 0 = never)");
  app.add_option("--fail-on-regions", arguments.fail_on_regions,
                 "Exit 1 when at least N regions are found (default 0 = never)");
  app.add_option("--fail-on-tracks", arguments.fail_on_tracks,
                 "Exit 1 when at least N tracks are found (default 0 = never)");
}

report::AllowRule parse_allow_spec(const std::string& spec) {
  auto bad = [&](const std::string& problem) { return UsageError("--allow '" + spec + "': " + problem); };
  report::AllowRule rule;
  std::vector<std::string> fields;
  const std::size_t note = spec.find(":note=");
  for (const std::string& field : split(spec.substr(0, note), ':')) fields.push_back(field);
  if (note != std::string::npos) rule.note = spec.substr(note + 6);

  const std::vector<std::string> objects = split(fields[0], ',');
  if (objects.size() > 2 || objects[0].empty() || (objects.size() == 2 && objects[1].empty())) {
    throw bad("expected the objects first: A or A,B ('*' = any object)");
  }
  rule.object_a = objects[0] == "*" ? "" : objects[0];
  rule.object_b = objects.size() < 2 || objects[1] == "*" ? "" : objects[1];

  bool has_kind = false, has_frames = false;
  for (std::size_t i = 1; i < fields.size(); ++i) {
    const std::string& field = fields[i];
    if (field == "collision" || field == "intersection" || field == "any") {
      if (has_kind) throw bad("the kind is given twice");
      has_kind = true;
      if (field == "collision") rule.kind = EventKind::kCollision;
      if (field == "intersection") rule.kind = EventKind::kIntersection;
    } else if (!field.empty() && field[0] >= '0' && field[0] <= '9') {
      if (has_frames) throw bad("the frames are given twice");
      has_frames = true;
      const std::size_t dash = field.find('-');
      const std::string first = field.substr(0, dash);
      const std::string last = dash == std::string::npos ? first : field.substr(dash + 1);
      if (!parse_count(first, rule.first_frame) ||
          (!last.empty() && !parse_count(last, rule.last_frame)) || rule.first_frame > rule.last_frame) {
        throw bad("frames '" + field + "': expected N, A-B (A <= B) or A-");
      }
    } else if (field.rfind("box=", 0) == 0) {
      if (rule.box) throw bad("the box is given twice");
      const std::vector<std::string> numbers = split(field.substr(4), ',');
      std::array<Vec3, 2> box;
      bool ok = numbers.size() == 6;
      for (std::size_t k = 0; ok && k < 6; ++k) ok = parse_double(numbers[k], box[k / 3][static_cast<int>(k % 3)]);
      for (int k = 0; ok && k < 3; ++k) ok = box[0][k] <= box[1][k];
      if (!ok) throw bad("box: expected six numbers X0,Y0,Z0,X1,Y1,Z1, the low corner first");
      rule.box = box;
    } else {
      throw bad("unknown field '" + field +
                "' (expected collision, intersection, any, frames N or A-B or A-, box=..., note=...)");
    }
  }
  return rule;
}

ScanSetup resolve_scan_setup(const CacheArguments& cache, const RuleArguments& rules,
                             std::optional<double> thickness_option) {
  ScanSetup setup;
  std::optional<Manifest> manifest;
  if (!rules.manifest.empty()) {
    manifest = read_manifest(rules.manifest);
    setup.manifest = rules.manifest;
  }
  const bool manifest_inputs = manifest && !manifest->inputs.empty();
  if (manifest_inputs) {
    const std::string which = "the manifest " + rules.manifest + " names the inputs";
    if (!cache.inputs.empty()) throw UsageError(which + ": give no input files on the command line as well");
    if (!cache.names.empty()) throw UsageError(which + " and their objects' names: --name cannot rename them");
    if (!cache.topologies.empty()) throw UsageError(which + ": give point cache topologies there, not with --topology");
    if (cache.sequence) throw UsageError(which + ": give a sequence's files there ('files'), not with --sequence");
  } else if (cache.inputs.empty()) {
    throw UsageError(manifest ? "no inputs: the manifest " + rules.manifest +
                                    " names none (an object's 'input' or 'files') and none are given"
                              : std::string("no inputs: give the cache's files or a --manifest that names them"));
  }

  CacheArguments merged = cache;
  if (manifest) {
    if (merged.frames.empty() && manifest->frames) merged.frames = *manifest->frames;
    if (merged.weld.empty() && manifest->weld) merged.weld = *manifest->weld;
    if (merged.sample_rate <= 0 && manifest->fps) merged.sample_rate = *manifest->fps;
  }
  setup.cache = to_cache_options(merged);
  if (manifest_inputs) setup.cache.inputs = manifest->inputs;
  setup.frames = merged.frames;
  setup.weld = merged.weld.empty() ? "auto" : merged.weld;

  setup.thickness = thickness_option ? *thickness_option : (manifest && manifest->thickness ? *manifest->thickness : 0);
  if (manifest) setup.rules = manifest->rules;
  report::ScanRules& out = setup.rules;
  for (const std::string& pair : rules.pairs) out.pairs.push_back(parse_pair(pair));
  for (const std::string& name : rules.no_self) {
    if (name.empty()) throw UsageError("--no-self: expected an object name");
    out.no_self.push_back(name);
  }
  for (const std::string& text : rules.object_thickness) out.thickness.push_back(parse_object_thickness(text));
  if (rules.neighbourhood) out.neighbourhood = *rules.neighbourhood;
  for (const std::string& spec : rules.allow) out.allow.push_back(parse_allow_spec(spec));
  if (rules.fail_on) out.fail.events = *rules.fail_on;
  if (rules.fail_on_collisions) out.fail.collisions = *rules.fail_on_collisions;
  if (rules.fail_on_intersections) out.fail.intersections = *rules.fail_on_intersections;
  if (rules.fail_on_regions) out.fail.regions = *rules.fail_on_regions;
  if (rules.fail_on_tracks) out.fail.tracks = *rules.fail_on_tracks;
  return setup;
}

}  // namespace snag::tools
