// libsnag_cupti_trace.so: a timeline of what a CUDA program ran on the
// device (kernels, copies, memsets: start, end, stream, name), recorded with
// CUPTI's activity API and written as CSV when the program ends. It needs no
// change to the program: the CUDA driver loads it at CUDA's start when
//   CUDA_INJECTION64_PATH=/path/to/libsnag_cupti_trace.so
//   SNAG_CUPTI_TRACE=/path/to/trace.csv
// are set, and calls InitializeInjection(). bench/gpu/trace_summary.py reads
// the CSV: the device's busy and idle time per step, the kernels' totals and
// the gaps between device work (see the README's benchmarks).
//
// With SNAG_CUPTI_API=1 the host's CUDA runtime calls are recorded too, as
// rows of kind api: which thread called what and when (a launch, a copy, a
// wait), to see where the threads that drive the device are when it idles.
//
// CSV columns: kind (kernel, memcpy, memset, api), start_ns, end_ns, stream
// (api: the calling thread's id), bytes (copies and memsets; api: the call's
// correlation id; 0 for kernels), name (kernels: the mangled name; copies:
// HtoD, DtoH, DtoD, ...; api: the runtime function). Times are CUPTI's, in
// nanoseconds.
#include <cupti.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <string>
#include <vector>

namespace {

struct Activity {
  const char* kind;
  std::uint64_t start, end;
  std::uint32_t stream;
  std::uint64_t bytes;
  std::string name;
};

constexpr std::size_t kBufferBytes = std::size_t{8} << 20;
constexpr std::size_t kAlignment = 8;

std::mutex activities_mutex;
std::vector<Activity> activities;
bool failed = false;

void report_cupti(CUptiResult result, const char* call) {
  if (result == CUPTI_SUCCESS) return;
  const char* message = nullptr;
  cuptiGetResultString(result, &message);
  std::fprintf(stderr, "snag-cupti-trace: %s failed: %s\n", call, message != nullptr ? message : "unknown error");
  failed = true;
}

const char* copy_kind(std::uint8_t kind) {
  switch (kind) {
    case CUPTI_ACTIVITY_MEMCPY_KIND_HTOD:
      return "HtoD";
    case CUPTI_ACTIVITY_MEMCPY_KIND_DTOH:
      return "DtoH";
    case CUPTI_ACTIVITY_MEMCPY_KIND_DTOD:
      return "DtoD";
    case CUPTI_ACTIVITY_MEMCPY_KIND_HTOH:
      return "HtoH";
    default:
      return "other";
  }
}

void CUPTIAPI buffer_requested(std::uint8_t** buffer, std::size_t* size, std::size_t* max_records) {
  *buffer = static_cast<std::uint8_t*>(std::aligned_alloc(kAlignment, kBufferBytes));
  *size = *buffer != nullptr ? kBufferBytes : 0;
  *max_records = 0;  // as many as fit
}

void CUPTIAPI buffer_completed(CUcontext, std::uint32_t, std::uint8_t* buffer, std::size_t, std::size_t valid) {
  std::vector<Activity> read;
  CUpti_Activity* record = nullptr;
  while (cuptiActivityGetNextRecord(buffer, valid, &record) == CUPTI_SUCCESS) {
    switch (record->kind) {
      case CUPTI_ACTIVITY_KIND_KERNEL:
      case CUPTI_ACTIVITY_KIND_CONCURRENT_KERNEL: {
        const auto* kernel = reinterpret_cast<const CUpti_ActivityKernel10*>(record);
        read.push_back(
            {"kernel", kernel->start, kernel->end, kernel->streamId, 0, kernel->name != nullptr ? kernel->name : "?"});
        break;
      }
      case CUPTI_ACTIVITY_KIND_MEMCPY: {
        const auto* copy = reinterpret_cast<const CUpti_ActivityMemcpy6*>(record);
        read.push_back({"memcpy", copy->start, copy->end, copy->streamId, copy->bytes, copy_kind(copy->copyKind)});
        break;
      }
      case CUPTI_ACTIVITY_KIND_MEMSET: {
        const auto* set = reinterpret_cast<const CUpti_ActivityMemset4*>(record);
        read.push_back({"memset", set->start, set->end, set->streamId, set->bytes, "memset"});
        break;
      }
      case CUPTI_ACTIVITY_KIND_RUNTIME: {
        const auto* call = reinterpret_cast<const CUpti_ActivityAPI*>(record);
        const char* name = nullptr;
        if (cuptiGetCallbackName(CUPTI_CB_DOMAIN_RUNTIME_API, call->cbid, &name) != CUPTI_SUCCESS) name = nullptr;
        read.push_back({"api", call->start, call->end, call->threadId, call->correlationId, name != nullptr ? name : "?"});
        break;
      }
      default:
        break;
    }
  }
  std::size_t dropped = 0;
  cuptiActivityGetNumDroppedRecords(nullptr, 0, &dropped);
  if (dropped > 0) std::fprintf(stderr, "snag-cupti-trace: %zu records dropped\n", dropped);
  std::free(buffer);
  std::lock_guard<std::mutex> lock(activities_mutex);
  for (Activity& activity : read) activities.push_back(std::move(activity));
}

// Flushes CUPTI's buffers and writes the CSV (at the program's exit).
void write_trace() {
  report_cupti(cuptiActivityFlushAll(CUPTI_ACTIVITY_FLAG_FLUSH_FORCED), "cuptiActivityFlushAll");
  const char* path = std::getenv("SNAG_CUPTI_TRACE");
  if (path == nullptr || *path == '\0') path = "cupti-trace.csv";
  std::FILE* out = std::fopen(path, "w");
  if (out == nullptr) {
    std::fprintf(stderr, "snag-cupti-trace: cannot write %s: %s\n", path, std::strerror(errno));
    return;
  }
  std::lock_guard<std::mutex> lock(activities_mutex);
  std::fprintf(out, "kind,start_ns,end_ns,stream,bytes,name\n");
  for (const Activity& a : activities)
    std::fprintf(out, "%s,%llu,%llu,%u,%llu,%s\n", a.kind, static_cast<unsigned long long>(a.start),
                 static_cast<unsigned long long>(a.end), a.stream, static_cast<unsigned long long>(a.bytes),
                 a.name.c_str());
  std::fclose(out);
  std::fprintf(stderr, "snag-cupti-trace: %zu activities in %s%s\n", activities.size(), path,
               failed ? " (CUPTI reported errors: the trace may be incomplete)" : "");
}

}  // namespace

// Called by the CUDA driver when CUDA_INJECTION64_PATH names this library.
extern "C" int InitializeInjection(void) {
  report_cupti(cuptiActivityRegisterCallbacks(buffer_requested, buffer_completed), "cuptiActivityRegisterCallbacks");
  for (CUpti_ActivityKind kind :
       {CUPTI_ACTIVITY_KIND_CONCURRENT_KERNEL, CUPTI_ACTIVITY_KIND_MEMCPY, CUPTI_ACTIVITY_KIND_MEMSET})
    report_cupti(cuptiActivityEnable(kind), "cuptiActivityEnable");
  const char* api = std::getenv("SNAG_CUPTI_API");
  if (api != nullptr && std::strcmp(api, "1") == 0)
    report_cupti(cuptiActivityEnable(CUPTI_ACTIVITY_KIND_RUNTIME), "cuptiActivityEnable");
  std::atexit(write_trace);
  return 1;
}
