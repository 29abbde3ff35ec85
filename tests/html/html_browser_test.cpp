// The HTML page as a person sees it: snag-scan scans the bundled sample, the
// page is written for its report with the positions of its worst frames, and
// Debian's headless Chromium opens it from disk. The screenshot must not be
// blank (and the 3D view must show more than a few colours), and the page's
// self-check, read back from the DOM, must count what the report holds:
// frames charted, tracks listed, regions coloured in the frame shown. Skipped
// when chromium is not installed (scripts/setup.sh installs it).
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <sys/stat.h>

#include "exporters/digest.hpp"
#include "exporters/frame_positions.hpp"
#include "exporters/html.hpp"
#include "tests/tools/run_process.hpp"
#include "tests/tools/sample_paths.hpp"

namespace snag::test {
namespace {

/// Chromium's path: $SNAG_CHROMIUM, else chromium or chromium-browser on the PATH; "" when none.
std::string find_chromium() {
  if (const char* given = std::getenv("SNAG_CHROMIUM")) return given;
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "/usr/bin");
  for (std::string dir; std::getline(dirs, dir, ':');)
    for (const char* name : {"chromium", "chromium-browser"}) {
      const std::string candidate = dir + "/" + name;
      struct stat info {};
      if (stat(candidate.c_str(), &info) == 0 && (info.st_mode & S_IXUSR)) return candidate;
    }
  return "";
}

/// The attributes of the first <TAG ...> of `html` (`tag` a literal tag name).
std::map<std::string, std::string> attributes_of(const std::string& html, const std::string& tag) {
  std::map<std::string, std::string> attributes;
  std::smatch element;
  if (!std::regex_search(html, element, std::regex("<" + tag + "(\\s[^>]*)?>"))) return attributes;
  const std::string text = element[1].str();
  const std::regex attribute("([a-z-]+)=\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), attribute); it != std::sregex_iterator(); ++it)
    attributes[(*it)[1].str()] = (*it)[2].str();
  return attributes;
}

/// What png_colours.py says of a screenshot.
struct Screenshot {
  int width = 0, height = 0;
  double changed = 0, box_changed = 0;  ///< share of pixels not of the background colour
  int colours = 0, box_colours = 0;
};

class HtmlInBrowser : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    chromium_ = new std::string(find_chromium());
    if (chromium_->empty()) return;
    dir_ = new TemporaryDirectory;
    report_ = new std::string(dir_->path("sample.jsonl"));
    std::vector<std::string> arguments = sample_pc2_inputs();
    arguments.insert(arguments.end(), {"--threads", "2", "-q", "-r", *report_});
    const ProcessResult scan = run_process(SNAG_SCAN_EXE, arguments);
    ASSERT_EQ(scan.exit_code, 1) << scan.err;  // the sample fails its default threshold
  }
  static void TearDownTestSuite() {
    delete dir_;
    delete report_;
    delete chromium_;
    dir_ = nullptr;
  }
  void SetUp() override {
    if (chromium_->empty())
      GTEST_SKIP() << "chromium is not installed (scripts/setup.sh installs it): the HTML page is not opened "
                      "in a browser";
  }

  /// The report read for the page, keeping the face lists of `frames`.
  static exporters::ReportDigest digest(const std::set<std::size_t>& frames = {}) {
    return exporters::read_digest(*report_, frames);
  }

  /// The sample's scene at `frames` (most important first), read from the cache again.
  static exporters::HtmlScene scene(const exporters::ReportDigest& digest, const std::vector<std::size_t>& frames) {
    io::CacheOptions cache;
    cache.inputs = {{kClothPc2, kClothRest, "", {}}, {kBodyPc2, kBodyRest, "", {}}};
    const exporters::FramePositions positions(digest, cache);
    exporters::HtmlScene view;
    const Scene& s = positions.scene();
    for (const Object& object : s.objects()) view.objects.push_back({{object.triangles.begin(), object.triangles.end()}});
    for (std::size_t frame : frames) {
      const std::vector<Vec3> x = positions.positions(frame);
      exporters::HtmlFrame f;
      f.frame = frame;
      for (std::size_t o = 0; o < s.objects().size(); ++o) {
        f.objects.emplace_back();
        for (Index v = s.vertex_offset(o); v < s.vertex_offset(o + 1); ++v)
          f.objects.back().insert(f.objects.back().end(), {float(x[v].x), float(x[v].y), float(x[v].z)});
      }
      view.frames.push_back(std::move(f));
    }
    return view;
  }

  static std::string write_page(const std::string& name, const std::vector<exporters::ReportDigest>& reports,
                                const exporters::HtmlInputs& inputs) {
    const std::string path = dir_->path(name);
    std::ofstream out(path, std::ios::binary);
    exporters::write_html(out, reports, inputs);
    out.close();
    EXPECT_TRUE(out) << path;
    return path;
  }

  /// Chromium's flags: headless, software WebGL (SwiftShader), time for the scripts to finish.
  static std::vector<std::string> browser_flags(const std::string& profile, bool webgl) {
    std::vector<std::string> flags{"--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
                                   "--user-data-dir=" + profile, "--virtual-time-budget=10000",
                                   "--window-size=1280,2400", "--hide-scrollbars"};
    if (webgl) {
      flags.insert(flags.end(), {"--use-angle=swiftshader", "--enable-unsafe-swiftshader"});
    } else {
      flags.push_back("--disable-3d-apis");
    }
    return flags;
  }

  /// The DOM after the page's scripts ran.
  static std::string dump_dom(const std::string& page, bool webgl = true) {
    std::vector<std::string> arguments = browser_flags(dir_->path("profile-dom"), webgl);
    arguments.insert(arguments.end(), {"--dump-dom", "file://" + page});
    ProcessOptions options;
    options.timeout_seconds = 120;
    const ProcessResult browser = run_process(*chromium_, arguments, options);
    EXPECT_EQ(browser.exit_code, 0) << browser.err;
    return browser.out;
  }

  /// A screenshot of the page, described by png_colours.py; `box` as "x0 y0 x1 y1" or "".
  static Screenshot screenshot(const std::string& page, const std::string& png, const std::string& box) {
    std::vector<std::string> arguments = browser_flags(dir_->path("profile-shot"), true);
    arguments.insert(arguments.end(), {"--screenshot=" + png, "file://" + page});
    ProcessOptions options;
    options.timeout_seconds = 120;
    const ProcessResult browser = run_process(*chromium_, arguments, options);
    EXPECT_EQ(browser.exit_code, 0) << browser.err;
    std::vector<std::string> check{PNG_COLOURS_PY, png};
    std::istringstream corners(box);
    for (std::string corner; corners >> corner;) check.push_back(corner);
    const ProcessResult python = run_process("/usr/bin/env", [&] {
      std::vector<std::string> a{"python3"};
      a.insert(a.end(), check.begin(), check.end());
      return a;
    }());
    EXPECT_EQ(python.exit_code, 0) << python.err;
    Screenshot shot;
    std::istringstream(python.out) >> shot.width >> shot.height >> shot.changed >> shot.colours >> shot.box_changed >>
        shot.box_colours;
    return shot;
  }

  static std::string* chromium_;
  static std::string* report_;
  static TemporaryDirectory* dir_;
};

std::string* HtmlInBrowser::chromium_ = nullptr;
std::string* HtmlInBrowser::report_ = nullptr;
TemporaryDirectory* HtmlInBrowser::dir_ = nullptr;

/// Regions of `frame` whose face lists the report gives (those the page colours).
std::size_t regions_with_faces(const exporters::ReportDigest& digest, std::size_t frame) {
  std::size_t n = 0;
  for (const report::RegionRecord& region : digest.regions)
    n += region.frame == frame && !(region.faces_a.empty() && region.faces_b.empty());
  return n;
}

std::size_t triangles_of(const exporters::ReportDigest& digest) {
  std::size_t n = 0;
  for (const report::ObjectInfo& object : digest.header.objects) n += object.triangles;
  return n;
}

TEST_F(HtmlInBrowser, SamplePageDrawsItsChartTracksAndRegions) {
  const std::vector<std::size_t> worst = exporters::worst_frames(digest(), 3);
  ASSERT_EQ(worst.size(), 3u);
  const exporters::ReportDigest report = digest({worst.begin(), worst.end()});
  exporters::HtmlInputs inputs;
  inputs.scenes.emplace_back(scene(report, worst));
  const std::string page = write_page("sample.html", {report}, inputs);

  const std::string dom = dump_dom(page);
  const auto body = attributes_of(dom, "body");
  EXPECT_EQ(body.count("data-error"), 0u) << body.at("data-error");
  EXPECT_EQ(body.at("data-ready"), "1");
  EXPECT_EQ(body.at("data-reports"), "1");
  EXPECT_EQ(body.at("data-frames-charted"), std::to_string(report.frames.size()));
  EXPECT_EQ(body.at("data-tracks-listed"), std::to_string(report.trailer.tracks));
  EXPECT_EQ(body.at("data-frame-shown"), std::to_string(worst[0]));
  EXPECT_EQ(body.at("data-regions-coloured"), std::to_string(regions_with_faces(report, worst[0])));
  EXPECT_GT(regions_with_faces(report, worst[0]), 0u);
  EXPECT_EQ(body.at("data-faces-drawn"), std::to_string(triangles_of(report)));  // small: nothing decimated
  EXPECT_EQ(body.at("data-webgl"), "1") << "SwiftShader's WebGL did not start in headless chromium";

  const auto section = attributes_of(dom, "section");
  ASSERT_EQ(section.count("data-view-box"), 1u);
  const std::string png = dir_->path("sample.png");
  const Screenshot shot = screenshot(page, png, section.at("data-view-box"));
  EXPECT_EQ(shot.width, 1280);
  EXPECT_GT(shot.changed, 0.05) << "the screenshot is blank";
  EXPECT_GT(shot.colours, 50);
  EXPECT_GT(shot.box_changed, 0.05) << "the 3D view is blank";
  EXPECT_GT(shot.box_colours, 20) << "the 3D view shows no shaded, coloured mesh";
  if (const char* keep = std::getenv("SNAG_KEEP_SCREENSHOT")) {  // e.g. to refresh docs/snag-report-sample.png
    std::ifstream in(png, std::ios::binary);
    std::ofstream(keep, std::ios::binary) << in.rdbuf();
  }
}

TEST_F(HtmlInBrowser, WithoutWebGLTheViewIsDrawnFlatAndSaysSo) {
  const std::vector<std::size_t> worst = exporters::worst_frames(digest(), 1);
  const exporters::ReportDigest report = digest({worst.begin(), worst.end()});
  exporters::HtmlInputs inputs;
  inputs.scenes.emplace_back(scene(report, worst));
  const std::string page = write_page("flat.html", {report}, inputs);
  const std::string dom = dump_dom(page, false);
  const auto body = attributes_of(dom, "body");
  EXPECT_EQ(body.count("data-error"), 0u) << body.at("data-error");
  EXPECT_EQ(body.at("data-ready"), "1");
  EXPECT_EQ(body.at("data-webgl"), "0");
  EXPECT_EQ(body.at("data-frames-charted"), std::to_string(report.frames.size()));
  EXPECT_EQ(body.at("data-regions-coloured"), std::to_string(regions_with_faces(report, worst[0])));
  EXPECT_NE(dom.find("WebGL is not available"), std::string::npos);
}

TEST_F(HtmlInBrowser, BatchPageListsEveryReport) {
  // The sample with its worst frame, a window of it without positions, and
  // the reference scene (cloth_ball 92 -> 93 of the shared meshes) without positions.
  const std::string window = dir_->path("window.jsonl");
  std::vector<std::string> arguments = sample_pc2_inputs();
  arguments.insert(arguments.end(), {"--frames", "24:26", "--threads", "2", "-q", "-r", window});
  ASSERT_EQ(run_process(SNAG_SCAN_EXE, arguments).exit_code, 1);
  const std::string reference = dir_->path("cloth_ball92_93.jsonl");
  const std::string meshes = std::string(SNAG_SHARED_DATA_DIR) + "/meshes/";
  ASSERT_EQ(run_process(SNAG_SCAN_EXE, {"--sequence", meshes + "cloth_ball92.ply", meshes + "cloth_ball93.ply",
                                        "--events", "regions", "-q", "-r", reference})
                .exit_code,
            1);
  const std::vector<std::size_t> worst = exporters::worst_frames(digest(), 1);
  std::vector<exporters::ReportDigest> reports{digest({worst.begin(), worst.end()}), exporters::read_digest(window),
                                               exporters::read_digest(reference)};
  exporters::HtmlInputs inputs;
  inputs.scenes.emplace_back(scene(reports[0], worst));
  inputs.scenes.emplace_back();
  inputs.scenes.emplace_back();
  const std::string page = write_page("batch.html", reports, inputs);

  const std::string dom = dump_dom(page);
  const auto body = attributes_of(dom, "body");
  EXPECT_EQ(body.count("data-error"), 0u) << body.at("data-error");
  EXPECT_EQ(body.at("data-ready"), "1");
  EXPECT_EQ(body.at("data-reports"), "3");
  std::size_t frames = 0, tracks = 0;
  for (const exporters::ReportDigest& report : reports) {
    frames += report.frames.size();
    tracks += report.trailer.tracks;
  }
  EXPECT_EQ(body.at("data-frames-charted"), std::to_string(frames));
  EXPECT_EQ(body.at("data-tracks-listed"), std::to_string(tracks));
  EXPECT_EQ(body.at("data-regions-coloured"), std::to_string(regions_with_faces(reports[0], worst[0])));
  EXPECT_NE(dom.find("<table class=\"summary\">"), std::string::npos);
  EXPECT_NE(dom.find("id=\"report-1\""), std::string::npos);
  EXPECT_NE(dom.find("id=\"report-2\""), std::string::npos);
  EXPECT_NE(dom.find("cloth_ball92_93.jsonl"), std::string::npos);
  EXPECT_NE(dom.find("This page carries no positions"), std::string::npos);
}

}  // namespace
}  // namespace snag::test
