#include "illum/core/log.h"

#include <cstdio>
#include <mutex>
#include <string>
#include <vector>

#include <spdlog/sinks/base_sink.h>
#include <spdlog/sinks/stdout_color_sinks.h>

namespace illum::log {

namespace {

// Forwards to the coloured stderr sink, or keeps the formatted lines while held.
class HoldableSink final : public spdlog::sinks::base_sink<std::mutex> {
 public:
  HoldableSink() : out_(std::make_shared<spdlog::sinks::stderr_color_sink_st>()) {}

  void hold() {
    std::lock_guard<std::mutex> lock(mutex_);
    held_ = true;
  }
  void release() {
    std::lock_guard<std::mutex> lock(mutex_);
    held_ = false;
    for (const std::string& line : waiting_) std::fputs(line.c_str(), stderr);
    std::fflush(stderr);
    waiting_.clear();
  }
  size_t discard() {
    std::lock_guard<std::mutex> lock(mutex_);
    held_ = false;
    const size_t n = waiting_.size();
    waiting_.clear();
    return n;
  }

 protected:
  void sink_it_(const spdlog::details::log_msg& msg) override {
    if (!held_) {
      out_->log(msg);
      return;
    }
    spdlog::memory_buf_t formatted;
    formatter_->format(msg, formatted);
    waiting_.emplace_back(formatted.data(), formatted.size());
  }
  void flush_() override { out_->flush(); }
  void set_pattern_(const std::string& pattern) override {
    out_->set_pattern(pattern);
    base_sink::set_pattern_(pattern);
  }

 private:
  std::shared_ptr<spdlog::sinks::sink> out_;
  bool held_ = false;
  std::vector<std::string> waiting_;
};

const std::shared_ptr<HoldableSink>& sink() {
  static const std::shared_ptr<HoldableSink> instance = std::make_shared<HoldableSink>();
  return instance;
}

}  // namespace

spdlog::logger& logger() {
  static const std::shared_ptr<spdlog::logger> instance = [] {
    auto created = std::make_shared<spdlog::logger>("illum", sink());
    created->set_pattern("illum: [%^%l%$] %v");
    spdlog::set_default_logger(created);  // direct spdlog calls print the same way
    return created;
  }();
  return *instance;
}

void hold() {
  logger();
  sink()->hold();
}

void release() {
  sink()->release();
}

size_t discard() {
  return sink()->discard();
}

void set_level(Level level) {
  switch (level) {
    case Level::kDebug:
      logger().set_level(spdlog::level::debug);
      break;
    case Level::kInfo:
      logger().set_level(spdlog::level::info);
      break;
    case Level::kWarn:
      logger().set_level(spdlog::level::warn);
      break;
    case Level::kError:
      logger().set_level(spdlog::level::err);
      break;
    case Level::kOff:
      logger().set_level(spdlog::level::off);
      break;
  }
}

}  // namespace illum::log
