// write_html without a browser: a self-contained page (libraries inlined, no
// external references), the page data as the reports give it, text from
// reports that cannot break out of the page, scenes that do not fit the
// report refused, and a large cache kept under 20 MB.
#include "exporters/html.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>

#include "libcd/core/error.hpp"
#include "tests/html/html_fixtures.hpp"

namespace snag::test {
namespace {

using nlohmann::json;

std::string page_of(const std::vector<exporters::ReportDigest>& reports, const exporters::HtmlInputs& inputs) {
  std::ostringstream out;
  exporters::write_html(out, reports, inputs);
  return out.str();
}

/// The JSON the page's script reads.
json page_data(const std::string& page) {
  const std::string open = "<script type=\"application/json\" id=\"snag-data\">";
  const std::size_t begin = page.find(open);
  EXPECT_NE(begin, std::string::npos);
  const std::size_t end = page.find("</script>", begin);
  return json::parse(page.substr(begin + open.size(), end - begin - open.size()));
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(HtmlPage, IsSelfContainedWithTheLibrariesInline) {
  exporters::HtmlInputs inputs;
  inputs.scenes.emplace_back(grid_scene(20, 2));
  const std::string page = page_of({grid_report(20, 2, 3, 4)}, inputs);
  EXPECT_NE(page.find("Chart.js v3.9.1"), std::string::npos);
  EXPECT_NE(page.find("REVISION=\"111\""), std::string::npos);
  EXPECT_NE(page.find("OrbitControls"), std::string::npos);
  EXPECT_EQ(page.find("<script src"), std::string::npos);
  EXPECT_EQ(page.find("<link"), std::string::npos);
  EXPECT_EQ(page.find("<img"), std::string::npos);
  EXPECT_NE(page.find("class=\"verdict fail\""), std::string::npos);
}

TEST(HtmlPage, CarriesTheReportsCountsTracksAndView) {
  exporters::HtmlInputs inputs;
  inputs.scenes.emplace_back(grid_scene(20, 3));
  inputs.scenes.emplace_back();  // the second report has no positions
  const std::string page = page_of({grid_report(20, 5, 3, 4, "a.jsonl"), grid_report(20, 2, 1, 1, "b.jsonl")}, inputs);
  EXPECT_NE(page.find("<table class=\"summary\">"), std::string::npos);
  EXPECT_NE(page.find("id=\"report-1\""), std::string::npos);
  const json data = page_data(page);
  ASSERT_EQ(data.size(), 2u);
  EXPECT_EQ(data[0]["frames"]["index"].size(), 5u);
  EXPECT_EQ(data[0]["frames"]["intersection_regions"][4], 1);
  EXPECT_EQ(data[0]["tracks"].size(), 1u);
  EXPECT_EQ(data[0]["verdict"]["pass"], false);
  const json& view = data[0]["view"];
  EXPECT_EQ(view["frames"].size(), 3u);
  EXPECT_EQ(view["objects"][0]["faces_drawn"], 800);
  EXPECT_EQ(view["regions"].size(), 3u);  // the regions of the three frames drawn
  EXPECT_TRUE(data[1]["view"].is_null());
}

TEST(HtmlPage, ReportTextCannotEndTheScriptsOrAddMarkup) {
  exporters::HtmlInputs inputs;
  const std::string page = page_of({grid_report(4, 1, 0, 0, "</script><b id=\"x\">evil.jsonl")}, inputs);
  EXPECT_EQ(count(page, "</script>"), 5u);  // the data and four scripts
  EXPECT_EQ(page.find("<b id=\"x\">"), std::string::npos);  // in the data it is <b id=\\"x\\">
  EXPECT_NE(page.find("&lt;/script&gt;&lt;b id=&quot;x&quot;&gt;evil.jsonl"), std::string::npos);
  EXPECT_EQ(page_data(page)[0]["path"], "</script><b id=\"x\">evil.jsonl");
}

TEST(HtmlPage, RefusesASceneThatDoesNotFitTheReport) {
  exporters::HtmlInputs two_objects;
  two_objects.scenes.emplace_back(grid_scene(4, 1));
  two_objects.scenes[0]->objects.push_back(grid_mesh(4));
  EXPECT_THROW(page_of({grid_report(4, 1, 0, 0)}, two_objects), UsageError);

  exporters::HtmlInputs short_positions;
  short_positions.scenes.emplace_back(grid_scene(4, 1));
  short_positions.scenes[0]->frames[0].objects[0].resize(6);
  EXPECT_THROW(page_of({grid_report(4, 1, 0, 0)}, short_positions), UsageError);

  exporters::HtmlInputs fits;
  fits.scenes.emplace_back(grid_scene(4, 1));
  exporters::ReportDigest face_out_of_range = grid_report(4, 1, 0, 0);
  face_out_of_range.regions[0].faces_a.push_back(32);
  EXPECT_THROW(page_of({face_out_of_range}, fits), UsageError);
}

TEST(HtmlPage, LargeCacheStaysUnder20MB) {
  constexpr std::size_t kGrid = 600;  // 720,000 triangles, 361,201 vertices: 54 MB of geometry for 8 frames
  exporters::HtmlInputs inputs;
  inputs.scenes.emplace_back(grid_scene(kGrid, 8));
  const std::string page = page_of({grid_report(kGrid, 8, 300, 300)}, inputs);
  EXPECT_LT(page.size(), std::size_t{20} << 20);
  const json data = page_data(page);
  const json& view = data[0]["view"];
  EXPECT_TRUE(view["decimated"].get<bool>());
  EXPECT_EQ(view["regions"].size(), view["frames"].size());
  EXPECT_GE(view["frames"].size(), 1u);
  EXPECT_LT(view["objects"][0]["faces_drawn"].get<std::size_t>(), 2 * kGrid * kGrid);
}

}  // namespace
}  // namespace snag::test
