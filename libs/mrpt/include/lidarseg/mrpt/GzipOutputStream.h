#pragma once
/// @file GzipOutputStream.h
/// A gzip file written as an MRPT stream, every write, the end of the stream and the close
/// checked (issue 16: a rawlog is never published short).

#include <cstdint>
#include <memory>
#include <string>

#include <mrpt/io/CStream.h>

namespace lidarseg::mrpt_adapter {

/// Writes a gzip file (one member, RFC 1952) through zlib's deflate, for
/// `mrpt::serialization::archiveFrom()`. Unlike `mrpt::io::CFileGZOutputStream`, whose
/// close() ignores whether the end of the compressed stream and its trailer (CRC-32 and
/// size) reached the file, every step is checked: a failing write() (disk full, file size
/// limit), the last bytes and the trailer written by close(), `fsync` and `close` each throw
/// `std::runtime_error` "cannot write 'NAME': REASON". After a failure the stream refuses
/// every further write with the same message (failure()); the file is then incomplete and
/// its owner removes it. Not copyable; single-threaded.
class GzipOutputStream : public mrpt::io::CStream {
 public:
  /// Output buffer of compressed bytes written to the file at once (bytes).
  static constexpr std::size_t kBufferBytes = std::size_t{1} << 16;

  /// Creates (or truncates) `path`.
  /// @param path the file written.
  /// @param name how messages name the file (a temporary file's published name); `path` when empty.
  /// @param level deflate level, 0 (stored) to 9; 1 as MRPT's own tools write rawlogs.
  /// @throws std::runtime_error "cannot write 'NAME': REASON" when the file cannot be created;
  ///         std::invalid_argument for a level outside [0, 9].
  explicit GzipOutputStream(const std::string& path, const std::string& name = {}, int level = 1);
  /// Closes the file if close() was not called, without checking (an error path: the owner
  /// removes the incomplete file).
  ~GzipOutputStream() override;
  GzipOutputStream(const GzipOutputStream&) = delete;
  GzipOutputStream& operator=(const GzipOutputStream&) = delete;

  /// Compresses `count` bytes; writes compressed bytes to the file whenever kBufferBytes of
  /// them are ready. @return `count`.
  /// @throws std::runtime_error naming the file when writing fails or failed before;
  ///         std::logic_error "cannot write 'NAME': the stream is closed …" after a
  ///         successful close(), which leaves the file and the stream as they were (a later
  ///         close() still does nothing).
  std::size_t Write(const void* buffer, std::size_t count) override;
  /// Not readable: throws std::logic_error.
  std::size_t Read(void* buffer, std::size_t count) override;
  /// Not seekable: throws std::logic_error.
  std::uint64_t Seek(std::int64_t offset, mrpt::io::CStream::TSeekOrigin origin = sFromBeginning) override;
  /// Uncompressed bytes written so far.
  std::uint64_t getTotalBytesCount() const override;
  /// Uncompressed bytes written so far (the stream only appends).
  std::uint64_t getPosition() const override;
  std::string getStreamDescription() const override;

  /// Ends the compressed stream (its last blocks and the trailer), writes them, syncs the file
  /// to its disk (`fsync`) and closes it. Does nothing when already closed successfully,
  /// whatever was attempted since (a refused write after close()); after a failure it
  /// throws that failure again.
  /// @throws std::runtime_error "cannot write 'NAME': REASON" when any of it fails (disk full
  ///         or file size limit reached by the last bytes, an I/O error reported by fsync or
  ///         close), or when a write failed before.
  void close();

  /// The reason of the first failure ("" while none), e.g. "File too large".
  const std::string& failure() const { return failure_; }
  /// The file's name in messages.
  const std::string& name() const { return name_; }

 private:
  struct Deflater;
  [[noreturn]] void fail(const std::string& reason);
  void drain(bool finish);       // deflates the pending input; writes full buffers (all at finish)
  void writeOut(const unsigned char* data, std::size_t size);
  std::string name_;
  int fd_ = -1;
  std::unique_ptr<Deflater> z_;
  std::uint64_t written_ = 0;    // uncompressed bytes
  std::string failure_;
};

}  // namespace lidarseg::mrpt_adapter
