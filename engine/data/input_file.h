// The one input policy for every file the programs read (data, preset, model, mapping, session,
// Monte Carlo and sweep parts), CLI and GUI alike: regular files only — a FIFO, device, socket or
// directory is refused at once, without blocking on it — and at most the kind's byte cap
// (core/limits.h), checked before reading and while reading.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>

#include "core/expected.h"
#include "core/limits.h"

namespace kfw {

// The whole file. `max_line` > 0: stops early once a line is longer (the parser refuses it).
Expected<std::string> read_input_file(const std::string& path, limits::Input kind,
                                      std::size_t max_line = 0);

// A data file's bytes, memory-mapped where the file allows it (a regular file of at least
// kMapMinBytes whose size is the same after mapping), else read into memory. A mapping is
// registered with a SIGBUS guard for its whole life: a page past the end of a file truncated by
// another program reads as zeros instead of killing the process, and changed() turns that into
// an error naming the file (docs/limits.md "Memory maps").
class InputBytes {
 public:
  static constexpr std::size_t kMapMinBytes = std::size_t{1} << 20;
  // The file under the input policy and the kind's byte cap (read_input_file's checks).
  static Expected<std::shared_ptr<const InputBytes>> open(const std::string& path,
                                                          limits::Input kind,
                                                          std::size_t max_line = 0);
  static std::shared_ptr<const InputBytes> of(std::string text);
  ~InputBytes();
  InputBytes(const InputBytes&) = delete;
  InputBytes& operator=(const InputBytes&) = delete;
  std::string_view view() const { return {data_, size_}; }
  bool mapped() const { return map_ != nullptr; }
  // The mapped file shrank while mapped (the guard replaced a page with zeros).
  bool changed() const;

 private:
  InputBytes() = default;
  std::string owned_;
  const char* data_ = nullptr;
  std::size_t size_ = 0;
  void* map_ = nullptr;
  std::size_t map_size_ = 0;
  int slot_ = -1;
};

// Opens the file for reading under the policy (not the byte cap): a descriptor the caller closes.
Expected<int> open_input_file(const std::string& path, limits::Input kind);

}  // namespace kfw
