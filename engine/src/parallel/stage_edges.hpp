// parallel/stage_edges.hpp — the happens-before edges of a parallel stage, for ThreadSanitizer.
//
// Debian's libtbb is not built with -fsanitize=thread, so TSan cannot see that a task runs after
// the thread that made it, or that the caller resumes after every task ended: those edges live in
// libtbb's own atomics. StageEdges states them with TSan's annotations, in TSan builds only; in
// every other build task() returns the body itself and join() is empty.
//
//   StageEdges edges;
//   tbb::parallel_for(0, n, edges.task(body));  // each task sees what its spawner wrote
//   edges.join();                               // and the caller sees what every task wrote
//
// SlotHold states a third edge, for state kept per arena slot (indexed by
// tbb::this_task_arena::current_thread_index()): oneTBB may hand a slot to another thread in the
// middle of a stage, and the new holder sees what the last one wrote to the slot's state.
#pragma once

#if defined(__SANITIZE_THREAD__)
#define MOSAIC_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define MOSAIC_TSAN 1
#endif
#endif

#if defined(MOSAIC_TSAN)
#include <sanitizer/tsan_interface.h>

// The runtime exports these (no header declares them): between them the calling thread's
// memory accesses are neither recorded nor checked. (AnnotateNewMemory, which would forget a
// range's history, is an empty function in GCC 12's libtsan.)
extern "C" void __tsan_ignore_thread_begin();
extern "C" void __tsan_ignore_thread_end();
#endif

#include <utility>

namespace mosaic::parallel {

#if defined(MOSAIC_TSAN)
inline constexpr bool kTsan = true;
#else
inline constexpr bool kTsan = false;
#endif

namespace tsan {
inline void release([[maybe_unused]] const void* sync) {
#if defined(MOSAIC_TSAN)
  __tsan_release(const_cast<void*>(sync));
#endif
}
inline void acquire([[maybe_unused]] const void* sync) {
#if defined(MOSAIC_TSAN)
  __tsan_acquire(const_cast<void*>(sync));
#endif
}
inline void ignore_begin() {
#if defined(MOSAIC_TSAN)
  __tsan_ignore_thread_begin();
#endif
}
inline void ignore_end() {
#if defined(MOSAIC_TSAN)
  __tsan_ignore_thread_end();
#endif
}
}  // namespace tsan

class StageEdges {
 public:
  /// `body` as a task. In TSan builds each copy oneTBB makes of it (one per task, in the thread
  /// that spawns that task) acquires its source and releases itself, and each call acquires the
  /// copy it runs. oneTBB's small-object pool hands a finished task's memory to the next task in
  /// uninstrumented code, so TSan would see a copy's writes race with the old task's last reads:
  /// a copy writes its own fields unrecorded. What the task body does is checked as ever.
  template <class Body>
  auto task(Body body) {
    if constexpr (kTsan) {
      return Task<Body>(*this, std::move(body));
    } else {
      return body;
    }
  }
  /// In the caller, after the stage returned: every task happens before what follows.
  void join() { tsan::acquire(&join_); }

 private:
  template <class Body>
  class Task {
   public:
    // The members are written between ignore_begin() (in the first one's initialiser) and
    // ignore_end().
    Task(StageEdges& edges, Body body)
        : edges_((tsan::acquire(this), tsan::ignore_begin(), &edges)), body_(std::move(body)) {
      tsan::ignore_end();
      tsan::release(this);
    }
    Task(const Task& other)
        : edges_((tsan::acquire(this), tsan::acquire(&other), tsan::ignore_begin(), other.edges_)),
          body_(other.body_) {
      tsan::ignore_end();
      tsan::release(this);
    }
    Task& operator=(const Task&) = delete;
    template <class... Args>
    void operator()(Args&&... args) const {
      tsan::acquire(this);
      body_(std::forward<Args>(args)...);
      tsan::release(&edges_->join_);
      tsan::release(this);  // oneTBB reuses a finished task's memory for the next copy
    }

   private:
    StageEdges* edges_;
    Body body_;
  };

  // Tasks release here and only the caller acquires, so that no task is ordered after another
  // through it: a race between two tasks of one stage stays visible.
  char join_ = 0;
};

/// Held by a task for as long as it uses its arena slot's state. oneTBB hands a slot from one
/// thread to another (synchronised inside libtbb) only between two tasks, so in TSan builds the
/// holder acquires the state at the start and releases it at the end. It orders the tasks of one
/// slot only: a race between tasks on two slots stays visible.
class SlotHold {
 public:
  explicit SlotHold([[maybe_unused]] const void* state) {
#if defined(MOSAIC_TSAN)
    state_ = state;
    tsan::acquire(state_);
#endif
  }
  ~SlotHold() {
#if defined(MOSAIC_TSAN)
    tsan::release(state_);
#endif
  }
  SlotHold(const SlotHold&) = delete;
  SlotHold& operator=(const SlotHold&) = delete;

 private:
#if defined(MOSAIC_TSAN)
  const void* state_;
#endif
};

}  // namespace mosaic::parallel
