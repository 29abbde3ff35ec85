#include "report/scan_part.hpp"

#include <cerrno>
#include <cstring>
#include <future>
#include <type_traits>

#include "libcd/core/error.hpp"
#include "report/records.hpp"

namespace snag::report {

namespace {

constexpr char kMagic[] = "snag-part-1\n";
constexpr std::size_t kMagicSize = sizeof(kMagic) - 1;
// Bounds what a damaged part can make the reader allocate.
constexpr std::size_t kMaxJsonBytes = std::size_t{1} << 24;

static_assert(std::is_trivially_copyable_v<Event>, "events are stored as bytes");
static_assert(std::is_trivially_copyable_v<FrameSummary>, "frame summaries are stored as bytes");

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

PartWriter::PartWriter(const std::string& path, PartRedecide redecide)
    : path_(path), file_(std::fopen(path.c_str(), "wb")), redecide_(std::move(redecide)) {
  if (!file_) throw part_error(path, kNone, std::string("cannot write the part: ") + std::strerror(errno));
  write(kMagic, kMagicSize);
}

PartWriter::~PartWriter() {
  if (file_) std::fclose(file_);
}

void PartWriter::write(const void* data, std::size_t bytes) {
  if (std::fwrite(data, 1, bytes, file_) != bytes) {
    throw part_error(path_, kNone, std::string("cannot write the part: ") + std::strerror(errno));
  }
}

void PartWriter::frame(ScannedFrame& frame) {
  std::vector<Event>& events = *frame.events;
  if (redecide_ && frame.x_next) redecide_(*frame.x, *frame.x_next, events);
  const std::size_t count = events.size();
  write("F", 1);
  write(&frame.position, sizeof frame.position);
  write(&frame.time, sizeof frame.time);
  write(&frame.summary, sizeof frame.summary);
  write(&count, sizeof count);
  write(events.data(), count * sizeof(Event));
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

PartTotals replay_part(const std::string& path, const FrameSource& source, ScanSink& sink,
                       const std::function<void(std::size_t)>& progress, const PartWait& wait_for_writer) {
  PartFile part(path, wait_for_writer);
  char magic[kMagicSize];
  part.read(magic, kMagicSize);
  if (std::memcmp(magic, kMagic, kMagicSize) != 0) throw part_error(path, 0, "not a snag scan part");
  // Frame i is read into buffers i % 2 while the sink takes frame i - 1 on
  // a thread of its own (reading the cache's positions costs about what the
  // sink does); the sink of frame i - 2, which used them, is done by then.
  ScannedFrame frames[2];
  std::vector<Event> events[2];
  std::vector<Vec3> x[2];
  std::future<void> sinking;
  auto wait_for_sink = [&] {
    if (sinking.valid()) sinking.get();  // rethrows what the sink threw
  };
  try {
    for (std::size_t i = 0;; ++i) {
      const auto tag = part.read<char>();
      if (tag == 'E') break;
      if (tag != 'F') throw part_error(path, part.offset() - 1, "unknown record in the part");
      ScannedFrame& frame = frames[i % 2];
      frame = ScannedFrame{};
      frame.position = part.read<std::size_t>();
      frame.time = part.read<double>();
      frame.summary = part.read<FrameSummary>();
      const auto count = part.read<std::size_t>();
      if (frame.position >= source.frame_count() ||
          count > frame.summary.collisions + frame.summary.intersections) {
        throw part_error(path, part.offset(), "the part does not match the cache");
      }
      events[i % 2].resize(count);
      part.read(events[i % 2].data(), count * sizeof(Event));
      // Only events make the sink look at positions (regions' bounds).
      x[i % 2].clear();
      if (count > 0) source.read_frame(frame.position, x[i % 2]);
      frame.events = &events[i % 2];
      frame.x = &x[i % 2];
      wait_for_sink();
      sinking = std::async(std::launch::async, [&sink, &frame] { sink.frame(frame); });
      if (progress) progress(frame.position);
    }
    wait_for_sink();
  } catch (...) {
    // Nothing may still use the buffers when they go.
    if (sinking.valid()) sinking.wait();
    throw;
  }
  PartTotals totals;
  totals.frames = part.read<std::size_t>();
  totals.stages_json = part.read_text();
  totals.timing_json = part.read_text();
  return totals;
}

}  // namespace snag::report
