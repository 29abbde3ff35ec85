// DeviceBuffer / PinnedBuffer ownership and DeviceMemoryTracker accounting;
// CudaEvent's pool of the thread's events.
// The tracker is process-wide: every check works on differences from the
// bytes held when the test starts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <thread>
#include <utility>
#include <vector>

#include "gpu_test.hpp"
#include "libcd/cuda/cuda_event.cuh"
#include "libcd/cuda/device_buffer.cuh"
#include "libcd/cuda/device_memory_tracker.hpp"

namespace snag {
namespace {

TEST(DeviceMemoryTracker, PeakIsTheLargestHeldSinceReset) {
  DeviceMemoryTracker& tracker = DeviceMemoryTracker::instance();
  const std::size_t base = tracker.current_bytes();
  tracker.reset_peak();
  tracker.on_allocate(100);
  tracker.on_allocate(50);
  tracker.on_free(100);
  tracker.on_allocate(70);
  EXPECT_EQ(tracker.current_bytes(), base + 120);
  EXPECT_EQ(tracker.peak_bytes(), base + 150);
  tracker.reset_peak();
  EXPECT_EQ(tracker.peak_bytes(), base + 120);
  tracker.on_free(50);
  tracker.on_free(70);
  EXPECT_EQ(tracker.current_bytes(), base);
  EXPECT_EQ(tracker.peak_bytes(), base + 120);
}

using DeviceBufferTest = test::GpuTest;

TEST_F(DeviceBufferTest, PeakCountsEveryLiveBuffer) {
  DeviceMemoryTracker& tracker = DeviceMemoryTracker::instance();
  const std::size_t base = tracker.current_bytes();
  tracker.reset_peak();
  {
    DeviceBuffer<double> a(1000);
    DeviceBuffer<std::int32_t> b(500);
    EXPECT_EQ(tracker.current_bytes(), base + 8000 + 2000);
    a.release();
    EXPECT_EQ(tracker.current_bytes(), base + 2000);
    EXPECT_EQ(tracker.peak_bytes(), base + 10000);

    b.resize(100);  // shrinking keeps the allocation
    EXPECT_EQ(b.size(), 100u);
    EXPECT_EQ(b.capacity(), 500u);
    EXPECT_EQ(tracker.current_bytes(), base + 2000);
    b.resize(4000);  // growing reallocates without copying: the old block is freed first
    EXPECT_EQ(b.capacity(), 4000u);
    EXPECT_EQ(tracker.current_bytes(), base + 16000);
    EXPECT_EQ(tracker.peak_bytes(), base + 16000);

    DeviceBuffer<std::int32_t> moved(std::move(b));
    EXPECT_TRUE(b.empty());
    EXPECT_EQ(b.data(), nullptr);
    EXPECT_EQ(moved.size(), 4000u);
    EXPECT_EQ(tracker.current_bytes(), base + 16000);  // a move neither allocates nor frees
  }
  SNAG_CUDA_CHECK(cudaDeviceSynchronize());
  EXPECT_EQ(tracker.current_bytes(), base);
  EXPECT_EQ(tracker.peak_bytes(), base + 16000);
}

TEST_F(DeviceBufferTest, UploadThenDownloadGivesTheSameValues) {
  std::vector<double> values(12345);
  std::iota(values.begin(), values.end(), -17.25);
  DeviceBuffer<double> buffer;
  buffer.upload(values);
  EXPECT_EQ(buffer.size(), values.size());
  EXPECT_EQ(buffer.download(), values);
}

TEST_F(DeviceBufferTest, FillZeroClearsEveryElement) {
  DeviceBuffer<std::uint64_t> buffer;
  buffer.upload(std::vector<std::uint64_t>(777, ~std::uint64_t{0}));
  buffer.fill_zero();
  EXPECT_EQ(buffer.download(), std::vector<std::uint64_t>(777, 0));
}

TEST_F(DeviceBufferTest, UploadsFromPinnedMemoryOnAStream) {
  cudaStream_t stream = nullptr;
  SNAG_CUDA_CHECK(cudaStreamCreateWithFlags(&stream, cudaStreamNonBlocking));
  {
    PinnedBuffer<float> staging(4096);
    for (std::size_t i = 0; i < staging.size(); ++i) staging[i] = 0.5f * static_cast<float>(i);
    DeviceBuffer<float> buffer(0, stream);
    buffer.upload(staging.data(), staging.size());
    PinnedBuffer<float> back(4096);
    buffer.download(back.data(), back.size());
    SNAG_CUDA_CHECK(cudaStreamSynchronize(stream));
    for (std::size_t i = 0; i < back.size(); ++i) ASSERT_EQ(back[i], staging[i]) << "element " << i;
  }
  SNAG_CUDA_CHECK(cudaStreamDestroy(stream));
}

TEST_F(DeviceBufferTest, ReadBackGivesEveryValueAtItsPlace) {
  cudaStream_t stream = nullptr;
  SNAG_CUDA_CHECK(cudaStreamCreateWithFlags(&stream, cudaStreamNonBlocking));
  {
    std::vector<std::uint64_t> totals(9);
    std::iota(totals.begin(), totals.end(), std::uint64_t{1} << 40);
    std::vector<unsigned> histogram(1000);
    std::iota(histogram.begin(), histogram.end(), 3u);
    std::vector<char> bytes = {'a', 'b', 'c'};  // an odd size: the next copy lands aligned
    DeviceBuffer<std::uint64_t> d_totals(0, stream);
    DeviceBuffer<unsigned> d_histogram(0, stream);
    DeviceBuffer<char> d_bytes(0, stream);
    d_totals.upload(totals);
    d_histogram.upload(histogram);
    d_bytes.upload(bytes);
    std::uint64_t last = 0, first_two[2] = {0, 0};
    std::vector<unsigned> histogram_back(histogram.size());
    char bytes_back[3] = {};
    for (int round = 0; round < 2; ++round) {  // the staging memory is used again
      ReadBack(stream)
          .add(&last, d_totals.data() + 8)
          .add(bytes_back, d_bytes.data(), 3)
          .add(histogram_back.data(), d_histogram.data(), histogram.size())
          .add(first_two, d_totals.data(), 2)
          .wait();
      EXPECT_EQ(last, totals[8]);
      EXPECT_EQ(first_two[0], totals[0]);
      EXPECT_EQ(first_two[1], totals[1]);
      EXPECT_EQ(std::vector<char>(bytes_back, bytes_back + 3), bytes);
      EXPECT_EQ(histogram_back, histogram);
      d_totals.fill_zero();
      d_histogram.fill_zero();
      d_bytes.fill_zero();
      std::fill(totals.begin(), totals.end(), 0);
      std::fill(histogram.begin(), histogram.end(), 0u);
      std::fill(bytes.begin(), bytes.end(), 0);
    }
  }
  SNAG_CUDA_CHECK(cudaStreamDestroy(stream));
}

// start() takes the values where it stands in the stream: work enqueued
// after it (the buffer zeroed, a large copy over it) does not change them.
TEST_F(DeviceBufferTest, StartedReadBackGivesTheValuesBeforeLaterWork) {
  cudaStream_t stream = nullptr;
  SNAG_CUDA_CHECK(cudaStreamCreateWithFlags(&stream, cudaStreamNonBlocking));
  {
    std::vector<std::uint64_t> values(1 << 20);
    std::iota(values.begin(), values.end(), std::uint64_t{7});
    DeviceBuffer<std::uint64_t> d_values(0, stream), d_other(0, stream);
    d_values.upload(values);
    d_other.upload(std::vector<std::uint64_t>(values.size(), 5));
    for (int round = 0; round < 3; ++round) {
      std::uint64_t first = 0, last_two[2] = {0, 0};
      ReadBack read(stream);
      read.add(&first, d_values.data()).add(last_two, d_values.data() + values.size() - 2, 2).start();
      SNAG_CUDA_CHECK(cudaMemcpyAsync(d_values.data(), d_other.data(), values.size() * sizeof(std::uint64_t),
                                      cudaMemcpyDeviceToDevice, stream));
      d_values.fill_zero();
      read.wait();
      EXPECT_EQ(first, values.front());
      EXPECT_EQ(last_two[0], values[values.size() - 2]);
      EXPECT_EQ(last_two[1], values.back());
      d_values.upload(values);
    }
    // The work enqueued before start() is in what it reads.
    d_values.fill_zero();
    std::uint64_t zeroed = 1;
    ReadBack(stream).add(&zeroed, d_values.data()).start().wait();
    EXPECT_EQ(zeroed, 0u);
  }
  SNAG_CUDA_CHECK(cudaStreamDestroy(stream));
}

TEST_F(DeviceBufferTest, EmptyBufferHoldsNoMemory) {
  DeviceMemoryTracker& tracker = DeviceMemoryTracker::instance();
  const std::size_t base = tracker.current_bytes();
  DeviceBuffer<double> buffer(0);
  buffer.upload(std::vector<double>{});
  EXPECT_EQ(buffer.data(), nullptr);
  EXPECT_TRUE(buffer.download().empty());
  EXPECT_EQ(tracker.current_bytes(), base);
}

using CudaEventTest = test::GpuTest;

TEST_F(CudaEventTest, TakesBackTheThreadsIdleEventsAndTimesWithThem) {
  cudaEvent_t first = nullptr, second = nullptr;
  {
    CudaEvent a, b;
    first = a.get();
    second = b.get();
    EXPECT_NE(first, second);
  }
  // Both went back to this thread's pool: the next two are the same events.
  CudaEvent c, d;
  EXPECT_TRUE((c.get() == first && d.get() == second) || (c.get() == second && d.get() == first));
  // A moved-from event gives nothing back; the moved one times as any.
  CudaEvent start(std::move(c)), end(std::move(d));
  DeviceBuffer<std::int32_t> buffer(1 << 20);
  start.record(nullptr);
  buffer.fill_zero();
  end.record(nullptr);
  SNAG_CUDA_CHECK(cudaEventSynchronize(end.get()));
  EXPECT_GE(CudaEvent::elapsed_ms(start, end), 0.0f);
}

TEST_F(CudaEventTest, EventsGivenBackOnAnotherThreadServeThatThread) {
  std::vector<CudaEvent> made(3);
  std::vector<cudaEvent_t> handles;
  for (const CudaEvent& event : made) handles.push_back(event.get());
  std::vector<cudaEvent_t> taken;
  std::thread([&] {
    made.clear();  // given back to this thread's pool
    for (int k = 0; k < 3; ++k) {
      CudaEvent event;
      taken.push_back(event.get());
    }
  }).join();
  // The thread took the events it had been given, not new ones.
  ASSERT_EQ(taken.size(), 3u);
  for (cudaEvent_t event : taken) EXPECT_NE(std::find(handles.begin(), handles.end(), event), handles.end());
}

}  // namespace
}  // namespace snag
