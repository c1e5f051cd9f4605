// A call that must end in an illum::Error within a time limit: inputs that once made a
// decoder or loader loop forever (test_image_errors, obj_texture_errors_test).
#pragma once

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <future>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "illum/core/error.h"

namespace illum::test {

// Runs `f` on a worker thread and returns the illum::Error it throws ("" and a failure if
// none). A call that has not returned after `seconds` fails the test and ends the process
// (the thread cannot be stopped), so a regression fails instead of stalling CI.
inline std::string error_within(double seconds, const std::function<void()>& f) {
  std::packaged_task<std::string()> task([f] {
    try {
      f();
    } catch (const Error& e) {
      return std::string(e.what());
    } catch (const std::exception& e) {
      return std::string("not an illum::Error: ") + e.what();
    }
    return std::string();
  });
  auto result = task.get_future();
  std::thread worker(std::move(task));
  if (result.wait_for(std::chrono::duration<double>(seconds)) != std::future_status::ready) {
    std::fprintf(stderr, "FAILED: the call did not return within %.0f s (hang)\n", seconds);
    std::fflush(stderr);
    std::_Exit(1);
  }
  worker.join();
  const std::string message = result.get();
  EXPECT_FALSE(message.empty()) << "no illum::Error was thrown";
  return message;
}

}  // namespace illum::test
