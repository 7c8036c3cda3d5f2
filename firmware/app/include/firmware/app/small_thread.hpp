// SPDX-License-Identifier: MIT
#pragma once
// A thread with a small stack. Under mlockall(MCL_CURRENT | MCL_FUTURE) every byte of a
// thread's stack mapping is resident, and std::thread takes the default 8 MiB: the
// gateway's helper threads (log drain, stdin reader) use 256 KiB instead.

#include <pthread.h>

#include <cstddef>
#include <functional>
#include <memory>

namespace excite::app {

inline constexpr std::size_t kHelperStack = 256 * 1024;

class SmallThread {
 public:
  SmallThread() = default;
  SmallThread(const SmallThread&) = delete;
  SmallThread& operator=(const SmallThread&) = delete;
  ~SmallThread() { join(); }

  /// Starts `body` on a new thread with a `stack_bytes` stack; false if it could not start.
  bool start(std::function<void()> body, std::size_t stack_bytes = kHelperStack) {
    body_ = std::make_unique<std::function<void()>>(std::move(body));
    pthread_attr_t attr;
    pthread_attr_init(&attr);
    pthread_attr_setstacksize(&attr, stack_bytes);
    const int rc = pthread_create(&thread_, &attr, &SmallThread::trampoline, body_.get());
    pthread_attr_destroy(&attr);
    running_ = rc == 0;
    return running_;
  }

  void join() {
    if (running_) {
      pthread_join(thread_, nullptr);
      running_ = false;
    }
  }

  void detach() {
    if (running_) {
      pthread_detach(thread_);
      running_ = false;
      // Owned by the detached thread until the process ends: never freed (the thread may
      // still run in it at exit), but kept reachable from this object, so a leak checker
      // does not call it lost (the gateway's SmallThread for stdin is static).
      detached_body_ = body_.release();
    }
  }

  [[nodiscard]] bool joinable() const { return running_; }

 private:
  std::function<void()>* detached_body_ = nullptr;
  static void* trampoline(void* arg) {
    (*static_cast<std::function<void()>*>(arg))();
    return nullptr;
  }

  pthread_t thread_{};
  bool running_ = false;
  std::unique_ptr<std::function<void()>> body_;
};

}  // namespace excite::app
