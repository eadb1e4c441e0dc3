// InputBytes (data/input_file.h): a data file mapped read-only, and the SIGBUS guard that makes a
// file truncated under the mapping an error instead of a crash.
#include <signal.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cstdint>
#include <mutex>
#include <system_error>

#include "core/suggest.h"
#include "data/input_file.h"

namespace kfw {

namespace {

// The live mappings the guard knows: [begin, end) and whether a fault was repaired in it.
struct GuardSlot {
  std::atomic<std::uintptr_t> begin{0}, end{0};
  std::atomic<bool> faulted{false};
};
constexpr std::size_t kGuardSlots = 64;
std::array<GuardSlot, kGuardSlots> g_slots;
struct sigaction g_previous {};
std::once_flag g_install;

void call_previous(int sig, siginfo_t* info, void* ctx) {
  if (g_previous.sa_flags & SA_SIGINFO) {
    if (g_previous.sa_sigaction) g_previous.sa_sigaction(sig, info, ctx);
    return;
  }
  if (g_previous.sa_handler == SIG_IGN) return;
  if (g_previous.sa_handler != SIG_DFL && g_previous.sa_handler) {
    g_previous.sa_handler(sig);
    return;
  }
  ::signal(sig, SIG_DFL);  // the default action: the fault repeats on return and kills
}

// Async-signal-safe: atomics, mmap (a system call) and nothing else.
extern "C" void on_sigbus(int sig, siginfo_t* info, void* ctx) {
  const auto addr = reinterpret_cast<std::uintptr_t>(info->si_addr);
  for (auto& s : g_slots) {
    const std::uintptr_t b = s.begin.load(std::memory_order_acquire);
    if (b == 0 || addr < b || addr >= s.end.load(std::memory_order_acquire)) continue;
    const auto page = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
    void* at = reinterpret_cast<void*>(addr & ~(page - 1));
    if (::mmap(at, page, PROT_READ, MAP_PRIVATE | MAP_ANONYMOUS | MAP_FIXED, -1, 0) != MAP_FAILED) {
      s.faulted.store(true, std::memory_order_release);
      return;  // the read restarts and sees zeros
    }
  }
  call_previous(sig, info, ctx);
}

void install_guard() {
  struct sigaction sa {};
  sa.sa_sigaction = on_sigbus;
  sa.sa_flags = SA_SIGINFO | SA_NODEFER;
  sigemptyset(&sa.sa_mask);
  ::sigaction(SIGBUS, &sa, &g_previous);
}

int claim_slot(const void* p, std::size_t n) {
  std::call_once(g_install, install_guard);
  for (std::size_t i = 0; i < kGuardSlots; ++i) {
    std::uintptr_t expected = 0;
    const auto b = reinterpret_cast<std::uintptr_t>(p);
    if (g_slots[i].begin.compare_exchange_strong(expected, b)) {
      g_slots[i].faulted.store(false);
      g_slots[i].end.store(b + n, std::memory_order_release);
      return static_cast<int>(i);
    }
  }
  return -1;  // every slot in use: the caller reads the file instead
}

}  // namespace

std::shared_ptr<const InputBytes> InputBytes::of(std::string text) {
  std::shared_ptr<InputBytes> b(new InputBytes);
  b->owned_ = std::move(text);
  b->data_ = b->owned_.data();
  b->size_ = b->owned_.size();
  return b;
}

Expected<std::shared_ptr<const InputBytes>> InputBytes::open(const std::string& path,
                                                             limits::Input kind,
                                                             std::size_t max_line) {
  auto fd = open_input_file(path, kind);
  if (!fd) return fd.err();
  struct stat st {};
  ::fstat(*fd, &st);
  const auto size = static_cast<std::uint64_t>(st.st_size);
  if (size < kMapMinBytes || size > limits::max_bytes(kind)) {
    ::close(*fd);  // small files are read; read_input_file says what is too big
    auto text = read_input_file(path, kind, max_line);
    if (!text) return text.err();
    return of(std::move(*text));
  }
  void* map = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE | MAP_POPULATE, *fd, 0);
  struct stat after {};
  const bool same = ::fstat(*fd, &after) == 0 && static_cast<std::uint64_t>(after.st_size) == size;
  ::close(*fd);
  if (map == MAP_FAILED) {
    auto text = read_input_file(path, kind, max_line);
    if (!text) return text.err();
    return of(std::move(*text));
  }
  if (!same) {
    ::munmap(map, size);
    return Error{truncate_token(path) +
                 ": the file changed size while being opened; read it "
                 "again when whatever writes it has finished"};
  }
  const int slot = claim_slot(map, size);
  if (slot < 0) {
    ::munmap(map, size);
    auto text = read_input_file(path, kind, max_line);
    if (!text) return text.err();
    return of(std::move(*text));
  }
  ::madvise(map, size, MADV_SEQUENTIAL);
  std::shared_ptr<InputBytes> b(new InputBytes);
  b->map_ = map;
  b->map_size_ = size;
  b->data_ = static_cast<const char*>(map);
  b->size_ = size;
  b->slot_ = slot;
  return std::shared_ptr<const InputBytes>(std::move(b));
}

bool InputBytes::changed() const {
  return slot_ >= 0 && g_slots[static_cast<std::size_t>(slot_)].faulted.load();
}

InputBytes::~InputBytes() {
  if (!map_) return;
  auto& s = g_slots[static_cast<std::size_t>(slot_)];  // released before the range can be reused
  s.end.store(0, std::memory_order_release);
  s.begin.store(0, std::memory_order_release);
  ::munmap(map_, map_size_);
}

}  // namespace kfw
