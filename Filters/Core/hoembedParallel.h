/**
 * @file hoembedParallel.h
 * @brief The kernels' parallel loop and per-thread scratch, on VTK's SMP tools or on a
 * small portable pool (header only).
 *
 *  - hoembed::ParallelLoop(begin, end, f) / ParallelLoop(begin, end, grain, f): runs
 *    f(b, e) over subranges of [begin, end), like vtkSMPTools::For (same arguments).
 *  - hoembed::ThreadLocal<T>: per-thread objects, like vtkSMPThreadLocal<T>::Local().
 *  - hoembed::ParallelThreadCount(): like vtkSMPTools::GetEstimatedNumberOfThreads().
 *
 * In the VTK build these are vtkSMPTools::For and vtkSMPThreadLocal, exactly as the
 * kernels called them before (so the VTK filters run the same code). When
 * HOEMBED_NO_VTK is defined (the pip wheel, Wrapping/Pip: the pip VTK wheels carry no
 * C++ headers), they run on a small pool of HOEMBED_NUM_THREADS - 1 threads (default:
 * std::thread::hardware_concurrency()), started at the first loop and kept: the range is
 * cut into fixed chunks (`grain` items, or 1/(8 x threads) of the range when no grain is
 * given) handed out in order by an atomic counter to the calling thread and the pool's.
 * A loop started inside another (or while the pool serves another caller) runs
 * serially on its thread, as vtkSMPTools does with nested parallelism off.
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
#include <condition_variable>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <type_traits>
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

/// Threads the loops may use (vtkSMPTools::GetEstimatedNumberOfThreads).
inline int ParallelThreadCount()
{
  return vtkSMPTools::GetEstimatedNumberOfThreads();
}

template <typename T>
class ThreadLocal
{
public:
  T& Local()
  {
    return this->Storage.Local();
  }

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

/// The worker index of this thread (0: a caller; 1..n-1: the pool's threads).
inline int& WorkerIndex()
{
  thread_local int index = 0;
  return index;
}

/// One loop: chunks [0, Chunks) taken in turn from Next; the caller returns when Done
/// reaches Chunks. Shared with the workers, so that one waking after the loop ended
/// finds no chunk left and never touches the caller's functor.
struct Job
{
  std::int64_t Chunks = 0;
  std::atomic<std::int64_t> Next{ 0 }, Done{ 0 };
  void (*Run)(void* functor, std::int64_t chunk) = nullptr;
  void* Functor = nullptr;
  std::mutex Mutex;
  std::condition_variable Finished;
  std::exception_ptr Error;

  // take chunks until none is left; true if this call finished the last one
  void Work()
  {
    for (std::int64_t c = this->Next++; c < this->Chunks; c = this->Next++)
    {
      try
      {
        this->Run(this->Functor, c);
      }
      catch (...)
      {
        std::lock_guard<std::mutex> lock(this->Mutex);
        if (!this->Error)
          this->Error = std::current_exception();
      }
      if (++this->Done == this->Chunks)
      {
        std::lock_guard<std::mutex> lock(this->Mutex);
        this->Finished.notify_all();
      }
    }
  }
};

/// NumberOfThreads() - 1 threads started at the first parallel loop and kept (never
/// joined: the pool lives until the process ends, so no exit-time ordering matters).
/// The caller works on its own loop too and waits only for chunks already taken, so a
/// worker the scheduler has not woken yet (a loaded machine) does not delay the loop.
class Pool
{
public:
  static Pool& Get()
  {
    static Pool* pool = new Pool(NumberOfThreads() - 1);
    return *pool;
  }

  /// false when the pool is busy (a loop inside a loop, or another caller): then the
  /// caller runs its loop alone
  bool TryRun(const std::shared_ptr<Job>& job)
  {
    bool expected = false;
    if (this->Workers.empty() || !this->Busy.compare_exchange_strong(expected, true))
      return false;
    {
      std::lock_guard<std::mutex> lock(this->Mutex);
      this->Current = job;
      ++this->Generation;
    }
    this->Wake.notify_all();
    job->Work();
    {
      std::unique_lock<std::mutex> lock(job->Mutex);
      job->Finished.wait(lock, [&] { return job->Done.load() == job->Chunks; });
    }
    {
      std::lock_guard<std::mutex> lock(this->Mutex);
      this->Current.reset();
    }
    this->Busy = false;
    return true;
  }

private:
  explicit Pool(int workers)
  {
    for (int t = 1; t <= workers; ++t)
      this->Workers.emplace_back([this, t] { this->Loop(t); });
    for (std::thread& w : this->Workers)
      w.detach();
  }

  void Loop(int index)
  {
    WorkerIndex() = index;
    std::uint64_t seen = 0;
    for (;;)
    {
      std::shared_ptr<Job> job;
      {
        std::unique_lock<std::mutex> lock(this->Mutex);
        this->Wake.wait(lock, [&] { return this->Generation != seen; });
        seen = this->Generation;
        job = this->Current;
      }
      if (job)
        job->Work();
    }
  }

  std::vector<std::thread> Workers;
  std::mutex Mutex;
  std::condition_variable Wake;
  std::uint64_t Generation = 0;
  std::shared_ptr<Job> Current;
  std::atomic<bool> Busy{ false };
};

/// Whether this thread is inside a loop (then a nested loop runs serially).
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
  struct Range
  {
    std::remove_reference_t<F>* Body;
    std::int64_t Begin, N, Grain;
  } range{ &f, static_cast<std::int64_t>(begin), n, g };
  auto job = std::make_shared<Job>();
  job->Chunks = chunks;
  job->Functor = &range;
  job->Run = [](void* r, std::int64_t c) {
    const Range& rg = *static_cast<Range*>(r);
    const std::int64_t b = c * rg.Grain;
    const std::int64_t e = std::min(rg.N, b + rg.Grain);
    const bool saved = InLoop();
    InLoop() = true;
    struct Restore
    {
      bool Saved;
      ~Restore()
      {
        InLoop() = this->Saved;
      }
    } restore{ saved };
    (*rg.Body)(static_cast<I>(rg.Begin + b), static_cast<I>(rg.Begin + e));
  };
  if (!Pool::Get().TryRun(job))
  {
    f(begin, end);
    return;
  }
  if (job->Error)
    std::rethrow_exception(job->Error);
}

template <typename I, typename F>
void ParallelLoop(I begin, I end, F&& f)
{
  ParallelLoop(begin, end, I(0), f);
}

/// Threads the loops may use (HOEMBED_NUM_THREADS, else the hardware's).
inline int ParallelThreadCount()
{
  return parallel_detail::NumberOfThreads();
}

template <typename T>
class ThreadLocal
{
public:
  ThreadLocal() : Slots(parallel_detail::NumberOfThreads()) {}
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
