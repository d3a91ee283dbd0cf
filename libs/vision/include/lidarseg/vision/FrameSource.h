#pragma once
/// @file FrameSource.h
/// The camera frames `lidarseg-people` analyses: a video, a folder of images or one image.

#include <cstddef>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>

namespace lidarseg::vision {

/// Frames of a video (anything OpenCV's VideoCapture reads), a folder of images (png, jpg,
/// jpeg, bmp, ppm, pgm; read in name order) or one image. Images are read through
/// readImage(), their header's size checked first (decision 52); a video's frames are held to
/// the same cap, from the size its container declares before any is decoded, and each frame:
/// a Motion-JPEG frame from its JPEG header before it is decoded (its size may change from
/// frame to frame), a frame of another codec once decoded.
class FrameSource {
 public:
  /// @throws std::runtime_error naming `input` when it does not exist, a folder holds no
  /// image, the file is neither an image nor a video OpenCV can read, or a video declares
  /// frames beyond kMaxImageSidePx.
  explicit FrameSource(const std::string& input);

  /// How many frames the input holds: its image files, or the frame count the video's
  /// container declares (0 when it declares none); for a progress's time left only.
  std::size_t expectedFrames() const;

  /// The next frame (BGR) and its file name (empty for a video's frame); false at the end.
  /// @throws std::runtime_error naming the file for an unreadable or oversized image, or the
  /// video and the frame's number (from 0) for an oversized frame.
  bool next(cv::Mat& frame, std::string& file);

 private:
  std::string input_;
  cv::VideoCapture video_;
  // A Motion-JPEG video read again undecoded (FFmpeg's raw packets), one frame ahead of
  // video_: each frame's JPEG header is checked before video_ decodes it.
  cv::VideoCapture undecoded_;
  std::vector<std::string> files_;
  std::size_t next_file_ = 0;
  std::size_t video_frame_ = 0;  // frames of the video read so far

  void requireDeclaredSize() const;
  void openUndecoded();
  void requireNextFrameSize();
};

}  // namespace lidarseg::vision
