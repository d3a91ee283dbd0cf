// GzipOutputStream: what it writes is the gzip file zlib reads back, and a write that fails,
// in the middle or only in the stream's end written by close(), throws naming the file.
#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/serialization/CArchive.h>
#include <zlib.h>

#include "FileSizeLimit.h"
#include "lidarseg/mrpt/GzipOutputStream.h"
#include "lidarseg/mrpt/RawlogScanReader.h"

namespace lidarseg::mrpt_adapter {
namespace {
namespace fs = std::filesystem;

const std::string kTmp = std::string(LIDARSEG_TEST_TMP_DIR) + "/gzip-output-stream";

std::string tmp(const std::string& name) {
  fs::create_directories(kTmp);
  return kTmp + "/" + name;
}

// `n` bytes that deflate cannot shrink.
std::string randomBytes(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::string out(n, '\0');
  for (char& c : out) c = static_cast<char>(rng() & 0xff);
  return out;
}

// The file read back with zlib; `error` is zlib's message when the stream is not whole.
std::string gunzipFile(const std::string& path, std::string& error) {
  gzFile g = gzopen(path.c_str(), "rb");
  if (g == nullptr) {
    error = "cannot open";
    return {};
  }
  std::string out;
  std::vector<char> buffer(1 << 16);
  int n = 0;
  while ((n = gzread(g, buffer.data(), static_cast<unsigned>(buffer.size()))) > 0) out.append(buffer.data(), n);
  int code = Z_OK;
  const char* message = gzerror(g, &code);
  error = (n < 0 || (code != Z_OK && code != Z_STREAM_END)) ? std::string(message) : std::string();
  gzclose(g);
  return out;
}

TEST(GzipOutputStream, WritesTheGzipFileZlibReadsBack) {
  const std::string path = tmp("round_trip.gz");
  // Pieces of several sizes, more than one output buffer of incompressible bytes in all.
  const std::string text = std::string(100000, 'a') + randomBytes(3 * GzipOutputStream::kBufferBytes, 7) + "end";
  {
    GzipOutputStream out(path);
    std::size_t at = 0;
    for (std::size_t piece : {std::size_t{1}, std::size_t{10}, std::size_t{99989}, text.size()}) {
      const std::size_t n = std::min(piece, text.size() - at);
      EXPECT_EQ(out.Write(text.data() + at, n), n);
      at += n;
    }
    ASSERT_EQ(at, text.size());
    EXPECT_EQ(out.getTotalBytesCount(), text.size());
    out.close();
    EXPECT_NO_THROW(out.close()) << "closing twice is harmless";
    EXPECT_TRUE(out.failure().empty());
  }
  std::string error;
  EXPECT_EQ(gunzipFile(path, error), text);  // zlib checks the trailer's CRC-32 and size
  EXPECT_EQ(error, "");
}

// A write after close() is refused naming the file, and leaves the stream closed and its
// file whole: a second close() does nothing (it threw "the stream is closed", the write's
// refusal recorded as the stream's failure; issue 16).
TEST(GzipOutputStream, AWriteAfterCloseIsRefusedNamingTheFileAndASecondCloseDoesNothing) {
  const std::string path = tmp("write_after_close.gz");
  const std::string text = "the whole text";
  GzipOutputStream out(path, "named.gz");
  out.Write(text.data(), text.size());
  out.close();
  try {
    out.Write("more", 4);
    ADD_FAILURE() << "a write after close() was accepted";
  } catch (const std::logic_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("cannot write 'named.gz': the stream is closed", 0), 0u) << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not a std::logic_error: " << e.what();
  }
  EXPECT_NO_THROW(out.close()) << "a second close() does nothing";
  EXPECT_TRUE(out.failure().empty()) << out.failure();
  EXPECT_EQ(out.getTotalBytesCount(), text.size());
  std::string error;
  EXPECT_EQ(gunzipFile(path, error), text);
  EXPECT_EQ(error, "");
}

TEST(GzipOutputStream, ARawlogWrittenThroughItIsReadBack) {
  const std::string path = tmp("odometry.rawlog");
  {
    GzipOutputStream out(path, "", 1);
    auto archive = mrpt::serialization::archiveFrom(out);
    for (int i = 0; i < 50; ++i) {
      mrpt::obs::CObservationOdometry odo;
      odo.sensorLabel = "ODOMETRY";
      odo.odometry = mrpt::poses::CPose2D(0.1 * i, 0.0, 0.0);
      archive << odo;
    }
    out.close();
  }
  RawlogScanReader reader(path);
  EXPECT_FALSE(reader.next().has_value()) << "no laser scan in the log";
  EXPECT_EQ(reader.entriesRead(), 50u);
}

using lidarseg::testing::inChildWithFileSizeLimit;

// The whole compressed file (about 20 KB) fits in the stream's buffer: every Write() succeeds
// and only the end of the stream, written by close(), meets the 4 KiB limit. MRPT's
// CFileGZOutputStream::close() ignored this failure and left a short file looking written.
TEST(GzipOutputStream, AFailureInTheStreamsEndIsReportedByClose) {
  const std::string path = tmp("end_fails.gz");
  const std::string bytes = randomBytes(20000, 3);
  ASSERT_LT(bytes.size() + 100, GzipOutputStream::kBufferBytes);
  const int code = inChildWithFileSizeLimit(4096, [&] {
    GzipOutputStream out(path, "published.rawlog");
    try {
      out.Write(bytes.data(), bytes.size());
    } catch (...) {
      return 10;  // failed too early for this test
    }
    try {
      out.close();
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      if (what != "cannot write 'published.rawlog': " + std::string(std::strerror(EFBIG))) return 11;
      if (out.failure() != std::strerror(EFBIG)) return 12;
      try {
        out.Write("x", 1);
      } catch (const std::runtime_error&) {
        return 0;  // a failed stream refuses later writes
      }
      return 13;
    }
    return 14;  // close() said nothing
  });
  EXPECT_EQ(code, 0) << "10: Write failed; 11: message; 12: failure(); 13: a later write accepted; 14: no error";
  std::string error;
  gunzipFile(path, error);
  EXPECT_NE(error, "") << "the file on disk is short: zlib must see it";
}

// More than the buffer of incompressible bytes: the write that meets the limit throws.
TEST(GzipOutputStream, AFailingWriteThrowsNamingTheFile) {
  const std::string path = tmp("write_fails.gz");
  const std::string bytes = randomBytes(4 * GzipOutputStream::kBufferBytes, 5);
  const int code = inChildWithFileSizeLimit(GzipOutputStream::kBufferBytes / 2, [&] {
    GzipOutputStream out(path, "named.gz");
    try {
      out.Write(bytes.data(), bytes.size());
    } catch (const std::runtime_error& e) {
      return std::string(e.what()).rfind("cannot write 'named.gz': ", 0) == 0 ? 0 : 11;
    }
    return 14;
  });
  EXPECT_EQ(code, 0) << "11: message; 14: no error";
}

TEST(GzipOutputStream, AFileThatCannotBeCreatedIsAnErrorNamingIt) {
  const std::string path = tmp("no-such-folder/x.gz");
  try {
    GzipOutputStream out(path);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot write '" + path + "': "), std::string::npos) << e.what();
  }
  EXPECT_THROW(GzipOutputStream(tmp("level.gz"), "", 10), std::invalid_argument);
}

}  // namespace
}  // namespace lidarseg::mrpt_adapter
