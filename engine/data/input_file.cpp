#include "data/input_file.h"

#include <fcntl.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>

#include "core/suggest.h"

namespace kfw {

namespace {

std::string kind_of(mode_t m) {
  if (S_ISFIFO(m)) return "a FIFO";
  if (S_ISCHR(m)) return "a character device";
  if (S_ISBLK(m)) return "a block device";
  if (S_ISSOCK(m)) return "a socket";
  return "not a plain file";
}

std::string too_big(const std::string& shown, std::uint64_t size, limits::Input kind) {
  return shown + ": " + std::to_string(size) + " bytes or more: larger than the " +
         limits::bytes_text(limits::max_bytes(kind)) + " limit for a " + limits::input_name(kind) +
         " (docs/limits.md)";
}

}  // namespace

Expected<int> open_input_file(const std::string& path, limits::Input kind) {
  const std::string shown = truncate_token(path);
  // O_NONBLOCK: opening a FIFO without a writer must not wait; fstat then refuses it.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    const int e = errno;
    if (e == EISDIR) {
      return Error{shown + ": is a directory, not a " + std::string(limits::input_name(kind))};
    }
    return Error{shown + ": cannot open " + std::string(limits::input_name(kind)) + " (" +
                 std::generic_category().message(e) + ")"};
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    const bool dir = S_ISDIR(st.st_mode);
    ::close(fd);
    if (dir)
      return Error{shown + ": is a directory, not a " + std::string(limits::input_name(kind))};
    return Error{shown + ": not a regular file (" + kind_of(st.st_mode) + "); kfw reads a " +
                 limits::input_name(kind) + " only from a regular file"};
  }
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags >= 0) ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
  return fd;
}

Expected<std::string> read_input_file(const std::string& path, limits::Input kind,
                                      std::size_t max_line) {
  auto fd = open_input_file(path, kind);
  if (!fd) return fd.err();
  const std::string shown = truncate_token(path);
  const std::uint64_t cap = limits::max_bytes(kind);
  struct stat st {};
  ::fstat(*fd, &st);
  const auto size = static_cast<std::uint64_t>(st.st_size);
  if (size > cap) {
    ::close(*fd);
    return Error{too_big(shown, size, kind)};
  }
  std::string text;
  text.reserve(static_cast<std::size_t>(size));
  char buf[1 << 16];
  std::size_t since_newline = 0;
  for (;;) {
    const ssize_t n = ::read(*fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int e = errno;
      ::close(*fd);
      return Error{shown + ": read error (" + std::generic_category().message(e) + ")"};
    }
    if (n == 0) break;
    const auto un = static_cast<std::size_t>(n);
    if (text.size() + un > cap) {  // the file grew while being read
      ::close(*fd);
      return Error{too_big(shown, text.size() + un, kind)};
    }
    text.append(buf, un);
    if (!max_line) continue;
    const void* nl = ::memrchr(buf, '\n', un);
    since_newline = nl ? un - static_cast<std::size_t>(static_cast<const char*>(nl) - buf) - 1
                       : since_newline + un;
    if (since_newline > max_line) break;  // the text ends inside a line the parser refuses
  }
  ::close(*fd);
  return text;
}

}  // namespace kfw
