#pragma once
/// @file FuzzInput.h
/// Helpers shared by the libFuzzer targets (docs/reliability.md): the input as a file, the
/// error-message contract, and a reader of numbers from the input bytes.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <stdexcept>
#include <string>
#include <unistd.h>

namespace lidarseg::fuzz {

/// Writes the input to a file of this process (the readers under test take paths) and
/// returns its path. `name` ends the file name, so that format detection by name works.
inline std::string writeInput(const std::uint8_t* data, std::size_t size, const std::string& name) {
  const char* dir = std::getenv("TMPDIR");
  const std::string path = std::string(dir && *dir ? dir : "/tmp") + "/lidarseg-fuzz-" +
                           std::to_string(::getpid()) + "-" + name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (size > 0) out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  out.close();
  if (!out) {
    std::fprintf(stderr, "fuzz harness: cannot write %s\n", path.c_str());
    std::abort();
  }
  return path;
}

/// The contract of every reader: an error message names the input (its path). A message
/// that does not is a finding: abort so that libFuzzer keeps the input.
inline void requireNamed(const std::exception& e, const std::string& path) {
  const std::string what = e.what();
  if (what.find(path) == std::string::npos) {
    std::fprintf(stderr, "error message does not name the file %s: %s\n", path.c_str(), what.c_str());
    std::abort();
  }
}

/// Runs `read` on the input at `path`: the errors a reader may throw
/// (std::runtime_error, std::invalid_argument) must name the file; any other exception
/// escapes and libFuzzer reports it.
template <typename Read>
void expectNamedErrors(const std::string& path, Read&& read) {
  try {
    read();
  } catch (const std::runtime_error& e) {
    requireNamed(e, path);
  } catch (const std::invalid_argument& e) {
    requireNamed(e, path);
  }
}

/// A finding when `condition` is false.
inline void require(bool condition, const char* what) {
  if (!condition) {
    std::fprintf(stderr, "invariant violated: %s\n", what);
    std::abort();
  }
}

/// Reads small integers and doubles from the front of the input; zeros once it is used up.
class ByteReader {
 public:
  ByteReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint8_t u8() { return pos_ < size_ ? data_[pos_++] : 0; }
  std::uint16_t u16() { return static_cast<std::uint16_t>(u8() | (u8() << 8)); }
  /// A value in [lo, hi], in 256 steps.
  double in(double lo, double hi) { return lo + (hi - lo) * u8() / 255.0; }
  std::size_t remaining() const { return size_ - pos_; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

}  // namespace lidarseg::fuzz
