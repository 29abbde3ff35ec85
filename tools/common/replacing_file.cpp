#include "tools/common/replacing_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cassert>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "libcd/core/error.hpp"

namespace snag::tools {
namespace {

// The temporary file a signal handler removes. Written before the handlers
// are installed and cleared after they are restored, so the handler reads a
// finished string.
char g_temporary[4096];
volatile std::sig_atomic_t g_active = 0;
struct sigaction g_previous_int, g_previous_term;

extern "C" void remove_temporary_and_reraise(int signal_number) {
  if (g_active) unlink(g_temporary);
  // Let the signal end the process as it would have: the previous
  // disposition, then the signal again.
  sigaction(signal_number, signal_number == SIGINT ? &g_previous_int : &g_previous_term, nullptr);
  raise(signal_number);
}

void install_handlers() {
  struct sigaction action {};
  action.sa_handler = remove_temporary_and_reraise;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, &g_previous_int);
  sigaction(SIGTERM, &action, &g_previous_term);
}

void restore_handlers() {
  sigaction(SIGINT, &g_previous_int, nullptr);
  sigaction(SIGTERM, &g_previous_term, nullptr);
}

mode_t new_file_mode() {
  const mode_t mask = umask(0);
  umask(mask);
  return 0666 & ~mask;
}

}  // namespace

ReplacingFile::ReplacingFile(const std::string& path) : path_(path) {
  assert(!g_active);
  struct stat existing {};
  if (stat(path.c_str(), &existing) == 0 && !S_ISREG(existing.st_mode)) {
    // A device, a pipe or a socket (/dev/null, /dev/stdout, a shell's
    // process substitution) is written in place: it cannot be replaced, and
    // renaming over it would put a plain file in its stead.
    out_.open(path, std::ios::binary);
    if (!out_) throw UsageError("cannot write '" + path + "': " + std::strerror(errno));
    in_place_ = true;
    return;
  }
  // A symbolic link to a file: replace the file, and keep the link.
  if (char* resolved = realpath(path.c_str(), nullptr)) {
    path_ = resolved;
    std::free(resolved);
  }
  mode_t mode = new_file_mode();
  if (stat(path_.c_str(), &existing) == 0) mode = existing.st_mode & 07777;  // keep an earlier file's permissions
  const std::size_t slash = path_.find_last_of('/');
  const std::string directory = slash == std::string::npos ? "" : path_.substr(0, slash + 1);
  const std::string name = slash == std::string::npos ? path_ : path_.substr(slash + 1);
  temporary_ = directory + "." + name + ".XXXXXX";
  if (name.empty() || temporary_.size() >= sizeof g_temporary) {
    throw UsageError("cannot write '" + path + "': not a file name");
  }
  std::vector<char> buffer(temporary_.begin(), temporary_.end());
  buffer.push_back('\0');
  const int fd = mkstemp(buffer.data());
  if (fd < 0) throw UsageError("cannot write '" + path + "': " + std::strerror(errno));
  temporary_ = buffer.data();
  const bool moded = fchmod(fd, mode) == 0;
  close(fd);
  std::memcpy(g_temporary, temporary_.c_str(), temporary_.size() + 1);
  g_active = 1;
  install_handlers();
  out_.open(temporary_, std::ios::binary | std::ios::trunc);
  if (!moded || !out_) {
    const int error = errno;
    unlink(temporary_.c_str());
    throw UsageError("cannot write '" + path + "': " + std::strerror(error));
  }
}

ReplacingFile::~ReplacingFile() {
  if (in_place_) return;
  if (!committed_) {
    out_.close();
    unlink(temporary_.c_str());
  }
  restore_handlers();
  g_active = 0;
}

void ReplacingFile::commit() {
  assert(!committed_);
  out_.flush();
  const bool written = static_cast<bool>(out_);
  out_.close();
  if (!written || out_.fail()) throw UsageError("cannot write '" + path_ + "': writing failed (disk full?)");
  committed_ = in_place_;
  if (in_place_) return;
  if (std::rename(temporary_.c_str(), path_.c_str()) != 0) {
    throw UsageError("cannot write '" + path_ + "': " + std::strerror(errno));
  }
  committed_ = true;
}

}  // namespace snag::tools
