#include "bench/pipeline/child_process.hpp"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <stdexcept>
#include <string>

namespace snag::bench {

namespace {

long long max_rss_bytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<long long>(usage.ru_maxrss) * 1024;  // Linux reports KiB
}

bool reset_peak_rss() {
  std::FILE* file = std::fopen("/proc/self/clear_refs", "w");
  if (file == nullptr) return false;
  const bool written = std::fputs("5", file) >= 0;
  return std::fclose(file) == 0 && written;
}

void write_all(int fd, const std::string& text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    done += static_cast<std::size_t>(n);
  }
}

}  // namespace

ChildResult run_in_child(const std::function<nlohmann::json()>& measure) {
  std::fflush(nullptr);
  int fds[2];
  if (::pipe(fds) != 0) throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
  if (pid == 0) {
    ::close(fds[0]);
    nlohmann::json message;
    try {
      const bool reset = reset_peak_rss();
      const long long before = max_rss_bytes();
      nlohmann::json value = measure();
      const long long after = max_rss_bytes();
      message = {{"ok", true}, {"value", std::move(value)}, {"peak_rss_growth_bytes", after - before},
                 {"peak_reset", reset}};
    } catch (const std::exception& e) {
      message = {{"ok", false}, {"error", e.what()}};
    } catch (...) {
      message = {{"ok", false}, {"error", "unknown exception"}};
    }
    write_all(fds[1], message.dump());
    ::close(fds[1]);
    std::fflush(nullptr);
    ::_exit(0);
  }
  ::close(fds[1]);
  std::string text;
  char buffer[65536];
  for (;;) {
    const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    text.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || text.empty())
    throw std::runtime_error("measurement process died (status " + std::to_string(status) + ")");
  const nlohmann::json message = nlohmann::json::parse(text);
  if (!message.at("ok").get<bool>()) throw std::runtime_error(message.at("error").get<std::string>());
  ChildResult result;
  result.value = message.at("value");
  result.peak_rss_growth_bytes = message.at("peak_rss_growth_bytes").get<long long>();
  result.peak_reset = message.at("peak_reset").get<bool>();
  return result;
}

}  // namespace snag::bench
