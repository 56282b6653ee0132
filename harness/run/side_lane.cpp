#include "harness/run/side_lane.h"

#include <exception>
#include <stdexcept>

namespace pxh {

SideLane::SideLane() : thread_([this] { loop(); }) {}

SideLane::~SideLane() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
}

std::future<void> SideLane::post(std::function<void()> work) {
    std::packaged_task<void()> task(std::move(work));
    std::future<void> done = task.get_future();
    {
        std::lock_guard<std::mutex> lock(mutex_);
        queue_.push_back(std::move(task));
    }
    wake_.notify_one();
    return done;
}

void SideLane::loop() {
    for (;;) {
        std::packaged_task<void()> task;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            wake_.wait(lock, [&] { return stop_ || !queue_.empty(); });
            if (queue_.empty()) return;  // stopped, and everything posted has run
            task = std::move(queue_.front());
            queue_.pop_front();
        }
        task();  // its exception (none escape SideRows' work) goes to its future
    }
}

SideRows::~SideRows() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        cancel_ = true;
    }
    room_.notify_all();
    for (auto& d : done_)
        if (d.valid()) d.wait();
}

void SideRows::add(std::function<MethodOutput()> run, std::function<std::string()> shader) {
    const size_t i = rows_.size();
    rows_.emplace_back();
    Row* row = &rows_.back();
    done_.push_back(lane_.post([this, i, row, run = std::move(run), shader = std::move(shader)] {
        {
            std::unique_lock<std::mutex> lock(mutex_);
            room_.wait(lock, [&] { return cancel_ || i < taken_ + window_; });
            if (cancel_) return;
        }
        try {
            row->out = run();
        } catch (const std::exception& e) {
            row->error = e.what();
            row->shader = shader();
        } catch (...) {
            row->fatal = std::current_exception();
        }
    }));
}

SideRows::Row SideRows::take() {
    size_t i;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        i = taken_;
    }
    if (i >= rows_.size()) throw std::logic_error("SideRows::take: no row left");
    done_[i].get();
    Row r = std::move(rows_[i]);
    rows_[i] = Row{};
    {
        std::lock_guard<std::mutex> lock(mutex_);
        ++taken_;
    }
    room_.notify_all();
    if (r.fatal) std::rethrow_exception(r.fatal);
    return r;
}

}  // namespace pxh
