#pragma once
/// @file ImageFile.h
/// Reading an image file with its size checked from the header, before anything is decoded;
/// encoding an image as PNG bytes.

#include <cstdint>
#include <optional>
#include <string>

#include <opencv2/core.hpp>

namespace lidarseg::vision {

/// Largest width or height of an image read from a file (pixels): 8192 x 8192 is 201 MB as
/// BGR. A header declaring more is refused before decoding (decision 52).
inline constexpr std::uint64_t kMaxImageSidePx = 8192;

/// Whether the `n` bytes at `b` hold a JPEG stream (from its start-of-image marker) that
/// reaches its end-of-image marker FF D9. The stream is walked marker by marker (segment
/// lengths, then each scan's entropy-coded data, where FF is followed by 00 or a restart
/// marker), so bytes after the image (a container's or a camera's padding) and an EXIF
/// thumbnail's own end marker inside its segment do not count. libjpeg (under OpenCV's
/// imdecode, or MRPT's) fills the missing rows of a cut image with grey and only warns.
bool reachesJpegEnd(const unsigned char* b, std::size_t n);

/// Refuses a size outside [1, kMaxImageSidePx] on either side, the same cap for image files,
/// video frames and images embedded in a log (decision 52).
/// @throws std::runtime_error "WHERE: WHAT of W x H pixels; images are read from 1 x 1 up to
/// 8192 x 8192 pixels", e.g. WHERE "'clip.avi', frame 3" and WHAT "video frame".
void requireImageSize(std::uint64_t width, std::uint64_t height, const std::string& where, const std::string& what);

/// What an image file's header says.
struct ImageHeader {
  std::string format;  ///< "PNG", "JPEG", "BMP" or "PNM"
  std::uint64_t width = 0, height = 0;  ///< pixels, as declared
};

/// The header of a PNG, JPEG, BMP or PNM (PBM/PGM/PPM) file, read without decoding pixels.
/// @return std::nullopt when the file is not a regular file or does not start like one of
/// these formats.
/// @throws std::runtime_error naming the file when it starts like one of them but its header
/// is cut short or invalid.
std::optional<ImageHeader> readImageHeader(const std::string& path);

/// The frame header of a JPEG held in memory (a Motion-JPEG video's frame, as its container
/// stores it), read without decoding pixels. Linear in the bytes before the frame header.
/// @throws std::runtime_error "'NAME': invalid JPEG header (...)" when the bytes do not start
/// like a JPEG or its header is cut short or invalid.
ImageHeader readJpegHeader(const std::string& bytes, const std::string& name);

/// The image (BGR, 8 bits per channel), its size checked first: readImageHeader(), then
/// both sides in [1, kMaxImageSidePx], then OpenCV's decoder.
/// @throws std::runtime_error naming the file (and the cap) for a size beyond the cap, a
/// format whose size cannot be read before decoding, or a file OpenCV cannot decode.
cv::Mat readImage(const std::string& path);

/// The image (BGR or grey) as PNG file bytes.
/// @throws std::runtime_error when OpenCV cannot encode it.
std::string encodePng(const cv::Mat& image);

}  // namespace lidarseg::vision
