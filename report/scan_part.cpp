#include "report/scan_part.hpp"

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <future>
#include <type_traits>

#include "libcd/core/error.hpp"
#include "report/records.hpp"

namespace snag::report {

namespace {

constexpr char kMagic[] = "snag-part-2\n";
constexpr std::size_t kMagicSize = sizeof(kMagic) - 1;
// Bounds what a damaged part can make the reader allocate.
constexpr std::size_t kMaxJsonBytes = std::size_t{1} << 24;

static_assert(std::is_trivially_copyable_v<Event>, "events are stored as bytes");
static_assert(std::is_trivially_copyable_v<FrameRecord>, "frame records are stored as bytes");
static_assert(std::is_trivially_copyable_v<PairCounts>, "pair counts are stored as bytes");
static_assert(std::is_trivially_copyable_v<Bounds>, "bounds are stored as bytes");

InputError part_error(const std::string& path, std::size_t byte, const std::string& message) {
  InputLocation where;
  where.file = path;
  where.byte = byte;
  return InputError(where, message);
}

// A part read from its start, possibly while its writer still writes it:
// at the end of what is there, `wait` (when given) says whether more may come.
class PartFile {
 public:
  PartFile(const std::string& path, PartWait wait) : path_(path), wait_(std::move(wait)) {
    bool finished = false;
    while (!(file_ = std::fopen(path.c_str(), "rb"))) {
      // Not there yet: its writer has not started; missing after it finished: gone.
      if (errno != ENOENT || !wait_ || finished) {
        throw part_error(path, kNone, std::string("cannot open the part: ") + std::strerror(errno));
      }
      finished = wait_();
    }
  }
  ~PartFile() { std::fclose(file_); }
  PartFile(const PartFile&) = delete;
  PartFile& operator=(const PartFile&) = delete;

  void read(void* data, std::size_t bytes) {
    if (bytes == 0) return;  // an empty vector's data() may be null, which fread must not get
    auto* to = static_cast<char*>(data);
    std::size_t got = std::fread(to, 1, bytes, file_);
    // At the end of what was written: wait for the writer, then read once
    // more after it has finished before calling the part truncated.
    bool finished = !wait_;
    while (got < bytes) {
      if (std::ferror(file_) || finished) throw part_error(path_, offset_ + got, "the part is truncated");
      finished = wait_();
      std::clearerr(file_);
      got += std::fread(to + got, 1, bytes - got, file_);
    }
    offset_ += bytes;
  }
  template <typename T>
  T read() {
    T value;
    read(&value, sizeof value);
    return value;
  }
  /// A count, checked against `most`, then that many values.
  template <typename T>
  void read_vector(std::vector<T>& values, std::size_t most) {
    const auto count = read<std::size_t>();
    if (count > most) throw part_error(path_, offset_, "the part does not match the cache");
    values.resize(count);
    read(values.data(), count * sizeof(T));
  }
  std::string read_text() {
    const auto size = read<std::size_t>();
    if (size > kMaxJsonBytes) throw part_error(path_, offset_, "the part's totals are too long");
    std::string text(size, '\0');
    read(text.data(), size);
    return text;
  }
  std::size_t offset() const { return offset_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  PartWait wait_;
  std::FILE* file_ = nullptr;
  std::size_t offset_ = 0;
};

}  // namespace

PartWriter::PartWriter(const std::string& path, const Scene& scene, const RuleSet& rules,
                       const ReportSettings& settings, PartRedecide redecide)
    : path_(path),
      file_(std::fopen(path.c_str(), "wb")),
      settings_(settings),
      redecide_(std::move(redecide)),
      digester_(scene, rules) {
  if (!file_) throw part_error(path, kNone, std::string("cannot write the part: ") + std::strerror(errno));
  write(kMagic, kMagicSize);
}

PartWriter::~PartWriter() {
  if (file_) std::fclose(file_);
}

void PartWriter::write(const void* data, std::size_t bytes) {
  if (bytes == 0) return;  // an empty vector's data() may be null, which fwrite must not get
  if (std::fwrite(data, 1, bytes, file_) != bytes) {
    throw part_error(path_, kNone, std::string("cannot write the part: ") + std::strerror(errno));
  }
}

template <typename T>
void PartWriter::write_vector(const std::vector<T>& values) {
  const std::size_t count = values.size();
  write(&count, sizeof count);
  write(values.data(), count * sizeof(T));
}

void PartWriter::frame(ScannedFrame& frame) {
  if (redecide_ && frame.x_next) redecide_(*frame.x, *frame.x_next, *frame.events);
  FrameDigest& d = digest_;
  digester_.digest(frame, d);
  // No more events than the report could list of this range were it the
  // run's first: the join lists a prefix of what this range would list.
  d.listable = events_to_list(settings_, stored_, d.kept);
  stored_ += d.listable;
  write("F", 1);
  write(&d.record, sizeof d.record);
  write(&d.not_checked, sizeof d.not_checked);
  write(&d.neighbourhood, sizeof d.neighbourhood);
  write_vector(d.allow_counts);
  write_vector(d.pairs);
  const std::size_t regions = d.regions.size();
  write(&regions, sizeof regions);
  for (const RegionRecord& r : d.regions) {
    const auto kind = static_cast<int>(r.kind);
    write(&kind, sizeof kind);
    for (const std::size_t* field : {&r.object_a, &r.object_b, &r.frame, &r.face_count, &r.events}) {
      write(field, sizeof *field);
    }
    write(&r.bounds, sizeof r.bounds);
    write(&r.centroid, sizeof r.centroid);
    write(&r.toi, sizeof r.toi);
    write_vector(r.faces_a);
    write_vector(r.faces_b);
  }
  write(&d.kept, sizeof d.kept);
  write(&d.listable, sizeof d.listable);
  write(d.events, d.listable * sizeof(Event));
  write(d.allowed_by.data(), d.listable * sizeof(std::size_t));
  write(d.region_of.data(), d.listable * sizeof(std::size_t));
  // Rank 0 merges the part while it is written (replay_part's wait_for_writer).
  if (std::fflush(file_) != 0) {
    throw part_error(path_, kNone, std::string("cannot write the part: ") + std::strerror(errno));
  }
}

void PartWriter::finish(const PartTotals& totals) {
  write("E", 1);
  write(&totals.frames, sizeof totals.frames);
  for (const std::string* text : {&totals.stages_json, &totals.timing_json}) {
    const std::size_t size = text->size();
    write(&size, sizeof size);
    write(text->data(), size);
  }
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!closed) throw part_error(path_, kNone, std::string("cannot write the part: ") + std::strerror(errno));
}

namespace {

// Reads one frame's digest (after its tag) into `d`, its events into
// `events`, checking every count against the scene and the rules so that a
// damaged part cannot make the reader allocate without bound or the join
// index out of range.
void read_digest(PartFile& part, const FrameSource& source, const RuleSet& rules, FrameDigest& d,
                 std::vector<Event>& events) {
  const Scene& scene = source.scene();
  const std::size_t objects = scene.objects().size();
  auto mismatch = [&] { return part_error(part.path(), part.offset(), "the part does not match the cache"); };
  d.record = part.read<FrameRecord>();
  d.not_checked = part.read<std::size_t>();
  d.neighbourhood = part.read<std::size_t>();
  const std::size_t allow_rules = rules.rules().allow.size();
  part.read_vector(d.allow_counts, allow_rules);
  if (d.record.position >= source.frame_count() || d.allow_counts.size() != allow_rules) throw mismatch();
  part.read_vector(d.pairs, 2 * objects * objects);
  for (const PairCounts& p : d.pairs) {
    if (p.object_a > p.object_b || p.object_b >= objects) throw mismatch();
    if (p.kind != EventKind::kCollision && p.kind != EventKind::kIntersection) throw mismatch();
  }
  const std::size_t checked = d.record.collisions + d.record.intersections;
  const auto regions = part.read<std::size_t>();
  if (regions > checked || regions != d.record.regions) throw mismatch();
  d.regions.resize(regions);
  for (RegionRecord& r : d.regions) {
    const auto kind = part.read<int>();
    if (kind != static_cast<int>(EventKind::kCollision) && kind != static_cast<int>(EventKind::kIntersection)) {
      throw mismatch();
    }
    r.kind = static_cast<EventKind>(kind);
    for (std::size_t* field : {&r.object_a, &r.object_b, &r.frame, &r.face_count, &r.events}) {
      *field = part.read<std::size_t>();
    }
    if (r.object_a > r.object_b || r.object_b >= objects) throw mismatch();
    r.bounds = part.read<Bounds>();
    r.centroid = part.read<Vec3>();
    r.toi = part.read<double>();
    part.read_vector(r.faces_a, scene.objects()[r.object_a].triangles.size());
    part.read_vector(r.faces_b, scene.objects()[r.object_b].triangles.size());
  }
  d.kept = part.read<std::size_t>();
  d.listable = part.read<std::size_t>();
  if (d.kept != checked + d.record.allowed || d.listable > d.kept) throw mismatch();
  events.resize(d.listable);
  d.allowed_by.resize(d.listable);
  d.region_of.resize(d.listable);
  part.read(events.data(), d.listable * sizeof(Event));
  part.read(d.allowed_by.data(), d.listable * sizeof(std::size_t));
  part.read(d.region_of.data(), d.listable * sizeof(std::size_t));
  for (std::size_t i = 0; i < d.listable; ++i) {
    if ((d.allowed_by[i] != kNone && d.allowed_by[i] >= allow_rules) ||
        (d.region_of[i] != kNone && d.region_of[i] >= regions)) {
      throw mismatch();
    }
  }
  d.events = events.data();
}

}  // namespace

PartTotals replay_part(const std::string& path, const FrameSource& source, ReportSink& sink,
                       const std::function<void(std::size_t)>& progress, const PartWait& wait_for_writer) {
  PartFile part(path, wait_for_writer);
  char magic[kMagicSize];
  part.read(magic, kMagicSize);
  if (std::memcmp(magic, kMagic, kMagicSize) != 0) throw part_error(path, 0, "not a snag scan part");
  // Frame i is read into buffers i % 2 while the sink joins frame i - 1 on
  // a thread of its own; the join of frame i - 2, which used them, is done by then.
  FrameDigest digests[2];
  std::vector<Event> events[2];
  std::future<void> joining;
  std::atomic<double> join_seconds{0};  // written by one join at a time
  auto wait_for_sink = [&] {
    if (joining.valid()) joining.get();  // rethrows what the sink threw
  };
  try {
    for (std::size_t i = 0;; ++i) {
      const auto tag = part.read<char>();
      if (tag == 'E') break;
      if (tag != 'F') throw part_error(path, part.offset() - 1, "unknown record in the part");
      FrameDigest& digest = digests[i % 2];
      read_digest(part, source, sink.rules(), digest, events[i % 2]);
      wait_for_sink();
      joining = std::async(std::launch::async, [&sink, &digest, &join_seconds] {
        const auto start = std::chrono::steady_clock::now();
        sink.join(digest);
        join_seconds = join_seconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      });
      if (progress) progress(digest.record.position);
    }
    wait_for_sink();
  } catch (...) {
    // Nothing may still use the buffers when they go.
    if (joining.valid()) joining.wait();
    throw;
  }
  PartTotals totals;
  totals.frames = part.read<std::size_t>();
  totals.stages_json = part.read_text();
  totals.timing_json = part.read_text();
  totals.join_seconds = join_seconds;
  return totals;
}

}  // namespace snag::report
