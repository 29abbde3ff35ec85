// PNG files of the page's charts, for documents and the README: each chart
// of exporters/bench_page.hpp opened alone (#only=ID) in headless Chromium
// and screenshotted.
#pragma once

#include <string>
#include <vector>

namespace snag::bench {

/// Chromium's path: $SNAG_CHROMIUM, else `chromium` or `chromium-browser`
/// on the PATH; "" when there is none.
std::string chromium_path();

/// Writes DIR/snag-bench-ID.png for each chart id of `page` (an absolute
/// path) with `chromium`; each run is limited to 120 seconds. Returns the
/// files written. Throws snag::UsageError naming the chart when Chromium
/// fails or writes nothing.
std::vector<std::string> render_chart_pngs(const std::string& chromium, const std::string& page,
                                           const std::vector<std::string>& chart_ids, const std::string& dir);

}  // namespace snag::bench
