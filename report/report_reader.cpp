// Streaming reader of scan reports. The file is read in chunks of kChunk
// bytes into one buffer with SIMDJSON_PADDING bytes to spare at its end; each
// line is parsed in place by simdjson's DOM parser (the bytes after a line are
// readable, which is all the padding must be), so nothing is copied but the
// tail of a chunk that holds the start of a line. A line longer than the
// buffer grows it, up to kMaxLine; a longer line is an error.
#include "report/report_reader.hpp"

#include <simdjson.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string_view>
#include <unordered_map>
#include <unordered_set>

#include "libcd/core/error.hpp"

namespace snag::report {

namespace {

constexpr std::size_t kChunk = std::size_t{8} << 20;
constexpr std::size_t kFirstBuffer = std::size_t{64} << 10;  // grows by doubling to kChunk: small reports stay cheap
constexpr std::size_t kMaxLine = std::size_t{256} << 20;

using simdjson::dom::array;
using simdjson::dom::element;
using simdjson::dom::object;

// Lines of a file, read in chunks. A line is handed out in place and stays
// valid (with SIMDJSON_PADDING readable bytes after it) until the next call.
class LineSource {
 public:
  explicit LineSource(const std::string& path) : path_(path) {
    if (path == "-") {
      file_ = stdin;
    } else {
      file_ = std::fopen(path.c_str(), "rb");
      if (file_ == nullptr) {
        throw InputError({path}, std::string("cannot open the report: ") + std::strerror(errno));
      }
      owned_ = true;
    }
    reserve(kFirstBuffer);
  }
  ~LineSource() {
    if (owned_) std::fclose(file_);
  }
  LineSource(const LineSource&) = delete;
  LineSource& operator=(const LineSource&) = delete;

  // The next line without its end ('\n', and a '\r' before it); false at the
  // end of the file. `line` is the number the line will have, for errors.
  bool next(std::string_view& text, bool& ended, std::size_t line) {
    std::size_t scanned = begin_;
    for (;;) {
      const void* found = std::memchr(buffer_.get() + scanned, '\n', end_ - scanned);
      if (found != nullptr) {
        const std::size_t stop = static_cast<const char*>(found) - buffer_.get();
        text = trimmed(begin_, stop);
        begin_ = stop + 1;
        ended = true;
        return true;
      }
      if (end_ - begin_ > kMaxLine) {
        throw InputError({path_, line}, "the line is longer than " + std::to_string(kMaxLine >> 20) +
                                            " MiB: not a scan report, or a damaged one");
      }
      if (eof_) {
        if (begin_ == end_) return false;
        text = trimmed(begin_, end_);
        begin_ = end_;
        ended = false;
        return true;
      }
      scanned = end_;
      refill(line);
      scanned -= shifted_;
    }
  }

 private:
  std::string_view trimmed(std::size_t from, std::size_t to) const {
    if (to > from && buffer_[to - 1] == '\r') --to;
    return {buffer_.get() + from, to - from};
  }

  void reserve(std::size_t capacity) {
    std::unique_ptr<char[]> grown(new char[capacity + simdjson::SIMDJSON_PADDING]);
    if (end_ > begin_) std::memcpy(grown.get(), buffer_.get() + begin_, end_ - begin_);
    end_ -= begin_;
    begin_ = 0;
    buffer_ = std::move(grown);
    capacity_ = capacity;
    std::memset(buffer_.get() + capacity_, ' ', simdjson::SIMDJSON_PADDING);
  }

  // Moves the unread part to the front (growing the buffer when a line fills
  // it) and reads one more chunk or what is left of the file.
  void refill(std::size_t line) {
    shifted_ = begin_;
    if (begin_ > 0) {
      std::memmove(buffer_.get(), buffer_.get() + begin_, end_ - begin_);
      end_ -= begin_;
      begin_ = 0;
    }
    if (capacity_ - end_ < std::min(capacity_, kChunk) / 2) reserve(std::min(2 * capacity_, kMaxLine + kChunk));
    const std::size_t n = std::fread(buffer_.get() + end_, 1, capacity_ - end_, file_);
    end_ += n;
    if (n == 0) {
      if (std::ferror(file_)) throw InputError({path_, line}, std::string("cannot read the report: ") +
                                                                   std::strerror(errno));
      eof_ = true;
    }
  }

  std::string path_;
  std::FILE* file_ = nullptr;
  bool owned_ = false;
  std::unique_ptr<char[]> buffer_;
  std::size_t capacity_ = 0, begin_ = 0, end_ = 0, shifted_ = 0;
  bool eof_ = false;
};

// Which element an element reference must name.
enum class RefKind { kVertex, kFace, kEdge };

}  // namespace

struct ReportReader::State {
  explicit State(const std::string& file) : path(file), lines(file) {}

  std::string path;
  LineSource lines;
  simdjson::dom::parser parser;
  std::size_t line = 0;
  const char* record = "header";  // the record being read, for messages

  Header header;
  std::unordered_map<std::string, std::size_t> object_of_name;
  FrameRecord frame;
  EventRecord event;
  RegionRecord region;
  TrackRecord track;
  Trailer trailer;

  // Order: frames read, where within the current frame, the trailer.
  enum class Phase { kHeader, kEvents, kRegions, kTracks, kDone };
  Phase phase = Phase::kHeader;
  std::size_t frames_read = 0;
  std::vector<std::size_t> frame_indices;  // cache indices of the frames read, increasing
  // Regions of the current frame, and the regions its events name (with the
  // first line naming each).
  std::unordered_set<std::size_t> frame_regions;
  std::unordered_map<std::size_t, std::size_t> named_regions;

  [[noreturn]] void fail(const std::string& problem) const { throw InputError({path, line}, problem); }
  [[noreturn]] void fail_key(const char* key, const char* problem) const {
    fail(std::string(record) + " record: \"" + key + "\" " + problem);
  }

  // --- typed access to keys of a record ------------------------------------

  element member(const object& o, const char* key) const {
    element value;
    if (o.at_key(key).get(value) != simdjson::SUCCESS) fail_key(key, "is missing");
    return value;
  }
  object dict(const object& o, const char* key) const {
    object value;
    if (member(o, key).get_object().get(value) != simdjson::SUCCESS) fail_key(key, "is not an object");
    return value;
  }
  array list(const object& o, const char* key) const {
    array value;
    if (member(o, key).get_array().get(value) != simdjson::SUCCESS) fail_key(key, "is not an array");
    return value;
  }
  std::size_t count_of(const element& e, const char* key) const {
    std::uint64_t value = 0;
    if (e.get_uint64().get(value) != simdjson::SUCCESS || value > std::numeric_limits<std::size_t>::max()) {
      fail_key(key, "is not a non-negative integer");
    }
    return static_cast<std::size_t>(value);
  }
  std::size_t count(const object& o, const char* key) const { return count_of(member(o, key), key); }
  /// A count or null (kNone).
  std::size_t optional_count(const object& o, const char* key) const {
    const element value = member(o, key);
    return value.is_null() ? kNone : count_of(value, key);
  }
  /// Non-finite numbers are written as null and read back as NaN.
  double number_of(const element& e, const char* key) const {
    if (e.is_null()) return std::numeric_limits<double>::quiet_NaN();
    double value = 0;
    if (e.get_double().get(value) != simdjson::SUCCESS) fail_key(key, "is not a number");
    return value;
  }
  double number(const object& o, const char* key) const { return number_of(member(o, key), key); }
  std::string_view text_of(const element& e, const char* key) const {
    std::string_view value;
    if (e.get_string().get(value) != simdjson::SUCCESS) fail_key(key, "is not a string");
    return value;
  }
  std::string_view text(const object& o, const char* key) const { return text_of(member(o, key), key); }
  bool flag(const object& o, const char* key) const {
    bool value = false;
    if (member(o, key).get_bool().get(value) != simdjson::SUCCESS) fail_key(key, "is not true or false");
    return value;
  }
  Vec3 vec3_of(const element& e, const char* key) const {
    array xyz;
    if (e.get_array().get(xyz) != simdjson::SUCCESS || xyz.size() != 3) fail_key(key, "is not [x, y, z]");
    Vec3 p;
    int i = 0;
    for (element c : xyz) p[i++] = number_of(c, key);
    return p;
  }
  Vec3 vec3(const object& o, const char* key) const { return vec3_of(member(o, key), key); }
  Bounds bounds_of(const element& e, const char* key) const {
    array corners;
    if (e.get_array().get(corners) != simdjson::SUCCESS || corners.size() != 2) {
      fail_key(key, "is not [[x, y, z], [x, y, z]]");
    }
    Bounds b;
    b.lo = vec3_of(corners.at(0).value_unsafe(), key);
    b.hi = vec3_of(corners.at(1).value_unsafe(), key);
    return b;
  }
  Bounds bounds(const object& o, const char* key) const { return bounds_of(member(o, key), key); }

  // --- names, ids and frames ------------------------------------------------

  std::size_t object_index(std::string_view name, const char* key) const {
    const auto it = object_of_name.find(std::string(name));
    if (it == object_of_name.end()) {
      fail(std::string(record) + " record: \"" + key + "\" names object \"" + std::string(name) +
           "\", which the header does not list");
    }
    return it->second;
  }
  // ["a", "b"]: two object names, as indices.
  std::pair<std::size_t, std::size_t> object_pair(const object& o, const char* key) const {
    array names = list(o, key);
    if (names.size() != 2) fail_key(key, "is not a pair of object names");
    const std::size_t a = object_index(text_of(names.at(0).value_unsafe(), key), key);
    const std::size_t b = object_index(text_of(names.at(1).value_unsafe(), key), key);
    return {a, b};
  }
  std::size_t local_id(const element& e, const char* key, std::size_t limit, const char* what,
                       std::size_t object) const {
    const std::size_t id = count_of(e, key);
    if (id >= limit) {
      fail(std::string(record) + " record: " + what + " " + std::to_string(id) + " of \"" +
           header.objects[object].name + "\" is out of range (it has " + std::to_string(limit) + ")");
    }
    return id;
  }
  // {"object": NAME, "vertex" | "face": ID} or {"object": NAME, "edge": [U, V]}.
  ElementRef element_ref(const object& o, const char* key, RefKind kind) const {
    object ref = dict(o, key);
    ElementRef out;
    out.object = object_index(text(ref, "object"), key);
    const ObjectInfo& info = header.objects[out.object];
    switch (kind) {
      case RefKind::kVertex:
        out.id = local_id(member(ref, "vertex"), "vertex", info.file_vertices, "vertex", out.object);
        break;
      case RefKind::kFace:
        out.id = local_id(member(ref, "face"), "face", info.triangles, "face", out.object);
        break;
      case RefKind::kEdge: {
        array ends = list(ref, "edge");
        if (ends.size() != 2) fail_key("edge", "is not a pair of vertex ids");
        out.id = local_id(ends.at(0).value_unsafe(), "edge", info.file_vertices, "edge vertex", out.object);
        out.id2 = local_id(ends.at(1).value_unsafe(), "edge", info.file_vertices, "edge vertex", out.object);
        if (out.id == out.id2) fail(std::string(record) + " record: the edge's two ends are one vertex");
        break;
      }
    }
    return out;
  }
  EventKind kind_of(std::string_view kind) const {
    if (kind == "collision") return EventKind::kCollision;
    if (kind == "intersection") return EventKind::kIntersection;
    fail(std::string(record) + " record: unknown kind \"" + std::string(kind) + "\"");
  }
  // A frame of the report that has been read: a cache index among the frame records so far.
  void check_frame_read(std::size_t index, const char* key) const {
    if (!std::binary_search(frame_indices.begin(), frame_indices.end(), index)) {
      fail(std::string(record) + " record: \"" + key + "\" is frame " + std::to_string(index) +
           ", which is not a frame of the report before this line");
    }
  }
  void check_objects_ordered(std::size_t a, std::size_t b) const {
    if (a > b) {
      fail(std::string(record) + " record: objects \"" + header.objects[a].name + "\", \"" +
           header.objects[b].name + "\" are not in the header's order");
    }
  }

  // --- lines ----------------------------------------------------------------

  // Reads and parses the next line; false at the end of the file.
  bool read_line(object& root, std::string_view& kind, bool first) {
    std::string_view text;
    bool ended = true;
    if (!lines.next(text, ended, line + 1)) return false;
    ++line;
    if (first) check_not_version_1(text);
    if (text.find_first_not_of(" \t") == std::string_view::npos) {
      fail("an empty line (a report holds one record on each line)");
    }
    element doc;
    if (const auto error = parser.parse(text.data(), text.size(), false).get(doc); error != simdjson::SUCCESS) {
      if (!ended) fail(std::string("the last line is cut short or not JSON (") + simdjson::error_message(error) + ")");
      fail(std::string("not a JSON record (") + simdjson::error_message(error) + ")");
    }
    if (doc.get_object().get(root) != simdjson::SUCCESS) fail("not a JSON object: each line holds one record");
    if (first) check_not_version_1(root);
    element record_key;
    if (root.at_key("record").get(record_key) != simdjson::SUCCESS) fail("no \"record\" key");
    if (record_key.get_string().get(kind) != simdjson::SUCCESS) fail("\"record\" is not a string");
    return true;
  }

  [[noreturn]] void fail_version_1() const {
    fail("this is a version 1 report; scan the cache again with this snag-scan");
  }
  // Version 1 was one JSON document, written indented: its first line is "{".
  void check_not_version_1(std::string_view first_line) const {
    const std::size_t start = first_line.find_first_not_of(" \t");
    if (start != std::string_view::npos && first_line.substr(start) == "{") fail_version_1();
  }
  void check_not_version_1(const object& root) const {
    std::int64_t version = 0;
    const bool has_record = root.at_key("record").error() == simdjson::SUCCESS;
    if (root.at_key("version").get_int64().get(version) == simdjson::SUCCESS && version == 1) fail_version_1();
    if (!has_record && root.at_key("version").error() == simdjson::SUCCESS) fail_version_1();
  }

  // --- records --------------------------------------------------------------

  void read_header() {
    object root;
    std::string_view kind;
    if (!read_line(root, kind, true)) {
      line = 1;
      fail("the file is empty: not a scan report");
    }
    if (kind != "header") fail("the first record is \"" + std::string(kind) + "\", not the header");
    record = "header";
    if (text(root, "format") != "snag-report") {
      fail("not a snag report (format \"" + std::string(text(root, "format")) + "\")");
    }
    std::int64_t version = 0;
    if (member(root, "version").get_int64().get(version) != simdjson::SUCCESS) fail_key("version", "is not an integer");
    if (version == 1) fail_version_1();
    if (version != kSchemaVersion) {
      fail("report version " + std::to_string(version) + " is not one this reader knows (it reads version " +
           std::to_string(kSchemaVersion) + ")");
    }
    Header& h = header;
    h.version = static_cast<int>(version);
    h.tool = text(root, "tool");
    h.snag_version = text(root, "snag_version");
    h.source = text(root, "source");
    for (element item : list(root, "objects")) {
      object o;
      if (item.get_object().get(o) != simdjson::SUCCESS) fail_key("objects", "holds something that is not an object");
      ObjectInfo info;
      info.name = text(o, "name");
      info.vertices = count(o, "vertices");
      info.file_vertices = count(o, "file_vertices");
      info.triangles = count(o, "triangles");
      info.edges = count(o, "edges");
      info.weld = text(o, "weld");
      info.thickness = number(o, "thickness");
      if (!(info.thickness >= 0) || !std::isfinite(info.thickness)) {
        fail("header record: object \"" + info.name + "\" has a thickness that is not a finite number >= 0");
      }
      if (info.file_vertices < info.vertices) {
        fail("header record: object \"" + info.name + "\" has fewer file vertices than vertices");
      }
      if (!object_of_name.emplace(info.name, h.objects.size()).second) {
        fail("header record: two objects are named \"" + info.name + "\"");
      }
      h.objects.push_back(std::move(info));
    }
    h.frame_count = count(root, "frame_count");
    read_settings(dict(root, "settings"));
    read_rules(dict(root, "rules"));
    h.certified = flag(root, "certified");
  }

  void read_settings(const object& o) {
    ReportSettings& s = header.settings;
    s.mode = text(o, "mode");
    if (s.mode != "ccd" && s.mode != "dcd" && s.mode != "all") {
      fail("header record: unknown mode \"" + s.mode + "\" (ccd, dcd or all)");
    }
    s.backend = text(o, "backend");
    s.precision = text(o, "precision");
    s.thickness = number(o, "thickness");
    s.lambda = number(o, "lambda");
    // Reports written before the grid was recorded ran the uniform grid.
    s.grid = o.at_key("grid").error() == simdjson::SUCCESS ? std::string(text(o, "grid")) : "uniform";
    if (s.grid != "uniform" && s.grid != "adaptive") {
      fail("header record: unknown grid \"" + s.grid + "\" (uniform or adaptive)");
    }
    const std::size_t threads = count(o, "threads");
    if (threads > std::numeric_limits<unsigned>::max()) fail_key("threads", "is out of range");
    s.threads = static_cast<unsigned>(threads);
    s.frames = text(o, "frames");
    s.weld = text(o, "weld");
    s.events = text(o, "events");
    if (s.events != "all" && s.events != "regions" && s.events != "none") {
      fail("header record: unknown events setting \"" + s.events + "\" (all, regions or none)");
    }
    s.max_events = count(o, "max_events");
    s.manifest = text(o, "manifest");
  }

  void read_rules(const object& o) {
    ScanRules& r = header.rules;
    for (element item : list(o, "pairs")) {
      array pair;
      std::string_view a, b;
      if (item.get_array().get(pair) != simdjson::SUCCESS || pair.size() != 2 ||
          pair.at(0).get_string().get(a) != simdjson::SUCCESS || pair.at(1).get_string().get(b) != simdjson::SUCCESS) {
        fail_key("pairs", "holds something that is not a pair of names");
      }
      r.pairs.emplace_back(std::string(a), std::string(b));
    }
    for (element item : list(o, "no_self")) r.no_self.emplace_back(text_of(item, "no_self"));
    const std::size_t neighbourhood = count(o, "neighbourhood");
    if (neighbourhood > std::numeric_limits<unsigned>::max()) fail_key("neighbourhood", "is out of range");
    r.neighbourhood = static_cast<unsigned>(neighbourhood);
    for (element item : list(o, "thickness")) {
      array pair;
      std::string_view name;
      if (item.get_array().get(pair) != simdjson::SUCCESS || pair.size() != 2 ||
          pair.at(0).get_string().get(name) != simdjson::SUCCESS) {
        fail_key("thickness", "holds something that is not [name, thickness]");
      }
      r.thickness.emplace_back(std::string(name), number_of(pair.at(1).value_unsafe(), "thickness"));
    }
    for (element item : list(o, "allow")) {
      object rule;
      if (item.get_object().get(rule) != simdjson::SUCCESS) fail_key("allow", "holds something that is not an object");
      AllowRule allow;
      array names = list(rule, "objects");
      if (names.size() != 2) fail_key("objects", "is not a pair of object names");
      std::string_view a = text_of(names.at(0).value_unsafe(), "objects");
      std::string_view b = text_of(names.at(1).value_unsafe(), "objects");
      allow.object_a = a == "*" ? std::string() : std::string(a);
      allow.object_b = b == "*" ? std::string() : std::string(b);
      const std::string_view kind = text(rule, "kind");
      if (kind != "any") allow.kind = kind_of(kind);
      array frames = list(rule, "frames");
      if (frames.size() != 2) fail_key("frames", "is not [first, last]");
      allow.first_frame = count_of(frames.at(0).value_unsafe(), "frames");
      const element last = frames.at(1).value_unsafe();
      allow.last_frame = last.is_null() ? static_cast<std::size_t>(-1) : count_of(last, "frames");
      const element box = member(rule, "box");
      if (!box.is_null()) {
        const Bounds b = bounds_of(box, "box");
        allow.box = std::array<Vec3, 2>{b.lo, b.hi};
      }
      allow.note = text(rule, "note");
      r.allow.push_back(std::move(allow));
    }
    const object fail_at = dict(o, "fail");
    r.fail.events = count(fail_at, "events");
    r.fail.collisions = count(fail_at, "collisions");
    r.fail.intersections = count(fail_at, "intersections");
    r.fail.regions = count(fail_at, "regions");
    r.fail.tracks = count(fail_at, "tracks");
  }

  // The current frame ends: every region its events named must have come.
  void end_frame() {
    if (phase != Phase::kEvents && phase != Phase::kRegions && phase != Phase::kTracks) return;
    for (const auto& [id, at] : named_regions) {
      if (frame_regions.count(id) == 0) {
        line = at;
        fail("event record: region " + std::to_string(id) + " is not a region of frame " +
             std::to_string(frame.index));
      }
    }
    named_regions.clear();
    frame_regions.clear();
  }

  void read_frame(const object& o) {
    end_frame();
    FrameRecord f;
    f.position = count(o, "position");
    f.index = count(o, "index");
    if (f.position != frames_read) {
      fail("frame record: position " + std::to_string(f.position) + " where " + std::to_string(frames_read) +
           " comes next (frames are numbered from 0, in order)");
    }
    if (f.position >= header.frame_count) {
      fail("frame record: position " + std::to_string(f.position) + " is beyond the header's " +
           std::to_string(header.frame_count) + " frames");
    }
    if (!frame_indices.empty() && f.index <= frame_indices.back()) {
      fail("frame record: frame " + std::to_string(f.index) + " does not come after frame " +
           std::to_string(frame_indices.back()));
    }
    f.time = number(o, "time");
    f.collisions = count(o, "collisions");
    f.vf = count(o, "vf");
    f.ee = count(o, "ee");
    f.uncertain = count(o, "uncertain");
    f.intersections = count(o, "intersections");
    f.allowed = count(o, "allowed");
    f.regions = count(o, "regions");
    frame = f;
    frame_indices.push_back(f.index);
    ++frames_read;
    phase = Phase::kEvents;
  }

  void read_event(const object& o) {
    if (phase == Phase::kHeader) fail("an event record before the first frame record");
    if (phase != Phase::kEvents) fail("an event record after the frame's regions or tracks (events come first)");
    EventRecord e;
    e.kind = kind_of(text(o, "kind"));
    e.frame = count(o, "frame");
    if (e.frame != frame.index) {
      fail("event record: frame " + std::to_string(e.frame) + " under the record of frame " +
           std::to_string(frame.index));
    }
    if (e.kind == EventKind::kCollision) {
      const std::string_view type = text(o, "type");
      if (type == "vf") {
        e.type = ContactType::kVertexFace;
        e.a = element_ref(o, "a", RefKind::kVertex);
        e.b = element_ref(o, "b", RefKind::kFace);
      } else if (type == "ee") {
        e.type = ContactType::kEdgeEdge;
        e.a = element_ref(o, "a", RefKind::kEdge);
        e.b = element_ref(o, "b", RefKind::kEdge);
      } else {
        fail("event record: unknown collision type \"" + std::string(type) + "\" (vf or ee)");
      }
      e.toi = number(o, "toi");
      array interval = list(o, "toi_interval");
      if (interval.size() != 2) fail_key("toi_interval", "is not [lo, hi]");
      e.toi_lo = number_of(interval.at(0).value_unsafe(), "toi_interval");
      e.toi_hi = number_of(interval.at(1).value_unsafe(), "toi_interval");
      if (!(e.toi_lo <= e.toi_hi)) fail("event record: \"toi_interval\" is empty or not finite");
      const std::string_view certainty = text(o, "certainty");
      if (certainty == "proven") {
        e.certainty = Certainty::kProven;
      } else if (certainty == "uncertain") {
        e.certainty = Certainty::kUncertain;
      } else {
        fail("event record: unknown certainty \"" + std::string(certainty) + "\" (proven or uncertain)");
      }
    } else {
      e.type = ContactType::kTriangleTriangle;
      e.a = element_ref(o, "a", RefKind::kFace);
      e.b = element_ref(o, "b", RefKind::kFace);
    }
    e.position = vec3(o, "position");
    e.region = optional_count(o, "region");
    element allowed;
    if (o.at_key("allowed").get(allowed) == simdjson::SUCCESS && !allowed.is_null()) {
      e.allowed = count_of(allowed, "allowed");
      if (e.allowed >= header.rules.allow.size()) {
        fail("event record: allow rule " + std::to_string(e.allowed) + " is out of range (the header has " +
             std::to_string(header.rules.allow.size()) + ")");
      }
    }
    if (e.region != kNone) named_regions.emplace(e.region, line);
    event = e;
  }

  void read_region(const object& o) {
    if (phase == Phase::kHeader) fail("a region record before the first frame record");
    if (phase == Phase::kTracks) fail("a region record after the frame's tracks (regions come before them)");
    phase = Phase::kRegions;
    RegionRecord r;
    r.id = count(o, "id");
    r.kind = kind_of(text(o, "kind"));
    std::tie(r.object_a, r.object_b) = object_pair(o, "objects");
    check_objects_ordered(r.object_a, r.object_b);
    r.frame = count(o, "frame");
    if (r.frame != frame.index) {
      fail("region record: frame " + std::to_string(r.frame) + " under the record of frame " +
           std::to_string(frame.index));
    }
    r.track = count(o, "track");
    r.events = count(o, "events");
    r.face_count = count(o, "face_count");
    // Reports that list no events (settings.events "none") list no faces either.
    if (o.at_key("faces").error() == simdjson::SUCCESS) read_region_faces(o, r, r.face_count);
    r.bounds = bounds(o, "bounds");
    r.centroid = vec3(o, "centroid");
    if (r.kind == EventKind::kCollision) r.toi = number(o, "toi");
    // Written by snag-volume only.
    if (o.at_key("measures").error() == simdjson::SUCCESS) r.measures = read_region_measures(dict(o, "measures"));
    if (!frame_regions.insert(r.id).second) {
      fail("region record: region " + std::to_string(r.id) + " is listed twice in frame " + std::to_string(r.frame));
    }
    region = std::move(r);
  }

  RegionMeasures read_region_measures(const object& o) const {
    RegionMeasures m;
    m.measure = std::string(text(o, "measure"));
    m.reason = std::string(text(o, "reason"));
    m.voxel_size = number(o, "voxel_size");
    if (m.measure == "overlap_volume" || m.measure == "self_overlap_volume") {
      m.volume = number(o, "volume");
      m.volume_error = number(o, "volume_error");
    } else if (m.measure == "penetration") {
      m.depth = number(o, "depth");
      m.depth_error = number(o, "depth_error");
      m.area = number(o, "area");
      m.area_error = number(o, "area_error");
    } else if (m.measure == "curve_length") {
      m.curve_length = number(o, "curve_length");
      m.segments = count(o, "segments");
    } else {
      fail("region record: unknown measure \"" + m.measure +
           "\" (overlap_volume, self_overlap_volume, penetration or curve_length)");
    }
    return m;
  }

  void read_region_faces(const object& o, RegionRecord& r, std::size_t face_count) {
    array faces = list(o, "faces");
    const std::size_t sides = r.object_a == r.object_b ? 1 : 2;
    if (faces.size() != sides) {
      fail("region record: \"faces\" has " + std::to_string(faces.size()) + " entries, not one for each of its " +
           std::to_string(sides) + " objects");
    }
    bool seen[2] = {false, false};
    for (element item : faces) {
      object side;
      if (item.get_object().get(side) != simdjson::SUCCESS) fail_key("faces", "holds something that is not an object");
      const std::size_t o_index = object_index(text(side, "object"), "faces");
      const int s = o_index == r.object_a ? 0 : o_index == r.object_b ? 1 : -1;
      if (s < 0 || seen[s]) fail("region record: \"faces\" names an object that is not one of its pair, or twice");
      seen[s] = true;
      std::vector<std::size_t>& ids = s == 0 ? r.faces_a : r.faces_b;
      for (element id : list(side, "ids")) {
        ids.push_back(local_id(id, "ids", header.objects[o_index].triangles, "face", o_index));
        if (ids.size() > 1 && ids[ids.size() - 2] >= ids.back()) {
          fail("region record: face ids of \"" + header.objects[o_index].name + "\" are not increasing");
        }
      }
    }
    if (face_count != r.faces_a.size() + r.faces_b.size()) {
      fail("region record: \"face_count\" is " + std::to_string(face_count) + " but it lists " +
           std::to_string(r.faces_a.size() + r.faces_b.size()) + " faces");
    }
  }

  TrackRecord read_track_fields(const object& o) {
    TrackRecord t;
    t.id = count(o, "id");
    t.kind = kind_of(text(o, "kind"));
    std::tie(t.object_a, t.object_b) = object_pair(o, "objects");
    check_objects_ordered(t.object_a, t.object_b);
    t.first_frame = count(o, "first_frame");
    t.last_frame = count(o, "last_frame");
    t.worst_frame = count(o, "worst_frame");
    check_frame_read(t.first_frame, "first_frame");
    check_frame_read(t.last_frame, "last_frame");
    check_frame_read(t.worst_frame, "worst_frame");
    if (t.first_frame > t.last_frame || t.worst_frame < t.first_frame || t.worst_frame > t.last_frame) {
      fail("track record: frames are not first <= worst <= last");
    }
    t.frames = count(o, "frames");
    t.regions = count(o, "regions");
    t.events = count(o, "events");
    t.max_faces = count(o, "max_faces");
    t.bounds = bounds(o, "bounds");
    t.centroid = vec3(o, "centroid");
    if (t.kind == EventKind::kCollision) t.toi = number(o, "toi");
    t.merged_into = optional_count(o, "merged_into");
    return t;
  }

  void read_track(const object& o) {
    phase = Phase::kTracks;
    track = read_track_fields(o);
  }

  void read_trailer(const object& o) {
    end_frame();
    Trailer t;
    t.frames = count(o, "frames");
    const object s = dict(o, "summary");
    t.events = count(s, "events");
    t.collisions = count(s, "collisions");
    t.vf = count(s, "vf");
    t.ee = count(s, "ee");
    t.intersections = count(s, "intersections");
    t.uncertain = count(s, "uncertain");
    t.allowed = count(s, "allowed");
    t.listed = count(s, "listed");
    t.left_out = count(s, "left_out");
    t.not_checked = count(s, "not_checked");
    t.neighbourhood = count(s, "neighbourhood");
    t.regions = count(s, "regions");
    t.tracks = count(s, "tracks");
    for (element item : list(o, "pairs")) {
      object p;
      if (item.get_object().get(p) != simdjson::SUCCESS) fail_key("pairs", "holds something that is not an object");
      PairSummary pair;
      pair.kind = kind_of(text(p, "kind"));
      std::tie(pair.object_a, pair.object_b) = object_pair(p, "objects");
      pair.events = count(p, "events");
      pair.allowed = count(p, "allowed");
      pair.regions = count(p, "regions");
      pair.tracks = count(p, "tracks");
      pair.frames = count(p, "frames");
      pair.worst_frame = optional_count(p, "worst_frame");
      if (pair.worst_frame != kNone) check_frame_read(pair.worst_frame, "worst_frame");
      pair.worst_frame_events = count(p, "worst_frame_events");
      t.pairs.push_back(pair);
    }
    for (element n : list(o, "allow")) t.allow_counts.push_back(count_of(n, "allow"));
    if (t.allow_counts.size() != header.rules.allow.size()) {
      fail("trailer record: \"allow\" has " + std::to_string(t.allow_counts.size()) + " counts for " +
           std::to_string(header.rules.allow.size()) + " allow rules");
    }
    for (element item : list(o, "largest_tracks")) {
      object track_object;
      if (item.get_object().get(track_object) != simdjson::SUCCESS) {
        fail_key("largest_tracks", "holds something that is not an object");
      }
      t.largest_tracks.push_back(read_track_fields(track_object));
    }
    const object verdict = dict(o, "verdict");
    t.pass = flag(verdict, "pass");
    for (element item : list(verdict, "failed")) {
      object f;
      if (item.get_object().get(f) != simdjson::SUCCESS) fail_key("failed", "holds something that is not an object");
      t.failed.push_back({std::string(text(f, "what")), count(f, "count"), count(f, "threshold")});
    }
    t.stages_json = simdjson::minify(dict(o, "stages"));
    t.timing_json = simdjson::minify(dict(o, "timing"));
    trailer = std::move(t);
    phase = Phase::kDone;
  }

  Record next() {
    object root;
    std::string_view kind;
    if (phase == Phase::kDone) {
      if (read_line(root, kind, false)) fail("a \"" + std::string(kind) + "\" record after the trailer");
      return Record::kEnd;
    }
    if (!read_line(root, kind, false)) {
      ++line;
      fail("incomplete report (no trailer): the scan did not finish");
    }
    if (kind == "frame") {
      record = "frame";
      read_frame(root);
      return Record::kFrame;
    }
    if (kind == "event") {
      record = "event";
      read_event(root);
      return Record::kEvent;
    }
    if (kind == "region") {
      record = "region";
      read_region(root);
      return Record::kRegion;
    }
    if (kind == "track") {
      record = "track";
      read_track(root);
      return Record::kTrack;
    }
    if (kind == "trailer") {
      record = "trailer";
      read_trailer(root);
      return Record::kTrailer;
    }
    if (kind == "header") fail("a second header record");
    fail("unknown record \"" + std::string(kind) + "\"");
  }
};

ReportReader::ReportReader(const std::string& path) : state_(std::make_unique<State>(path)) {
  state_->read_header();
}

ReportReader::~ReportReader() = default;

const Header& ReportReader::header() const { return state_->header; }

ReportReader::Record ReportReader::next() { return state_->next(); }

const FrameRecord& ReportReader::frame() const { return state_->frame; }
const EventRecord& ReportReader::event() const { return state_->event; }
const RegionRecord& ReportReader::region() const { return state_->region; }
const TrackRecord& ReportReader::track() const { return state_->track; }
const Trailer& ReportReader::trailer() const { return state_->trailer; }

std::size_t ReportReader::line() const { return state_->line; }
const std::string& ReportReader::path() const { return state_->path; }

}  // namespace snag::report
