#include "exporters/bench_page.hpp"

#include "exporters/html_assets.hpp"
#include "exporters/markup.hpp"
#include "libcd/core/error.hpp"

namespace snag::exporters {

namespace bench_assets {
extern const char page_js[], page_css[];  // bench_page_assets.cpp, generated
}  // namespace bench_assets

void write_bench_page(std::ostream& out, const nlohmann::json& results) {
  if (!html_assets::libraries)
    throw UsageError("the HTML page needs Chart.js, which this build left out; configure with -DSNAG_WITH_HTML=ON");
  out << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
      << "<title>snag-bench: speed against accuracy</title>\n<style>" << bench_assets::page_css << "</style>\n"
      << "<script>" << html_assets::chart_js << "</script>\n</head>\n<body>\n"
      << "<h1>snag-bench: speed against accuracy</h1>\n"
      << "<p>CCD methods on query sets with exact ground truth, on generated stability families and on scenes; "
         "every number is also in the JSON written beside this page.</p>\n"
      << "<div id=\"content\" data-results=\""
      << markup_escape(results.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)) << "\"></div>\n"
      << "<script>" << bench_assets::page_js << "</script>\n</body></html>\n";
}

}  // namespace snag::exporters
