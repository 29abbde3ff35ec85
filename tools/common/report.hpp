// The scan report: JSON with a version number (schema in man/snag-scan.1).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "libcd/pipeline/scan.hpp"

namespace snag::tools {

/// What the report says about how the scan was run.
struct ReportSettings {
  std::string mode;        ///< "ccd", "dcd" or "all"
  std::string backend;     ///< the back end that ran: "cpu" or "cuda"
  std::string precision;   ///< "certified" or "fast"
  double thickness = 0, lambda = 1.2;
  unsigned threads = 0;
  std::string frames;      ///< the --frames selection, empty for all
  std::string source;      ///< FrameSource::description()
  std::string weld;        ///< the --weld setting (each object says which method ran)
};

/// Element references as reports write them: {"object": name, "vertex" | "face": local id}
/// or {"object": name, "edge": [two local vertex ids]}, from global ids of `scene`.
/// Vertex ids are the file's (file_vertex_id): a welded vertex is named by the
/// smallest file vertex joined into it.
nlohmann::json vertex_ref(const Scene& scene, Index v);
nlohmann::json face_ref(const Scene& scene, Index f);
nlohmann::json edge_ref(const Scene& scene, Index e);
/// "vf", "ee" or "tt".
const char* type_name(ContactType type);

/// Current report schema version.
constexpr int kReportVersion = 1;

/// Builds the report. Element ids are local to their object; frames are the
/// cache's 0-based frame indices after selection.
nlohmann::json make_report(const FrameSource& source, const ScanResult& result, const ReportSettings& settings);

}  // namespace snag::tools
