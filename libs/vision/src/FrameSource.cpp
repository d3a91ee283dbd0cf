#include "lidarseg/vision/FrameSource.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cctype>
#include <filesystem>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>

#include "lidarseg/vision/ImageFile.h"

namespace lidarseg::vision {

namespace fs = std::filesystem;

namespace {

// Whether the file's name says it is an image the folder reader takes.
bool hasImageExtension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp" || ext == ".ppm" || ext == ".pgm";
}

}  // namespace

FrameSource::FrameSource(const std::string& input) : input_(input) {
  if (fs::is_directory(input)) {
    for (const auto& e : fs::directory_iterator(input)) {
      if (hasImageExtension(e.path())) files_.push_back(e.path().string());
    }
    std::sort(files_.begin(), files_.end());
    if (files_.empty())
      throw std::runtime_error("'" + input + "': no image files (png, jpg, bmp, ppm, pgm)");
  } else if (!fs::exists(input)) {
    throw std::runtime_error("'" + input + "': no such file or directory");
  } else if (fs::is_regular_file(input) && fs::file_size(input) == 0) {
    // Neither an image nor a video; OpenCV's video backends would print their own noise.
    throw std::runtime_error("'" + input + "': empty file (no image or video)");
  } else if (hasImageExtension(input) || readImageHeader(input) || cv::haveImageReader(input)) {
    // An image by name or by content: read (and its size checked) by next(), whose error
    // names what is wrong with it; never handed to the video backends.
    files_.push_back(input);
  } else {
    video_.open(input);
    if (!video_.isOpened())
      throw std::runtime_error("'" + input + "': neither an image nor a video OpenCV can read");
    requireDeclaredSize();
    openUndecoded();
  }
}

// FFmpeg's Motion-JPEG decoder takes each frame's size from its own JPEG header, whatever the
// container declared; OpenCV's raw mode (CAP_PROP_FORMAT -1) gives those frames undecoded.
void FrameSource::openUndecoded() {
  const int fourcc = static_cast<int>(video_.get(cv::CAP_PROP_FOURCC));
  const bool mjpeg = fourcc == cv::VideoWriter::fourcc('M', 'J', 'P', 'G') ||
                     fourcc == cv::VideoWriter::fourcc('m', 'j', 'p', 'g');
  if (!mjpeg || video_.getBackendName() != "FFMPEG") return;
  undecoded_.open(input_, cv::CAP_FFMPEG, {cv::CAP_PROP_FORMAT, -1});
  // Without the raw mode (an older FFmpeg backend), video_ decodes each frame as another codec's.
}

void FrameSource::skip(const std::string& message) {
  ++skipped_count_;
  if (skipped_.size() < kKeptSkips) skipped_.push_back(message);
}

// One packet is one frame: a packet that cannot be decoded is skipped under its own number,
// so the next packet is the next frame (a second, decoding capture could fall out of step
// with this one on a packet FFmpeg drops).
bool FrameSource::nextMotionJpeg(cv::Mat& frame) {
  cv::Mat packet;
  // grab() then retrieve(): read() would take an empty packet (a dropped frame) for the end.
  while (undecoded_.grab()) {
    const std::size_t number = video_frame_++;
    const std::string where = "'" + input_ + "', frame " + std::to_string(number);
    packet.release();
    const bool bytes = undecoded_.retrieve(packet) && !packet.empty() && packet.type() == CV_8UC1;
    if (!bytes && number == 0) {
      undecoded_.release();  // no raw mode after all: video_ decodes from the first frame
      video_frame_ = 0;
      return false;
    }
    if (packet.empty()) {
      skip(where + ": an empty frame; frame skipped");
      continue;
    }
    if (!bytes) throw std::runtime_error(where + ": OpenCV did not give the frame's undecoded bytes");
    ImageHeader header;
    try {
      header = readJpegHeader(std::string(reinterpret_cast<const char*>(packet.data), packet.total()), input_);
    } catch (const std::runtime_error& e) {
      skip(where + ": not a Motion-JPEG frame (" + e.what() + "); frame skipped");
      continue;
    }
    requireImageSize(header.width, header.height, where, "video frame");
    if (!reachesJpegEnd(packet.ptr<unsigned char>(), packet.total())) {
      skip(where + ": its JPEG data is truncated; frame skipped");
      continue;
    }
    cv::Mat decoded;
    try {
      decoded = cv::imdecode(packet, cv::IMREAD_COLOR);
    } catch (const cv::Exception&) {
      decoded.release();
    }
    if (decoded.empty() || static_cast<std::uint64_t>(decoded.cols) != header.width ||
        static_cast<std::uint64_t>(decoded.rows) != header.height) {
      skip(where + ": its JPEG data cannot be decoded; frame skipped");
      continue;
    }
    frame = decoded;
    frame_index_ = number;
    return true;
  }
  return false;
}

// The size the video's container declares, checked before any frame is decoded; a container
// that declares none has each frame checked by next().
void FrameSource::requireDeclaredSize() const {
  const double w = video_.get(cv::CAP_PROP_FRAME_WIDTH), h = video_.get(cv::CAP_PROP_FRAME_HEIGHT);
  if (!(w > 0.0 && h > 0.0 && std::isfinite(w) && std::isfinite(h))) return;
  const auto side = [](double v) { return static_cast<std::uint64_t>(std::min(v, 1e18)); };
  requireImageSize(side(w), side(h), "'" + input_ + "'", "video frames");
}

std::size_t FrameSource::expectedFrames() const {
  if (!video_.isOpened()) return files_.size();
  const double n = video_.get(cv::CAP_PROP_FRAME_COUNT);
  return std::isfinite(n) && n > 0 ? static_cast<std::size_t>(n) : 0;
}

bool FrameSource::next(cv::Mat& frame, std::string& file) {
  if (undecoded_.isOpened()) {
    file.clear();
    if (nextMotionJpeg(frame)) return true;
    if (undecoded_.isOpened()) return false;
  }
  if (video_.isOpened()) {
    file.clear();
    if (!video_.read(frame) || frame.empty()) return false;
    requireImageSize(static_cast<std::uint64_t>(frame.cols), static_cast<std::uint64_t>(frame.rows),
                     "'" + input_ + "', frame " + std::to_string(video_frame_), "video frame");
    frame_index_ = video_frame_++;
    return true;
  }
  // A folder's image that cannot be read (corrupt, truncated, oversized) is skipped and
  // counted like a video's frame, under its own number; a single image given alone is the
  // input, and its failure is the run's error.
  const bool folder = files_.size() > 1 || fs::is_directory(input_);
  while (next_file_ < files_.size()) {
    frame_index_ = next_file_;
    const std::string& path = files_[next_file_++];
    try {
      frame = readImage(path);
    } catch (const std::runtime_error& e) {
      if (!folder) throw;
      skip(std::string(e.what()) + "; image skipped");
      continue;
    }
    file = fs::path(path).filename().string();
    return true;
  }
  return false;
}

}  // namespace lidarseg::vision
