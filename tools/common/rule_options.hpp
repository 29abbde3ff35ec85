// The scan rules on the command line (--manifest, --pair, --no-self,
// --object-thickness, --neighbourhood, --allow, --fail-on*), and how they
// merge with a manifest's: one place for snag-scan and any tool that judges
// a scan the same way. Semantics in man/snag-manifest.5.
#pragma once

#include <CLI/CLI.hpp>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "io/open_cache.hpp"
#include "report/rules.hpp"
#include "tools/common/cli.hpp"

namespace snag::tools {

/// Raw rule options as the command line gives them; resolve_scan_setup() checks them.
struct RuleArguments {
  std::string manifest;                       ///< --manifest FILE
  std::vector<std::string> pairs;             ///< --pair A,B
  std::vector<std::string> no_self;           ///< --no-self NAME
  std::vector<std::string> object_thickness;  ///< --object-thickness NAME=T
  std::optional<unsigned> neighbourhood;      ///< --neighbourhood K
  std::vector<std::string> allow;             ///< --allow SPEC
  std::optional<std::size_t> fail_on;         ///< --fail-on N (events)
  std::optional<std::size_t> fail_on_collisions, fail_on_intersections, fail_on_regions, fail_on_tracks;
};

/// Adds the rule options to `app`. Call it after add_cache_options(): the
/// positional inputs become optional, since a manifest may name them
/// (resolve_scan_setup() then says when there are none).
void add_rule_options(CLI::App& app, RuleArguments& arguments);

/// Parses one --allow SPEC: OBJECTS[:FIELD]... with OBJECTS = A | A,B (either
/// may be '*', any object) and FIELD one of collision | intersection | any,
/// a frame N or range A-B or A- (cache frame indices, inclusive),
/// box=X0,Y0,Z0,X1,Y1,Z1 (low corner, then high), note=TEXT (last: takes the
/// rest of the spec, colons included). Throws UsageError.
report::AllowRule parse_allow_spec(const std::string& spec);

/// What a scan runs with, the manifest and the command line merged.
struct ScanSetup {
  io::CacheOptions cache;   ///< for io::open_cache
  std::string frames;       ///< the frame selection as given ("" = every frame), for the report
  std::string weld;         ///< the weld as given ("auto" when not given), for the report
  double thickness = 0;     ///< global contact thickness: objects not in rules.thickness have it
  report::ScanRules rules;  ///< resolve against the scene with report::RuleSet
  std::string manifest;     ///< the manifest's path; empty when none
};

/// Reads the manifest (when --manifest is given) and merges it with the
/// command line. Inputs: the manifest's, or the positional ones (giving both,
/// or --name, --topology or --sequence with a manifest that names its inputs,
/// is a usage error; so is giving none). --frames, --weld, --fps and
/// `thickness_option` (the tool's --thickness, unset when not given) override
/// the manifest's values. Lists (--pair, --no-self, --object-thickness,
/// --allow) add to the manifest's (allow rules after the manifest's; a later
/// thickness for the same object wins); --neighbourhood and each --fail-on*
/// given override. Throws InputError (the manifest) or UsageError.
ScanSetup resolve_scan_setup(const CacheArguments& cache, const RuleArguments& rules,
                             std::optional<double> thickness_option);

}  // namespace snag::tools
