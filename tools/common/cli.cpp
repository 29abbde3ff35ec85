#include "tools/common/cli.hpp"

#include <algorithm>
#include <cctype>
#include <iostream>

#include "libcd/core/error.hpp"
#include "snag/config.hpp"

namespace snag::tools {

static std::string lower_extension(const std::string& path) {
  std::size_t dot = path.find_last_of('.');
  std::size_t slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

void add_cache_options(CLI::App& app, CacheArguments& arguments) {
  app.add_option("inputs", arguments.inputs,
                 "Cache inputs: a mesh file, a printf pattern (frame_%04d.obj), a glob (\"frame_*.ply\"),\n"
                 "a directory of per-frame meshes, a point cache (.pc2, .mdd; with --topology), or an\n"
                 "animated file (.gltf, .glb, .fbx, .dae). Several inputs become several objects.")
      ->required();
  app.add_option("-t,--topology", arguments.topologies,
                 "Topology mesh for each point cache input, in order (one value per -t)")
      ->allow_extra_args(false)
      ->take_all();
  app.add_option("-n,--name", arguments.names, "Object name for each input, in order (one value per -n)")
      ->allow_extra_args(false)
      ->take_all();
  app.add_flag("-s,--sequence", arguments.sequence,
               "The inputs are the frames of one mesh sequence, in order (e.g. a two-frame step: t0.ply t1.ply)");
  app.add_option("-f,--frames", arguments.frames, "Frames to use, 0-based and inclusive: A:B or A:B:STEP or A:");
  app.add_option("--fps", arguments.sample_rate, "Animated files: samples per second (default: the file's rate)")
      ->check(CLI::PositiveNumber);
  app.add_option("--start", arguments.start_time, "Animated files: first sample time in seconds")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--end", arguments.end_time, "Animated files: last sample time in seconds")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--weld", arguments.weld,
                 "Join coincident vertices for topology: auto (exact for FBX, Collada, glTF and other assimp\n"
                 "formats, none for OBJ, PLY, STL, point caches), none, exact (bit-identical in every frame),\n"
                 "or a distance DIST (within DIST in every frame). Reports keep the file's vertex ids.");
}

io::CacheOptions to_cache_options(const CacheArguments& arguments) {
  io::CacheOptions options;
  std::size_t next_topology = 0;
  if (arguments.sequence) {
    if (!arguments.topologies.empty()) throw UsageError("--sequence takes mesh files, not point caches (--topology)");
    if (arguments.names.size() > 1) throw UsageError("--sequence makes one input: give at most one --name");
    io::InputSpec spec;
    spec.path = arguments.inputs.front();
    spec.frame_files = arguments.inputs;
    if (!arguments.names.empty()) spec.name = arguments.names.front();
    options.inputs.push_back(std::move(spec));
  }
  for (std::size_t i = 0; i < arguments.inputs.size() && !arguments.sequence; ++i) {
    io::InputSpec spec;
    spec.path = arguments.inputs[i];
    const std::string ext = lower_extension(spec.path);
    if (ext == "pc2" || ext == "mdd") {
      if (next_topology >= arguments.topologies.size()) {
        throw UsageError("point cache '" + spec.path + "' needs a topology mesh: add --topology MESH");
      }
      spec.topology = arguments.topologies[next_topology++];
    }
    if (i < arguments.names.size()) spec.name = arguments.names[i];
    options.inputs.push_back(std::move(spec));
  }
  if (next_topology < arguments.topologies.size()) {
    throw UsageError("more --topology meshes than point cache inputs (.pc2, .mdd)");
  }
  if (arguments.names.size() > arguments.inputs.size()) {
    throw UsageError("more --name values than inputs");
  }
  options.weld = io::parse_weld(arguments.weld.empty() ? "auto" : arguments.weld);
  if (!arguments.frames.empty()) options.frames = io::parse_frame_selection(arguments.frames);
  if (arguments.sample_rate > 0) options.sample_rate = arguments.sample_rate;
  if (arguments.start_time >= 0) options.start_time = arguments.start_time;
  if (arguments.end_time >= 0) options.end_time = arguments.end_time;
  if (options.start_time && options.end_time && *options.end_time < *options.start_time) {
    throw UsageError("--end is before --start");
  }
  return options;
}

int parse_command_line(CLI::App& app, int argc, char** argv) {
  app.set_version_flag("--version", std::string(SNAG_VERSION));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    int code = app.exit(error);
    return code == 0 ? 0 : 2;
  }
  return -1;
}

}  // namespace snag::tools
