#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "ErrorOf.h"
#include "lidarseg/vision/FrameSource.h"
#include "lidarseg/vision/ImageFile.h"

namespace lidarseg::vision {
namespace {
namespace fs = std::filesystem;
const std::string kTmp = std::string(LIDARSEG_TEST_TMP_DIR) + "/image_file";

std::string bytesOf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

// A 40 x 30 test card in `ext`'s format.
std::string card(const std::string& ext) {
  fs::create_directories(kTmp);
  cv::Mat m(30, 40, CV_8UC3, cv::Scalar(10, 120, 230));
  cv::rectangle(m, {5, 5}, {20, 25}, cv::Scalar(0, 0, 0), cv::FILLED);
  if (ext == "pgm") cv::cvtColor(m, m, cv::COLOR_BGR2GRAY);
  // One file per test: CTest runs this binary's tests in parallel processes.
  const std::string path =
      kTmp + "/" + ::testing::UnitTest::GetInstance()->current_test_info()->name() + "_card." + ext;
  if (!cv::imwrite(path, m)) throw std::runtime_error("cannot write " + path);
  return path;
}

void putBigEndian(std::string& b, std::size_t at, std::uint32_t v, int n) {
  for (int i = n - 1; i >= 0; --i, v >>= 8) b[at + static_cast<std::size_t>(i)] = static_cast<char>(v & 0xFF);
}

// The offset of the first JPEG frame header (SOF0/SOF2) marker, found by walking segments.
std::size_t jpegFrameHeader(const std::string& b) {
  std::size_t i = 2;
  while (i + 4 < b.size()) {
    const auto m = static_cast<unsigned char>(b[i + 1]);
    if (m == 0xC0 || m == 0xC2) return i;
    i += 2 + (static_cast<unsigned char>(b[i + 2]) << 8 | static_cast<unsigned char>(b[i + 3]));
  }
  throw std::runtime_error("no SOF");
}

using lidarseg::testing::errorOf;

}  // namespace

TEST(ImageFile, HeadersGiveTheSizeOfEveryFormatWithoutDecoding) {
  for (const std::string ext : {"png", "jpg", "bmp", "ppm", "pgm"}) {
    const std::string path = card(ext);
    const auto h = readImageHeader(path);
    ASSERT_TRUE(h) << ext;
    EXPECT_EQ(h->width, 40u) << ext;
    EXPECT_EQ(h->height, 30u) << ext;
    const cv::Mat m = readImage(path);
    EXPECT_EQ(m.cols, 40) << ext;
    EXPECT_EQ(m.rows, 30) << ext;
    EXPECT_EQ(m.type(), CV_8UC3) << ext;
  }
  // PNM with comments between the numbers.
  const std::string pgm = kTmp + "/commented.pgm";
  writeBytes(pgm, "P5\n# a comment\n# another\n 7\t5 \n255\n" + std::string(35, '\x40'));
  const auto h = readImageHeader(pgm);
  ASSERT_TRUE(h);
  EXPECT_EQ(h->format, "PNM");
  EXPECT_EQ(h->width, 7u);
  EXPECT_EQ(h->height, 5u);
  EXPECT_EQ(readImage(pgm).cols, 7);
}

// Issue 16: a 20000 x 20000 header took 6 GB. The refusal names the file and the cap and
// comes from the header: the pixel data behind it is a 40 x 30 image (a decoder would fail
// on it only after allocating the declared size).
TEST(ImageFile, AHugeDeclaredSizeIsRefusedBeforeDecoding) {
  std::string png = bytesOf(card("png"));
  putBigEndian(png, 16, 20000, 4);
  putBigEndian(png, 20, 20000, 4);
  const std::string huge_png = kTmp + "/huge.png";
  writeBytes(huge_png, png);

  std::string jpg = bytesOf(card("jpg"));
  const std::size_t sof = jpegFrameHeader(jpg);
  putBigEndian(jpg, sof + 5, 20000, 2);  // height
  putBigEndian(jpg, sof + 7, 20000, 2);  // width
  const std::string huge_jpg = kTmp + "/huge.jpg";
  writeBytes(huge_jpg, jpg);

  std::string bmp = bytesOf(card("bmp"));
  putBigEndian(bmp, 18, 0x204E0000, 4);  // 20000, little-endian
  const std::string huge_bmp = kTmp + "/huge.bmp";
  writeBytes(huge_bmp, bmp);

  const std::string huge_pgm = kTmp + "/huge.pgm";
  writeBytes(huge_pgm, "P5\n20000 20000\n255\n" + std::string(100, '\0'));
  const std::string endless_pgm = kTmp + "/endless.pgm";
  writeBytes(endless_pgm, "P5\n99999999999999999999999 2\n255\n");

  for (const std::string& path : {huge_png, huge_jpg, huge_bmp, huge_pgm, endless_pgm}) {
    const std::string e = errorOf([&] { readImage(path); });
    EXPECT_NE(e.find("'" + path + "'"), std::string::npos) << e;
    EXPECT_NE(e.find("up to 8192 x 8192 pixels"), std::string::npos) << e;
    EXPECT_EQ(e.find("decode"), std::string::npos) << "decoded before the check: " << e;
  }
  EXPECT_NE(errorOf([&] { readImage(huge_png); }).find("PNG image of 20000 x 20000 pixels"), std::string::npos);
  EXPECT_NE(errorOf([&] { readImage(huge_jpg); }).find("JPEG image of 20000 x 20000 pixels"), std::string::npos);

  // Exactly at the cap: the header passes (the decoder then fails on the short data).
  putBigEndian(png, 16, 8192, 4);
  putBigEndian(png, 20, 8192, 4);
  writeBytes(huge_png, png);
  EXPECT_EQ(readImageHeader(huge_png)->width, 8192u);
}

TEST(ImageFile, CutOrUnknownFilesAreNamed) {
  const std::string png = bytesOf(card("png"));
  const std::string cut = kTmp + "/cut.png";
  writeBytes(cut, png.substr(0, 12));
  EXPECT_NE(errorOf([&] { readImage(cut); }).find("'" + cut + "': invalid PNG header"), std::string::npos)
      << errorOf([&] { readImage(cut); });
  const std::string jpg = bytesOf(card("jpg"));
  const std::string cut_jpg = kTmp + "/cut.jpg";
  writeBytes(cut_jpg, jpg.substr(0, jpegFrameHeader(jpg) + 3));
  EXPECT_NE(errorOf([&] { readImage(cut_jpg); }).find("'" + cut_jpg + "': invalid JPEG header"), std::string::npos)
      << errorOf([&] { readImage(cut_jpg); });
  const std::string zero = kTmp + "/zero.pgm";
  writeBytes(zero, "P5\n0 10\n255\n");
  EXPECT_NE(errorOf([&] { readImage(zero); }).find("0 x 10 pixels"), std::string::npos);
  const std::string text = kTmp + "/text.png";
  writeBytes(text, "not an image at all\n");
  EXPECT_FALSE(readImageHeader(text));
  EXPECT_NE(errorOf([&] { readImage(text); }).find("cannot read image '" + text + "'"), std::string::npos);
  EXPECT_NE(errorOf([&] { readImage(kTmp + "/absent.png"); }).find("absent.png"), std::string::npos);
  EXPECT_FALSE(readImageHeader(kTmp));  // a directory
  if (cv::haveImageWriter(kTmp + "/x.tiff")) {
    const std::string tiff = card("tiff");
    EXPECT_NE(errorOf([&] { readImage(tiff); }).find("size cannot be checked before decoding"), std::string::npos)
        << errorOf([&] { readImage(tiff); });
  }
}

namespace {

// A two-frame MJPEG video of w x h pixels; empty when this OpenCV cannot write one.
std::string mjpegVideo(const std::string& name, int w, int h) {
  fs::create_directories(kTmp);
  const std::string path = kTmp + "/" + name;
  cv::VideoWriter out(path, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10.0, cv::Size(w, h));
  if (!out.isOpened()) return {};
  for (int k = 0; k < 2; ++k) out.write(cv::Mat(h, w, CV_8UC3, cv::Scalar(40.0 * k, 80, 120)));
  return path;
}

}  // namespace

// Video frames are held to the image files' cap (issue 16): a video whose container declares
// frames beyond it is refused, naming it, before a frame is decoded.
TEST(ImageFile, AVideoWhoseFramesAreBeyondTheCapIsRefusedBeforeAnyIsDecoded) {
  const std::string small = mjpegVideo("small.avi", 64, 48);
  const std::string wide = mjpegVideo("wide.avi", 8200, 16);
  if (small.empty() || wide.empty()) GTEST_SKIP() << "this OpenCV cannot write an MJPEG video";
  FrameSource frames(small);
  cv::Mat frame;
  std::string file;
  std::size_t n = 0;
  while (frames.next(frame, file)) {
    EXPECT_EQ(frame.cols, 64);
    EXPECT_EQ(frame.rows, 48);
    ++n;
  }
  EXPECT_EQ(n, 2u);
  const std::string e = errorOf([&] { FrameSource refused(wide); });
  EXPECT_NE(e.find("'" + wide + "': video frames of 8200 x 16 pixels"), std::string::npos) << e;
  EXPECT_NE(e.find("up to 8192 x 8192 pixels"), std::string::npos) << e;
}

// A Motion-JPEG frame's size is its own JPEG header's, whatever the container declares: each
// frame is checked from that header before it is decoded (issue 16). Here the second frame of
// a 64 x 48 video declares 8200 x 16; FFmpeg could not decode it, and the video used to end
// there without a word.
TEST(ImageFile, AMotionJpegFrameBeyondTheCapIsRefusedFromItsHeaderBeforeItIsDecoded) {
  const std::string small = mjpegVideo("changing.avi", 64, 48);
  if (small.empty()) GTEST_SKIP() << "this OpenCV cannot write an MJPEG video";
  std::ifstream in(small, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  in.close();
  std::vector<std::size_t> frame_headers;  // SOF0 of each frame: FF C0, length, precision, height, width
  for (std::size_t i = 0; i + 9 < bytes.size(); ++i) {
    if (static_cast<unsigned char>(bytes[i]) == 0xFF && static_cast<unsigned char>(bytes[i + 1]) == 0xC0) {
      frame_headers.push_back(i);
    }
  }
  ASSERT_EQ(frame_headers.size(), 2u);
  const std::size_t sof = frame_headers[1];
  bytes[sof + 5] = 0, bytes[sof + 6] = 16;                                        // height 16
  bytes[sof + 7] = static_cast<char>(8200 / 256), bytes[sof + 8] = static_cast<char>(8200 % 256);  // width 8200
  const std::string changing = kTmp + "/changing-size.avi";
  std::ofstream(changing, std::ios::binary) << bytes;

  FrameSource frames(changing);  // the container declares 64 x 48
  cv::Mat frame;
  std::string file;
  ASSERT_TRUE(frames.next(frame, file));
  EXPECT_EQ(frame.cols, 64);
  const std::string e = errorOf([&] { frames.next(frame, file); });
  EXPECT_EQ(e, "'" + changing + "', frame 1: video frame of 8200 x 16 pixels; images are read from 1 x 1 up to "
                "8192 x 8192 pixels");
}

// The bytes of a Motion-JPEG video of `n` frames of 64 x 48, frame k of blue 40 k, and where
// each frame's markers `marker` (FF xx) are.
std::string mjpegFrames(const std::string& name, int n, unsigned char marker, std::vector<std::size_t>& at) {
  fs::create_directories(kTmp);
  const std::string path = kTmp + "/" + name;
  {
    cv::VideoWriter out(path, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10.0, cv::Size(64, 48));
    if (!out.isOpened()) return {};
    for (int k = 0; k < n; ++k) out.write(cv::Mat(48, 64, CV_8UC3, cv::Scalar(40.0 * k, 80, 120)));
  }
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  for (std::size_t i = 0; i + 1 < bytes.size(); ++i) {
    if (static_cast<unsigned char>(bytes[i]) == 0xFF && static_cast<unsigned char>(bytes[i + 1]) == marker) at.push_back(i);
  }
  return bytes;
}

// Reads every frame the source gives and returns their numbers; each frame must be the
// 64 x 48 test image of its own colour (blue 40 k for frame k; JPEG moves it by a few
// levels), so a grey-filled or out-of-step frame fails here.
std::vector<std::size_t> readFrameNumbers(FrameSource& frames) {
  cv::Mat frame;
  std::string file;
  std::vector<std::size_t> numbers;
  while (frames.next(frame, file)) {
    numbers.push_back(frames.frameIndex());
    EXPECT_EQ(frame.cols, 64);
    EXPECT_EQ(frame.rows, 48);
    EXPECT_NEAR(cv::mean(frame)[0], 40.0 * static_cast<double>(frames.frameIndex()), 6.0) << frames.frameIndex();
  }
  return numbers;
}

// A corrupt Motion-JPEG frame is skipped and counted with its number; the frames after it
// are the right ones, under their own numbers (issue 16: a corrupt packet could put the
// header check one frame behind the decoder, and FFmpeg's decoder ended the video there).
TEST(ImageFile, ACorruptMotionJpegFrameIsSkippedAndCountedAndTheNextFramesStayInStep) {
  std::vector<std::size_t> soi, sos;
  std::string bytes = mjpegFrames("corrupt.avi", 5, 0xD8, soi);
  if (bytes.empty()) GTEST_SKIP() << "this OpenCV cannot write an MJPEG video";
  mjpegFrames("corrupt.avi", 5, 0xDA, sos);
  ASSERT_EQ(soi.size(), 5u);
  ASSERT_EQ(sos.size(), 5u);
  bytes[soi[1] + 1] = 0x00;                       // frame 1: no JPEG start: not a JPEG image
  bytes[sos[3] + 1] = static_cast<char>(0xD9);    // frame 3: the image ends before its scan
  const std::string path = kTmp + "/corrupt-frames.avi";
  std::ofstream(path, std::ios::binary) << bytes;

  FrameSource frames(path);
  const std::vector<std::size_t> numbers = readFrameNumbers(frames);
  EXPECT_EQ(numbers, (std::vector<std::size_t>{0, 2, 4}));
  EXPECT_EQ(frames.skippedFrameCount(), 2u);
  ASSERT_EQ(frames.skippedFrames().size(), 2u);
  EXPECT_EQ(frames.skippedFrames()[0].rfind("'" + path + "', frame 1: not a Motion-JPEG frame", 0), 0u)
      << frames.skippedFrames()[0];
  EXPECT_EQ(frames.skippedFrames()[1], "'" + path + "', frame 3: its JPEG data cannot be decoded; frame skipped");
}

// A Motion-JPEG frame whose JPEG data is cut (here the second half of its scan, end-of-image
// marker included, zeroed as a recorder stopped mid-frame leaves it) is skipped and counted: OpenCV's
// imdecode filled the missing rows with grey and gave it as a whole frame (issue 16).
TEST(ImageFile, ATruncatedMotionJpegFrameIsSkippedAndCountedNotGreyFilled) {
  std::vector<std::size_t> sos, eoi;
  std::string bytes = mjpegFrames("truncated.avi", 4, 0xDA, sos);
  if (bytes.empty()) GTEST_SKIP() << "this OpenCV cannot write an MJPEG video";
  mjpegFrames("truncated.avi", 4, 0xD9, eoi);
  ASSERT_EQ(sos.size(), 4u);
  ASSERT_EQ(eoi.size(), 4u);
  ASSERT_LT(sos[2], eoi[2]);
  const std::size_t half = sos[2] + (eoi[2] + 2 - sos[2]) / 2;  // within the image's scan
  std::fill(bytes.begin() + static_cast<std::ptrdiff_t>(half), bytes.begin() + static_cast<std::ptrdiff_t>(eoi[2] + 2), '\0');
  const std::string path = kTmp + "/truncated-frame.avi";
  std::ofstream(path, std::ios::binary) << bytes;

  FrameSource frames(path);
  const std::vector<std::size_t> numbers = readFrameNumbers(frames);
  EXPECT_EQ(numbers, (std::vector<std::size_t>{0, 1, 3}));
  EXPECT_EQ(frames.skippedFrameCount(), 1u);
  ASSERT_EQ(frames.skippedFrames().size(), 1u);
  EXPECT_EQ(frames.skippedFrames()[0], "'" + path + "', frame 2: its JPEG data is truncated; frame skipped");
}

// A corrupt frame before one beyond the cap: the oversize frame is refused under its own number.
TEST(ImageFile, AnOversizeFrameAfterACorruptOneIsRefusedUnderItsOwnNumber) {
  std::vector<std::size_t> soi, sof;
  std::string bytes = mjpegFrames("corrupt-then-wide.avi", 4, 0xD8, soi);
  if (bytes.empty()) GTEST_SKIP() << "this OpenCV cannot write an MJPEG video";
  mjpegFrames("corrupt-then-wide.avi", 4, 0xC0, sof);
  ASSERT_EQ(sof.size(), 4u);
  bytes[soi[1] + 1] = 0x00;  // frame 1 corrupt
  bytes[sof[2] + 5] = 0, bytes[sof[2] + 6] = 16;  // frame 2 declares 8200 x 16
  bytes[sof[2] + 7] = static_cast<char>(8200 / 256), bytes[sof[2] + 8] = static_cast<char>(8200 % 256);
  const std::string path = kTmp + "/corrupt-then-wide-frames.avi";
  std::ofstream(path, std::ios::binary) << bytes;
  FrameSource frames(path);
  cv::Mat frame;
  std::string file;
  ASSERT_TRUE(frames.next(frame, file));
  EXPECT_EQ(frames.frameIndex(), 0u);
  EXPECT_EQ(errorOf([&] { frames.next(frame, file); }),
            "'" + path + "', frame 2: video frame of 8200 x 16 pixels; images are read from 1 x 1 up to 8192 x 8192 pixels");
  EXPECT_EQ(frames.skippedFrameCount(), 1u);
}

// The end-of-image check walks the JPEG's markers: bytes after a whole image do not make it
// cut, and a thumbnail's end marker inside an APP1 segment does not make a cut image whole.
TEST(ImageFile, AJpegStreamIsWholeOnlyWhenItsOwnScanReachesTheEndMarker) {
  cv::Mat gradient(48, 64, CV_8UC1);
  for (int r = 0; r < gradient.rows; ++r) {
    for (int c = 0; c < gradient.cols; ++c) gradient.at<unsigned char>(r, c) = static_cast<unsigned char>(3 * r + 2 * c);
  }
  std::vector<unsigned char> jpeg;
  ASSERT_TRUE(cv::imencode(".jpg", gradient, jpeg));
  const auto whole = [](const std::vector<unsigned char>& v) { return reachesJpegEnd(v.data(), v.size()); };
  EXPECT_TRUE(whole(jpeg));
  std::vector<unsigned char> padded = jpeg;
  padded.insert(padded.end(), {0x00, 0x00, 0x12, 0x34, 0xFF});  // a container's or camera's padding
  EXPECT_TRUE(whole(padded));
  const std::vector<unsigned char> cut(jpeg.begin(), jpeg.begin() + static_cast<std::ptrdiff_t>(jpeg.size() - 40));
  EXPECT_FALSE(whole(cut));
  std::vector<unsigned char> zeroed = jpeg;  // the end marker overwritten
  zeroed[zeroed.size() - 2] = zeroed[zeroed.size() - 1] = 0;
  EXPECT_FALSE(whole(zeroed));
  // A whole JPEG (a thumbnail) inside an APP1 segment, then the cut image.
  std::vector<unsigned char> with_thumbnail{0xFF, 0xD8, 0xFF, 0xE1};
  const std::size_t app1 = jpeg.size() + 2;
  with_thumbnail.push_back(static_cast<unsigned char>(app1 >> 8));
  with_thumbnail.push_back(static_cast<unsigned char>(app1 & 0xFF));
  with_thumbnail.insert(with_thumbnail.end(), jpeg.begin(), jpeg.end());
  with_thumbnail.insert(with_thumbnail.end(), cut.begin() + 2, cut.end());  // after its SOI
  EXPECT_FALSE(whole(with_thumbnail));
  std::vector<unsigned char> thumbnail_and_whole(with_thumbnail.begin(), with_thumbnail.begin() + static_cast<std::ptrdiff_t>(6 + jpeg.size()));
  thumbnail_and_whole.insert(thumbnail_and_whole.end(), jpeg.begin() + 2, jpeg.end());
  EXPECT_TRUE(whole(thumbnail_and_whole));
  cv::Mat decoded = cv::imdecode(thumbnail_and_whole, cv::IMREAD_GRAYSCALE);  // a valid stream indeed
  EXPECT_EQ(decoded.cols, 64);
  EXPECT_FALSE(reachesJpegEnd(jpeg.data(), 3));
  EXPECT_FALSE(reachesJpegEnd(nullptr, 0));
}

TEST(ImageFile, TheCapIsOneToMaxOnEachSide) {
  EXPECT_NO_THROW(requireImageSize(1, 1, "w", "x"));
  EXPECT_NO_THROW(requireImageSize(kMaxImageSidePx, kMaxImageSidePx, "w", "x"));
  EXPECT_EQ(errorOf([] { requireImageSize(0, 5, "'v.avi', frame 3", "video frame"); }),
            "'v.avi', frame 3: video frame of 0 x 5 pixels; images are read from 1 x 1 up to 8192 x 8192 pixels");
  EXPECT_NE(errorOf([] { requireImageSize(5, kMaxImageSidePx + 1, "w", "x"); }), "(no error)");
}

}  // namespace lidarseg::vision
