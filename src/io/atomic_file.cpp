// src/io/atomic_file.cpp — write_file_atomic (declared in mwst/io/triangle_files.hpp): writes a file under a
// temporary name in the same directory (PATH.tmp.<pid>) and renames it over PATH when complete, so
// readers never see a partial file and a failure leaves nothing behind.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <span>
#include <string>
#include <string_view>
#include <system_error>

#include "mwst/error.hpp"
#include "mwst/io/triangle_files.hpp"

namespace mwst::io {

void write_file_atomic(const std::string& path, std::span<const std::string_view> pieces) {
  const std::string tmp = path + ".tmp." + std::to_string(static_cast<long long>(::getpid()));
  const auto fail = [&](int err, bool remove_tmp) {
    if (remove_tmp) ::unlink(tmp.c_str());
    throw InputError(path, 0, "cannot write: " + std::error_code(err, std::generic_category()).message());
  };
  int fd;
  do {
    fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  } while (fd < 0 && errno == EINTR);
  if (fd < 0) fail(errno, false);
  for (const std::string_view content : pieces) {
    const char* p = content.data();
    std::size_t left = content.size();
    while (left > 0) {
      const ssize_t n = ::write(fd, p, left);
      if (n < 0) {
        if (errno == EINTR) continue;
        const int err = errno;
        ::close(fd);
        fail(err, true);
      }
      p += n;
      left -= static_cast<std::size_t>(n);
    }
  }
  if (::close(fd) != 0) fail(errno, true);
  if (std::rename(tmp.c_str(), path.c_str()) != 0) fail(errno, true);
}

void write_file_atomic(const std::string& path, std::string_view content) {
  write_file_atomic(path, std::span<const std::string_view>(&content, 1));
}

}  // namespace mwst::io
