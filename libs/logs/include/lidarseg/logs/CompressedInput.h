#pragma once
/// @file CompressedInput.h
/// A file's bytes, gunzipped when it is gzip-compressed (detected from its first bytes),
/// every member of a multi-member file in turn, and nothing after the last one lost
/// silently.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace lidarseg::logs {

/// Reads a plain or gzip-compressed file. zlib's gzread() stops without an error at bytes
/// after a member that are not another member's header (a damaged second member, garbage
/// appended) and at a member cut inside its header: the rest of the log was dropped without
/// a word. Here a gzip file is whole or an error: every member decompressed and checked
/// (CRC, size), and anything after the last member other than zero padding refused.
class CompressedInput {
 public:
  /// @throws std::runtime_error naming the file (with the system's reason) when it cannot
  /// be opened.
  explicit CompressedInput(const std::string& path);
  ~CompressedInput();
  CompressedInput(const CompressedInput&) = delete;
  CompressedInput& operator=(const CompressedInput&) = delete;

  /// Up to `n` bytes of the (decompressed) content into `out`; 0 at the end.
  /// @throws std::runtime_error with the reason only (the caller names the place) for a
  /// corrupt, truncated or trailing-garbage gzip file, or a read error.
  std::size_t read(char* out, std::size_t n);
  /// Bytes of the file itself used so far (compressed bytes of a gzip file; read ahead but
  /// not yet used, not counted).
  std::uint64_t fileBytesRead() const { return file_read_ - (in_end_ - in_begin_); }
  /// Whether the file is gzip-compressed.
  bool gzip() const { return gzip_; }

  /// The reason a gzip file is not whole (read through once), or empty when it is whole or
  /// not compressed.
  static std::string problemOf(const std::string& path);

 private:
  bool refill();              // more file bytes into in_; false at the file's end
  std::size_t readMembers(char* out, std::size_t n);
  std::FILE* file_ = nullptr;
  bool gzip_ = false;
  bool file_end_ = false;
  std::uint64_t file_read_ = 0;
  std::vector<unsigned char> in_;
  std::size_t in_begin_ = 0, in_end_ = 0;
  struct Stream;
  std::unique_ptr<Stream> z_;
  bool in_member_ = false;
};

}  // namespace lidarseg::logs
