#pragma once
// Private to lidarseg::apps: images to PNG bytes (for OutputSet and embedding).

#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

namespace lidarseg::apps {

/// The image (BGR or grey) as PNG file bytes.
/// @throws std::runtime_error when OpenCV cannot encode it.
inline std::string encodePng(const cv::Mat& image) {
  std::vector<unsigned char> png;
  if (!cv::imencode(".png", image, png)) throw std::runtime_error("cannot encode a PNG image");
  return std::string(png.begin(), png.end());
}

}  // namespace lidarseg::apps
