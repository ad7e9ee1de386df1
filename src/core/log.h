// Logging, error values and checks shared by every stage.
//
// Policy (see README "Errors"): bad input (files, glTF, shaders, sizes) throws
// voxgi::Error with a one-line message naming the file and the problem; only app/
// catches it and decides to exit. Programmer mistakes use VOXGI_CHECK, which prints
// both operands and aborts in every build.
#ifndef VOXGI_CORE_LOG_H
#define VOXGI_CORE_LOG_H

#include <cstdarg>
#include <sstream>
#include <stdexcept>
#include <string>

namespace voxgi {

enum class LogLevel { kDebug = 0, kInfo = 1, kWarning = 2, kError = 3, kQuiet = 4 };

void setLogLevel(LogLevel level);
LogLevel logLevel();

// printf-style formatting into a std::string.
std::string strf(const char* fmt, ...) __attribute__((format(printf, 1, 2)));

void logDebug(const std::string& msg);
void logInfo(const std::string& msg);
void logWarning(const std::string& msg);
void logError(const std::string& msg);

// Count of warnings logged so far (tests and stats read it).
int warningCount();

// Bad input: one line, naming the file (or other source) and the problem.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

[[noreturn]] void checkFailed(const char* file, int line, const char* expr,
                              const std::string& detail);

namespace detail {
template <typename A, typename B>
std::string describeOperands(const A& a, const B& b) {
  std::ostringstream s;
  s << "(" << a << " vs " << b << ")";
  return s.str();
}
}  // namespace detail

}  // namespace voxgi

#define VOXGI_CHECK(cond) \
  ((cond) ? (void)0 : ::voxgi::checkFailed(__FILE__, __LINE__, #cond, std::string()))
#define VOXGI_CHECK_OP(a, op, b)                                            \
  (((a)op(b)) ? (void)0                                                     \
              : ::voxgi::checkFailed(__FILE__, __LINE__, #a " " #op " " #b, \
                                     ::voxgi::detail::describeOperands((a), (b))))
#define VOXGI_CHECK_EQ(a, b) VOXGI_CHECK_OP(a, ==, b)
#define VOXGI_CHECK_LE(a, b) VOXGI_CHECK_OP(a, <=, b)
#define VOXGI_CHECK_LT(a, b) VOXGI_CHECK_OP(a, <, b)
#ifdef NDEBUG
#define VOXGI_DCHECK(cond) ((void)0)
#else
#define VOXGI_DCHECK(cond) VOXGI_CHECK(cond)
#endif

#endif  // VOXGI_CORE_LOG_H
