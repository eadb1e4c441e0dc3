#include "data/output.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <system_error>
#include <thread>

#include "core/suggest.h"

namespace kfw {

namespace fs = std::filesystem;

namespace {

constexpr int kMaxSymlinkHops = 40;
constexpr std::size_t kMaxTempStem = 100;
constexpr std::size_t kMaxHeldLocks = 256;  // keeps ".NAME.kfw-XXXXXX" under NAME_MAX

std::string errno_text(int e) {
  return std::generic_category().message(e);
}

std::string shown(const fs::path& p) {
  return truncate_token(p.string());
}

std::string prefix(std::string_view option, const std::string& path) {
  return (option.empty() ? std::string() : std::string(option) + ": ") + truncate_token(path) +
         ": ";
}

// The same file: one inode when both exist, else the same canonical path.
bool same_file(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) {
    const bool eq = fs::equivalent(a, b, ec);
    if (!ec) return eq;
  }
  const fs::path ca = fs::weakly_canonical(a, ec);
  if (ec) return false;
  const fs::path cb = fs::weakly_canonical(b, ec);
  return !ec && ca == cb;
}

fs::path directory_of(const fs::path& target) {
  return target.has_parent_path() ? target.parent_path() : fs::path(".");
}

// The process umask without changing it (umask(2) would race with other threads).
mode_t current_umask() {
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("Umask:", 0) == 0)
      return static_cast<mode_t>(std::strtol(line.c_str() + 6, nullptr, 8));
  }
  return 022;
}

// The new file's permissions: those of the file it replaces, else what a plain create gives.
mode_t file_mode(const fs::path& target) {
  struct stat st {};
  if (::stat(target.c_str(), &st) == 0) return st.st_mode & 07777;
  return 0666 & ~current_umask();
}

void pause_before_rename() {
  const char* ms = std::getenv(kPauseBeforeRenameEnv);
  if (!ms || !*ms) return;
  const long n = std::strtol(ms, nullptr, 10);
  if (n > 0) std::this_thread::sleep_for(std::chrono::milliseconds(n));
}

void sync_directory(const fs::path& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

std::string temp_prefix(const fs::path& target) {
  std::string stem = target.filename().string();
  if (stem.size() > kMaxTempStem) stem.resize(kMaxTempStem);
  return "." + stem + ".kfw-";
}

// Temporaries of earlier writes to `target` whose writer died (SIGKILL, power loss) before the
// rename: a live writer holds flock on its temporary until the rename, so one whose lock can be
// taken, and older than a second (a writer between mkstemp and flock is younger), is removed.
void remove_stale_temporaries(const fs::path& target) {
  const std::string prefix = temp_prefix(target);
  std::error_code ec;
  for (fs::directory_iterator it(directory_of(target), ec), end; !ec && it != end;
       it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.size() != prefix.size() + 6 || name.compare(0, prefix.size(), prefix) != 0) continue;
    const int fd = ::open(it->path().c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) continue;
    struct stat st {};
    const bool stale = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) &&
                       std::time(nullptr) - st.st_mtime >= 1 && ::flock(fd, LOCK_EX | LOCK_NB) == 0;
    if (stale) ::unlink(it->path().c_str());
    ::close(fd);  // releases the lock
  }
}

// Writes the content (`text`, or what `writer` streams) to a new ".NAME.kfw-XXXXXX" beside
// `target`, fsynced, and returns it still open and locked (flock) until the caller has renamed
// it: the lock tells later writers it is live.
Expected<std::pair<fs::path, int>> write_temporary(const fs::path& target, const std::string& path,
                                                   const std::string& text,
                                                   const OutputWriter& writer = {}) {
  remove_stale_temporaries(target);
  std::string name = (directory_of(target) / (temp_prefix(target) + "XXXXXX")).string();
  const int fd = ::mkstemp(name.data());
  if (fd < 0) {
    return failure(truncate_token(path) + ": cannot create a temporary file in " +
                   shown(directory_of(target)) + ": " + errno_text(errno));
  }
  ::flock(fd, LOCK_EX | LOCK_NB);  // a new file: nobody else holds it
  auto fail = [&](const std::string& what, int e) -> Error {
    ::close(fd);
    ::unlink(name.c_str());
    return failure(truncate_token(path) + ": " + what + (e ? ": " + errno_text(e) : ""));
  };
  if (::fchmod(fd, file_mode(target)) != 0) return fail("cannot set permissions", errno);
  OutputStream out(fd);
  if (writer) {
    if (auto st = writer(out); !st) return fail(st.error(), 0);
  } else {
    out.write(text);
  }
  if (!out.flush()) return fail("write failed", out.error());
  if (::fsync(fd) != 0) return fail("fsync failed", errno);
  return std::pair<fs::path, int>(fs::path(name), fd);
}

}  // namespace

OutputStream::OutputStream(int fd) : fd_(fd), buf_(new char[kBuffer]) {}

bool OutputStream::flush() {
  const char* p = buf_.get();
  std::size_t left = used_;
  used_ = 0;
  while (left > 0 && error_ == 0) {
    const ssize_t n = ::write(fd_, p, left);
    if (n < 0) {
      if (errno != EINTR) error_ = errno;
      continue;
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  return error_ == 0;
}

char* OutputStream::reserve(std::size_t n) {
  if (used_ + n > kBuffer) flush();
  return buf_.get() + used_;
}

void OutputStream::write(std::string_view bytes) {
  while (!bytes.empty()) {
    if (used_ == kBuffer) flush();
    const std::size_t k = std::min(bytes.size(), kBuffer - used_);
    std::memcpy(buf_.get() + used_, bytes.data(), k);
    used_ += k;
    bytes.remove_prefix(k);
  }
}

OutputStreamBuf::int_type OutputStreamBuf::overflow(int_type c) {
  if (c != traits_type::eof()) {
    const char ch = traits_type::to_char_type(c);
    out_.write(std::string_view(&ch, 1));
  }
  return traits_type::not_eof(c);
}

std::streamsize OutputStreamBuf::xsputn(const char* s, std::streamsize n) {
  out_.write(std::string_view(s, static_cast<std::size_t>(n)));
  return n;
}

Expected<fs::path> OutputSet::target_of(const std::string& path) {
  fs::path p(path);
  std::error_code ec;
  for (int hops = 0; fs::is_symlink(fs::symlink_status(p, ec)); ++hops) {
    if (hops >= kMaxSymlinkHops) return Error{"too many levels of symbolic links"};
    const fs::path link = fs::read_symlink(p, ec);
    if (ec) return Error{"cannot read the symbolic link: " + ec.message()};
    p = link.is_absolute() ? link : directory_of(p) / link;
  }
  return p;
}

void OutputSet::add_input(const std::string& path) {
  if (!path.empty()) inputs_.emplace_back(path);
}

Status OutputSet::add(const std::string& path, std::string_view option) {
  if (path.empty()) {
    return Error{(option.empty() ? std::string("output") : std::string(option)) +
                 ": the path is empty"};
  }
  const std::string at = prefix(option, path);
  auto target = target_of(path);
  if (!target) return Error{at + target.error()};
  std::error_code ec;
  const fs::file_status st = fs::status(*target, ec);
  if (fs::exists(st)) {
    if (fs::is_directory(st)) return Error{at + "is a directory"};
    if (!fs::is_regular_file(st)) {
      return Error{at + "is not a regular file (a FIFO, device or socket); refusing to replace it"};
    }
  }
  const fs::path dir = directory_of(*target);
  const fs::file_status ds = fs::status(dir, ec);
  if (!fs::exists(ds)) return Error{at + "the directory " + shown(dir) + " does not exist"};
  if (!fs::is_directory(ds)) return Error{at + shown(dir) + " is not a directory"};
  if (::access(dir.c_str(), W_OK | X_OK) != 0) {
    return Error{at + "cannot write in " + shown(dir) + ": " + errno_text(errno)};
  }
  // access() says yes to root on a read-only mount or in /proc: create (and remove) a temporary
  // there now, so the commit cannot fail for that reason after the work.
  if (auto probe = write_temporary(*target, path, {}); !probe) {
    return Error{at + "cannot write in " + shown(dir) +
                 probe.error().substr(probe.error().rfind(':'))};
  } else {
    ::unlink(probe->first.c_str());
    ::close(probe->second);
  }
  for (const auto& in : inputs_) {
    if (same_file(*target, in)) {
      return Error{at + "is also an input of this command; refusing to overwrite it"};
    }
  }
  for (const auto& e : entries_) {
    if (same_file(*target, e.target)) {
      return Error{at + "is already an output of this command" +
                   (e.option.empty() ? std::string() : " (" + e.option + ")")};
    }
  }
  entries_.push_back(Entry{path, std::string(option), *target, std::nullopt});
  return Ok{};
}

Status OutputSet::stage(const std::string& path, std::string text) {
  for (auto& e : entries_) {
    if (e.path == path) {
      e.text = std::move(text);
      e.writer = nullptr;
      return Ok{};
    }
  }
  return failure(truncate_token(path) + ": output staged without being declared");
}

Status OutputSet::stage_stream(const std::string& path, OutputWriter writer) {
  for (auto& e : entries_) {
    if (e.path == path) {
      e.text = std::string();
      e.writer = std::move(writer);
      return Ok{};
    }
  }
  return failure(truncate_token(path) + ": output staged without being declared");
}

Status OutputSet::commit() {
  struct Pending {
    fs::path temp;
    int fd;  // open and locked until renamed
    const Entry* entry;
  };
  std::vector<Pending> pending;
  auto remove_from = [&](std::size_t first) {
    for (std::size_t i = first; i < pending.size(); ++i)
      ::unlink(pending[i].temp.c_str());
  };
  auto close_all = [&] {
    for (const auto& p : pending) {
      if (p.fd >= 0) ::close(p.fd);
    }
  };
  for (const auto& e : entries_) {
    if (!e.text) continue;
    auto temp = write_temporary(e.target, e.path, *e.text, e.writer);
    if (!temp) {
      remove_from(0);
      close_all();
      return temp.err();
    }
    // Locks are held for the first kMaxHeldLocks files (a Monte Carlo --out-dir may write
    // thousands; each later one is unlocked at once, protected by its age alone).
    int fd = temp->second;
    if (pending.size() >= kMaxHeldLocks) {
      ::close(fd);
      fd = -1;
    }
    pending.push_back({temp->first, fd, &e});
  }
  pause_before_rename();
  for (std::size_t i = 0; i < pending.size(); ++i) {
    if (::rename(pending[i].temp.c_str(), pending[i].entry->target.c_str()) != 0) {
      const int e = errno;
      remove_from(i);
      close_all();
      return failure(truncate_token(pending[i].entry->path) +
                     ": cannot replace the file: " + errno_text(e));
    }
    sync_directory(directory_of(pending[i].entry->target));
  }
  close_all();
  return Ok{};
}

Status write_file_atomic(const std::string& path, std::string text) {
  OutputSet out;
  if (auto st = out.add(path); !st) return st;
  if (auto st = out.stage(path, std::move(text)); !st) return st;
  return out.commit();
}

}  // namespace kfw
