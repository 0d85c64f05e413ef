// hoembedParallel.h as the pip wheel compiles it (HOEMBED_NO_VTK: the kept std::thread
// pool instead of vtkSMPTools), against plain serial loops: every item visited exactly
// once for any range, grain and thread count; nested loops run serially; an exception in
// a chunk reaches the caller and leaves the pool usable; ThreadLocal gives each running
// thread its own slot; a loop started from two threads at once is still complete.
#define HOEMBED_NO_VTK 1
#include "hoembedParallel.h"

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <thread>
#include <vector>

namespace
{
int failures = 0;
void Expect(bool ok, const char* what)
{
  if (!ok)
  {
    std::printf("FAILED: %s\n", what);
    ++failures;
  }
}

// every item of [b, e) once, through ParallelLoop with `grain`
bool Covers(std::int64_t b, std::int64_t e, std::int64_t grain)
{
  std::vector<std::atomic<int>> hits(static_cast<std::size_t>(e > b ? e - b : 0) + 1);
  for (auto& h : hits)
    h = 0;
  hoembed::ParallelLoop(b, e, grain, [&](std::int64_t cb, std::int64_t ce) {
    if (cb < b || ce > e || cb >= ce)
      hits.back() += 1000; // a chunk outside the range or empty
    for (std::int64_t i = cb; i < ce; ++i)
      ++hits[static_cast<std::size_t>(i - b)];
  });
  for (std::size_t i = 0; i + 1 < hits.size(); ++i)
    if (hits[i] != 1)
      return false;
  return hits.back() == 0;
}
} // namespace

int main()
{
  // HOEMBED_NUM_THREADS is read once: 3 threads even on a 1- or 2-core machine
  setenv("HOEMBED_NUM_THREADS", "3", 1);
  Expect(hoembed::ParallelThreadCount() == 3, "HOEMBED_NUM_THREADS sets the thread count");

  const std::int64_t ranges[][2] = { { 0, 0 }, { 0, 1 }, { 5, 6 }, { 0, 7 }, { -3, 1000 },
    { 0, 100003 }, { 17, 4096 } };
  const std::int64_t grains[] = { 0, 1, 2, 7, 64, 1 << 20 };
  for (const auto& r : ranges)
    for (std::int64_t g : grains)
      Expect(Covers(r[0], r[1], g), "every item once");

  // a sum over per-item results equals the serial one (integer: order-free)
  std::vector<std::int64_t> values(200000);
  for (std::size_t i = 0; i < values.size(); ++i)
    values[i] = static_cast<std::int64_t>((i * 2654435761u) % 1000003);
  std::vector<std::int64_t> out(values.size(), -1);
  hoembed::ParallelLoop(
    std::int64_t(0), std::int64_t(values.size()), [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t i = b; i < e; ++i)
        out[i] = values[i] * 3 + 1;
    });
  bool same = true;
  for (std::size_t i = 0; i < values.size(); ++i)
    same = same && out[i] == values[i] * 3 + 1;
  Expect(same, "per-item results as the serial loop");

  // nested: the inner loop runs on the thread of its outer chunk, completely
  std::atomic<std::int64_t> inner(0);
  std::atomic<int> innerThreadsDiffer(0);
  hoembed::ParallelLoop(0, 8, 1, [&](int b, int e) {
    for (int i = b; i < e; ++i)
    {
      const std::thread::id outer = std::this_thread::get_id();
      hoembed::ParallelLoop(
        std::int64_t(0), std::int64_t(1000), [&](std::int64_t ib, std::int64_t ie) {
          if (std::this_thread::get_id() != outer)
            ++innerThreadsDiffer;
          inner += ie - ib;
        });
    }
  });
  Expect(inner == 8000, "nested loops complete");
  Expect(innerThreadsDiffer == 0, "nested loops run serially on their thread");

  // an exception in one chunk reaches the caller; the pool serves the next loop
  bool caught = false;
  try
  {
    hoembed::ParallelLoop(0, 1000, 10, [&](int b, int) {
      if (b == 500)
        throw std::runtime_error("chunk 50");
    });
  }
  catch (const std::runtime_error&)
  {
    caught = true;
  }
  Expect(caught, "an exception in a chunk is rethrown in the caller");
  Expect(Covers(0, 50000, 0), "the pool works after an exception");

  // ThreadLocal: one object per running thread, never shared at the same time
  struct Slot
  {
    std::atomic<int> InUse{ 0 };
    std::int64_t Items = 0;
  };
  hoembed::ThreadLocal<Slot> slots;
  std::atomic<int> shared(0);
  std::atomic<std::int64_t> total(0);
  hoembed::ParallelLoop(
    std::int64_t(0), std::int64_t(20000), std::int64_t(5), [&](std::int64_t b, std::int64_t e) {
      Slot& s = slots.Local();
      if (s.InUse++ != 0)
        ++shared;
      s.Items += e - b;
      total += e - b;
      --s.InUse;
    });
  Expect(shared == 0, "ThreadLocal slots are per thread");
  Expect(total == 20000, "ThreadLocal loop complete");

  // two callers at once: one gets the pool, the other runs its loop alone; both complete
  std::atomic<bool> ok1(false), ok2(false);
  std::thread t1([&] { ok1 = Covers(0, 300000, 0); });
  std::thread t2([&] { ok2 = Covers(0, 300000, 3); });
  t1.join();
  t2.join();
  Expect(ok1 && ok2, "loops from two threads at once are complete");

  std::printf("%s\n", failures ? "TestParallelPool: FAILED" : "TestParallelPool: passed");
  return failures ? 1 : 0;
}
