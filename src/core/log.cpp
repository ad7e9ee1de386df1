#include "core/log.h"

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace voxgi {
namespace {
std::atomic<int> gLevel{static_cast<int>(LogLevel::kInfo)};
std::atomic<int> gWarnings{0};

void emit(LogLevel level, const char* tag, const std::string& msg) {
  if (static_cast<int>(level) < gLevel.load()) return;
  std::fprintf(stderr, "voxgi: %s%s\n", tag, msg.c_str());
}
}  // namespace

void setLogLevel(LogLevel level) {
  gLevel = static_cast<int>(level);
}
LogLevel logLevel() {
  return static_cast<LogLevel>(gLevel.load());
}

std::string strf(const char* fmt, ...) {
  va_list args;
  va_start(args, fmt);
  va_list copy;
  va_copy(copy, args);
  const int n = std::vsnprintf(nullptr, 0, fmt, copy);
  va_end(copy);
  std::string out;
  if (n > 0) {
    std::vector<char> buf(static_cast<size_t>(n) + 1);
    std::vsnprintf(buf.data(), buf.size(), fmt, args);
    out.assign(buf.data(), static_cast<size_t>(n));
  }
  va_end(args);
  return out;
}

void logDebug(const std::string& msg) {
  emit(LogLevel::kDebug, "debug: ", msg);
}
void logInfo(const std::string& msg) {
  emit(LogLevel::kInfo, "", msg);
}
void logWarning(const std::string& msg) {
  ++gWarnings;
  emit(LogLevel::kWarning, "warning: ", msg);
}
void logError(const std::string& msg) {
  emit(LogLevel::kError, "error: ", msg);
}
int warningCount() {
  return gWarnings.load();
}

void checkFailed(const char* file, int line, const char* expr, const std::string& detail) {
  std::fprintf(stderr, "voxgi: internal check failed at %s:%d: %s %s\n", file, line, expr,
               detail.c_str());
  std::abort();
}

}  // namespace voxgi
