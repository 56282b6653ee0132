// A thread of the run's own for the rows of backends that work in a process of their own (the
// GLSL backend's GL worker, BackendEntry::own_process): while the worker draws a view's rows,
// this process traces the view's truth and runs its other backends' rows, instead of waiting
// on the worker's pipe.
//
// Only where nothing is timed (a run with timing_repeats = 0, or a sweep's untimed companion
// view): two things drawn at once would be in each other's times. The rows, their order and
// every number are the same as when one thread runs them all: each row's output depends only on
// its own inputs, and the rows are scored on the calling thread in row order.
//
// One thread for the whole run, not one per view: a GL worker started again after a failure
// (gl_time_limit_s) is a child of the thread that started it, and dies with that thread
// (PR_SET_PDEATHSIG), so that thread must live as long as the backend.
#pragma once
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <future>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "harness/backends/backend.h"
#include "harness/core/limits.h"

namespace pxh {

class SideLane {
  public:
    SideLane();
    ~SideLane();  // after the work posted so far
    SideLane(const SideLane&) = delete;
    SideLane& operator=(const SideLane&) = delete;
    // Runs `work` on the lane after what was posted before it.
    std::future<void> post(std::function<void()> work);

  private:
    void loop();
    std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<std::packaged_task<void()>> queue_;
    bool stop_ = false;
    std::thread thread_;
};

// One view's rows of the own-process backends, drawn on the lane in row order, at most
// `window` outputs ahead of the rows taken (kSideRowsAhead) (a view's outputs are not all held at
// once). The destructor waits for the lane to finish this view's work (rows not yet begun are
// skipped), so nothing the work reads outlives it.
class SideRows {
  public:
    struct Row {
        std::optional<MethodOutput> out;  // empty: the row failed, `error` says why
        std::string error;
        std::string shader;  // the results' shader column of a failed row
        // Not a std::exception: rethrown by take() on the calling thread, as the same throw
        // would leave the view there (a std::exception fails the row, as run_method does).
        std::exception_ptr fatal;
    };
    SideRows(SideLane& lane, size_t window = kSideRowsAhead) : lane_(lane), window_(window) {}
    ~SideRows();
    SideRows(const SideRows&) = delete;
    SideRows& operator=(const SideRows&) = delete;
    // Posts the next row: `run` makes its output (an exception fails the row with its message),
    // `shader` names its shader for a failed row. Both run on the lane.
    void add(std::function<MethodOutput()> run, std::function<std::string()> shader);
    // The next row in the order added, once drawn.
    Row take();

  private:
    SideLane& lane_;
    size_t window_;
    std::mutex mutex_;
    std::condition_variable room_;
    size_t taken_ = 0;
    bool cancel_ = false;
    std::deque<Row> rows_;  // per row added (a deque: its elements stay where they are)
    std::deque<std::future<void>> done_;
};

}  // namespace pxh
