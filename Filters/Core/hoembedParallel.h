/**
 * @file hoembedParallel.h
 * @brief The kernels' parallel loop and per-thread scratch, on VTK's SMP tools or on a
 * small portable pool (header only).
 *
 *  - hoembed::ParallelLoop(begin, end, f) / ParallelLoop(begin, end, grain, f): runs
 *    f(b, e) over subranges of [begin, end), like vtkSMPTools::For (same arguments).
 *  - hoembed::ThreadLocal<T>: per-thread objects, like vtkSMPThreadLocal<T>::Local().
 *
 * In the VTK build these are vtkSMPTools::For and vtkSMPThreadLocal, exactly as the
 * kernels called them before (so the VTK filters run the same code). When
 * HOEMBED_NO_VTK is defined (the pip wheel, Wrapping/Pip: the pip VTK wheels carry no
 * C++ headers), they run on std::thread: the range is cut into fixed chunks (`grain`
 * items, or 1/(8 x threads) of the range when no grain is given) handed out in order by
 * an atomic counter to the calling thread and HOEMBED_NUM_THREADS - 1 helpers
 * (default: std::thread::hardware_concurrency()). A loop started inside another runs
 * serially on its thread (as vtkSMPTools does with nested parallelism off).
 *
 * Every kernel loop writes per-item results (or reduces with min/sum over integers), so
 * its results do not depend on the chunks or on the number of threads; the embedding's
 * flood partition is fixed by the surface (hoembedEmbeddingFlood.h), not by the threads.
 *
 * @warning In the portable pool a ThreadLocal<T> has one slot per worker index: two
 * unrelated caller threads running loops over the same object at the same time would
 * share slot 0 (the VTK filters are not meant to be updated from two threads either).
 */
#ifndef hoembedParallel_h
#define hoembedParallel_h

#ifndef HOEMBED_NO_VTK
#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"
#else
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>
#endif

namespace hoembed
{
#ifndef HOEMBED_NO_VTK

template <typename I, typename F>
void ParallelLoop(I begin, I end, F&& f)
{
  vtkSMPTools::For(begin, end, f);
}

template <typename I, typename F>
void ParallelLoop(I begin, I end, I grain, F&& f)
{
  vtkSMPTools::For(begin, end, grain, f);
}

template <typename T>
class ThreadLocal
{
public:
  T& Local() { return this->Storage.Local(); }

private:
  vtkSMPThreadLocal<T> Storage;
};

#else

namespace parallel_detail
{
/// Threads a loop may use: HOEMBED_NUM_THREADS when set (>= 1), else the hardware's.
inline int NumberOfThreads()
{
  static const int n = [] {
    if (const char* s = std::getenv("HOEMBED_NUM_THREADS"))
    {
      const int v = std::atoi(s);
      if (v >= 1)
        return std::min(v, 256);
    }
    const unsigned hw = std::thread::hardware_concurrency();
    return hw ? static_cast<int>(std::min(hw, 256u)) : 1;
  }();
  return n;
}

/// The worker index of this thread within the running loop (0: the caller), and
/// whether it runs inside a loop (then a nested loop runs serially).
inline int& WorkerIndex()
{
  thread_local int index = 0;
  return index;
}
inline bool& InLoop()
{
  thread_local bool inLoop = false;
  return inLoop;
}
} // namespace parallel_detail

template <typename I, typename F>
void ParallelLoop(I begin, I end, I grain, F&& f)
{
  using namespace parallel_detail;
  if (end <= begin)
    return;
  const std::int64_t n = static_cast<std::int64_t>(end - begin);
  const int threads = NumberOfThreads();
  std::int64_t g = static_cast<std::int64_t>(grain);
  if (g <= 0)
    g = std::max<std::int64_t>(1, n / (8 * std::int64_t(threads)));
  const std::int64_t chunks = (n + g - 1) / g;
  if (threads == 1 || chunks == 1 || InLoop())
  {
    f(begin, end);
    return;
  }
  std::atomic<std::int64_t> next(0);
  std::exception_ptr error;
  std::mutex errorMutex;
  auto work = [&](int index) {
    const int savedIndex = WorkerIndex();
    const bool savedIn = InLoop();
    WorkerIndex() = index;
    InLoop() = true;
    try
    {
      for (std::int64_t c = next++; c < chunks; c = next++)
      {
        const I b = static_cast<I>(begin + c * g);
        const I e = static_cast<I>(std::min<std::int64_t>(n, (c + 1) * g) + begin);
        f(b, e);
      }
    }
    catch (...)
    {
      std::lock_guard<std::mutex> lock(errorMutex);
      if (!error)
        error = std::current_exception();
      next = chunks; // the others stop at their next chunk
    }
    WorkerIndex() = savedIndex;
    InLoop() = savedIn;
  };
  const int helpers = static_cast<int>(std::min<std::int64_t>(threads, chunks)) - 1;
  std::vector<std::thread> pool;
  pool.reserve(helpers);
  for (int t = 1; t <= helpers; ++t)
    pool.emplace_back(work, t);
  work(0);
  for (std::thread& t : pool)
    t.join();
  if (error)
    std::rethrow_exception(error);
}

template <typename I, typename F>
void ParallelLoop(I begin, I end, F&& f)
{
  ParallelLoop(begin, end, I(0), f);
}

template <typename T>
class ThreadLocal
{
public:
  ThreadLocal()
    : Slots(parallel_detail::NumberOfThreads())
  {
  }
  T& Local()
  {
    std::unique_ptr<T>& slot = this->Slots[parallel_detail::WorkerIndex()];
    if (!slot)
      slot.reset(new T());
    return *slot;
  }

private:
  std::vector<std::unique_ptr<T>> Slots;
};

#endif
} // namespace hoembed

#endif
