#include "lidarseg/vision/ImageFile.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <opencv2/imgcodecs.hpp>

namespace lidarseg::vision {

namespace {

// A PNM header (magic, width, height, comments) longer than this is not one.
constexpr std::size_t kMaxPnmHeaderBytes = 4096;
// Digits of a PNM dimension kept before it is taken as "too large" anyway.
constexpr std::size_t kMaxPnmDigits = 12;

[[noreturn]] void invalid(const std::string& path, const std::string& format, const std::string& what) {
  throw std::runtime_error("'" + path + "': invalid " + format + " header (" + what + ")");
}

std::uint64_t bigEndian(const unsigned char* b, int n) {
  std::uint64_t v = 0;
  for (int i = 0; i < n; ++i) v = (v << 8) | b[i];
  return v;
}

std::uint64_t littleEndian(const unsigned char* b, int n) {
  std::uint64_t v = 0;
  for (int i = n - 1; i >= 0; --i) v = (v << 8) | b[i];
  return v;
}

// PNG: signature, then the IHDR chunk (length, "IHDR", width, height, ...).
ImageHeader pngHeader(const std::string& path, const std::vector<unsigned char>& b) {
  if (b.size() < 24) invalid(path, "PNG", "cut before the end of IHDR");
  if (b[12] != 'I' || b[13] != 'H' || b[14] != 'D' || b[15] != 'R') invalid(path, "PNG", "the first chunk is not IHDR");
  return {"PNG", bigEndian(&b[16], 4), bigEndian(&b[20], 4)};
}

// BMP: file header (14 bytes), then the DIB header whose size says its layout.
ImageHeader bmpHeader(const std::string& path, const std::vector<unsigned char>& b) {
  if (b.size() < 26) invalid(path, "BMP", "cut before the image size");
  const std::uint64_t dib = littleEndian(&b[14], 4);
  if (dib == 12) return {"BMP", littleEndian(&b[18], 2), littleEndian(&b[20], 2)};  // OS/2 core header
  const auto w = static_cast<std::int32_t>(littleEndian(&b[18], 4));
  const auto h = static_cast<std::int32_t>(littleEndian(&b[22], 4));  // negative: stored top-down
  if (w < 0) invalid(path, "BMP", "negative width");
  const std::int64_t abs_h = h < 0 ? -static_cast<std::int64_t>(h) : h;
  return {"BMP", static_cast<std::uint64_t>(w), static_cast<std::uint64_t>(abs_h)};
}

// PNM (P1..P6): magic, then width and height as decimal text, with # comments between.
ImageHeader pnmHeader(const std::string& path, const std::vector<unsigned char>& b) {
  std::size_t i = 2;
  std::array<std::uint64_t, 2> dims{};
  for (std::uint64_t& d : dims) {
    while (i < b.size() && (std::isspace(b[i]) || b[i] == '#')) {
      if (b[i] == '#') {
        while (i < b.size() && b[i] != '\n' && b[i] != '\r') ++i;
      } else {
        ++i;
      }
    }
    const std::size_t start = i;
    while (i < b.size() && std::isdigit(b[i])) {
      // Beyond kMaxPnmDigits the value is already far above any cap: keep it saturated.
      if (i - start < kMaxPnmDigits) d = d * 10 + static_cast<std::uint64_t>(b[i] - '0');
      ++i;
    }
    if (i == start || i >= b.size()) invalid(path, "PNM", "no width and height in its first " + std::to_string(b.size()) + " bytes");
  }
  return {"PNM", dims[0], dims[1]};
}

bool isJpegFrameMarker(unsigned char m) {
  // SOF0..SOF15 except DHT (C4), JPG (C8) and DAC (CC).
  return m >= 0xC0 && m <= 0xCF && m != 0xC4 && m != 0xC8 && m != 0xCC;
}

// JPEG: the segments after SOI up to the first frame header (SOFn), whose height and width
// the decoder uses; each segment is skipped by its length, so the walk is linear in the file.
ImageHeader jpegHeader(const std::string& path, std::istream& in) {
  in.clear();
  in.seekg(2);
  while (true) {
    int c = in.get();
    if (c != 0xFF) invalid(path, "JPEG", c == EOF ? "no frame header before the end" : "a segment without its marker");
    while (c == 0xFF) c = in.get();  // fill bytes
    if (c == EOF) invalid(path, "JPEG", "no frame header before the end");
    const auto marker = static_cast<unsigned char>(c);
    if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD8)) continue;  // no length
    if (marker == 0xD9 || marker == 0xDA) invalid(path, "JPEG", "no frame header before the image data");
    std::array<unsigned char, 7> s{};
    in.read(reinterpret_cast<char*>(s.data()), 2);
    if (in.gcount() != 2) invalid(path, "JPEG", "cut inside a segment");
    const std::uint64_t length = bigEndian(s.data(), 2);
    if (length < 2) invalid(path, "JPEG", "a segment shorter than its length field");
    if (isJpegFrameMarker(marker)) {
      in.read(reinterpret_cast<char*>(s.data() + 2), 5);  // precision, height, width
      if (length < 7 || in.gcount() != 5) invalid(path, "JPEG", "cut inside the frame header");
      return {"JPEG", bigEndian(&s[5], 2), bigEndian(&s[3], 2)};
    }
    in.seekg(static_cast<std::streamoff>(length - 2), std::ios::cur);
    if (!in) invalid(path, "JPEG", "cut inside a segment");
  }
}

}  // namespace

ImageHeader readJpegHeader(const std::string& bytes, const std::string& name) {
  if (bytes.size() < 3 || static_cast<unsigned char>(bytes[0]) != 0xFF || static_cast<unsigned char>(bytes[1]) != 0xD8 ||
      static_cast<unsigned char>(bytes[2]) != 0xFF) {
    invalid(name, "JPEG", "no start of image");
  }
  std::istringstream in(bytes);
  return jpegHeader(name, in);
}

std::optional<ImageHeader> readImageHeader(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return std::nullopt;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open image '" + path + "'");
  std::vector<unsigned char> b(kMaxPnmHeaderBytes);
  in.read(reinterpret_cast<char*>(b.data()), static_cast<std::streamsize>(b.size()));
  b.resize(static_cast<std::size_t>(in.gcount()));
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  if (b.size() >= 8 && std::equal(kPng, kPng + 8, b.begin())) return pngHeader(path, b);
  if (b.size() >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF) return jpegHeader(path, in);
  if (b.size() >= 2 && b[0] == 'B' && b[1] == 'M') return bmpHeader(path, b);
  if (b.size() >= 3 && b[0] == 'P' && b[1] >= '1' && b[1] <= '6' && std::isspace(b[2])) return pnmHeader(path, b);
  return std::nullopt;
}

void requireImageSize(std::uint64_t width, std::uint64_t height, const std::string& where, const std::string& what) {
  if (width >= 1 && height >= 1 && width <= kMaxImageSidePx && height <= kMaxImageSidePx) return;
  const std::string cap = std::to_string(kMaxImageSidePx);
  throw std::runtime_error(where + ": " + what + " of " + std::to_string(width) + " x " + std::to_string(height) +
                           " pixels; images are read from 1 x 1 up to " + cap + " x " + cap + " pixels");
}

cv::Mat readImage(const std::string& path) {
  const std::optional<ImageHeader> header = readImageHeader(path);
  if (!header) {
    if (std::filesystem::exists(path) && cv::haveImageReader(path)) {
      throw std::runtime_error("'" + path + "': an image format whose size cannot be checked before decoding; "
                               "give PNG, JPEG, BMP or PNM (PGM/PPM)");
    }
    throw std::runtime_error("cannot read image '" + path + "' (not a PNG, JPEG, BMP or PNM file)");
  }
  requireImageSize(header->width, header->height, "'" + path + "'", header->format + " image");
  cv::Mat image = cv::imread(path, cv::IMREAD_COLOR);
  if (image.empty()) throw std::runtime_error("cannot decode image '" + path + "' (" + header->format + ")");
  const auto w = static_cast<std::uint64_t>(image.cols), h = static_cast<std::uint64_t>(image.rows);
  // A JPEG's EXIF orientation may swap the sides.
  if (!((w == header->width && h == header->height) || (w == header->height && h == header->width))) {
    throw std::runtime_error("'" + path + "': decoded as " + std::to_string(w) + " x " + std::to_string(h) +
                             " pixels, but its header says " + std::to_string(header->width) + " x " +
                             std::to_string(header->height));
  }
  return image;
}

std::string encodePng(const cv::Mat& image) {
  std::vector<unsigned char> png;
  if (!cv::imencode(".png", image, png)) throw std::runtime_error("cannot encode a PNG image");
  return std::string(png.begin(), png.end());
}

bool reachesJpegEnd(const unsigned char* b, std::size_t n) {
  if (n < 4 || b[0] != 0xFF || b[1] != 0xD8) return false;
  const auto restart = [](unsigned char m) { return m >= 0xD0 && m <= 0xD7; };
  std::size_t i = 2;
  while (i + 1 < n) {
    if (b[i] != 0xFF) return false;  // no marker where one must be
    const unsigned char m = b[i + 1];
    if (m == 0xFF) {  // a fill byte
      ++i;
      continue;
    }
    if (m == 0xD9) return true;
    if (m == 0x01 || restart(m)) {  // markers without a length
      i += 2;
      continue;
    }
    if (i + 3 >= n) return false;
    const std::size_t length = (static_cast<std::size_t>(b[i + 2]) << 8) | b[i + 3];
    if (length < 2) return false;
    i += 2 + length;
    if (m == 0xDA) {  // a scan's entropy-coded data, up to the next marker
      while (i + 1 < n && !(b[i] == 0xFF && b[i + 1] != 0x00 && !restart(b[i + 1]))) ++i;
    }
  }
  return false;
}

}  // namespace lidarseg::vision
