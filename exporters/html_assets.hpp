// The scripts and style that the HTML page inlines, embedded into the binary
// at build time (EmbedJs.cmake, embed_assets.cmake): Chart.js, three.js and
// its OrbitControls from Debian's packages, and the page's own script and
// style. Internal to html.cpp.
#pragma once

namespace snag::exporters::html_assets {

extern const char page_js[], page_css[];
extern const char chart_js[], three_js[], orbit_controls_js[];  ///< empty when built with SNAG_WITH_HTML=OFF
extern const bool libraries;  ///< whether the three libraries above are embedded

}  // namespace snag::exporters::html_assets
