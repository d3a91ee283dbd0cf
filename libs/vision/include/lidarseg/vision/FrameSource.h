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
///
/// A Motion-JPEG video (on OpenCV's FFmpeg backend) is read as its undecoded packets, one per
/// frame, each decoded by OpenCV's JPEG decoder (`cv::imdecode`): a packet that is not a JPEG
/// image, is truncated (its last bytes, trailing zeros aside, are not the end-of-image marker
/// FF D9: the decoder would fill the missing rows with grey) or does not decode is skipped
/// and counted with its frame number (skippedFrames()),
/// and the frames after it keep their own numbers (frameIndex()), so a corrupt frame neither
/// ends the video nor shifts the frames after it.
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
  /// A folder's image that cannot be read or is oversized is skipped and counted
  /// (skippedFrames(): "...; image skipped"), and the next one read.
  /// @throws std::runtime_error naming the file for an unreadable or oversized image given
  /// alone, or the video and the frame's number (from 0) for an oversized frame.
  bool next(cv::Mat& frame, std::string& file);

  /// The number (from 0) of the frame next() returned last: its place in the video, counting
  /// the frames skipped before it, or the image's in the folder's name order.
  std::size_t frameIndex() const { return frame_index_; }
  /// Frames skipped because they could not be decoded, "'VIDEO', frame N: why; frame
  /// skipped" (the first kKeptSkips), and how many in all.
  const std::vector<std::string>& skippedFrames() const { return skipped_; }
  std::size_t skippedFrameCount() const { return skipped_count_; }

  /// Messages of skipped frames kept (the count goes on).
  static constexpr std::size_t kKeptSkips = 100;

 private:
  std::string input_;
  cv::VideoCapture video_;
  // A Motion-JPEG video read undecoded (FFmpeg's raw packets, one per frame): each frame's
  // JPEG header is checked before imdecode decodes it; video_ then only declares sizes.
  cv::VideoCapture undecoded_;
  std::vector<std::string> files_;
  std::size_t next_file_ = 0;
  std::size_t video_frame_ = 0;  // frames of the video read so far (skipped ones too)
  std::size_t frame_index_ = 0;
  std::vector<std::string> skipped_;
  std::size_t skipped_count_ = 0;

  void requireDeclaredSize() const;
  void openUndecoded();
  bool nextMotionJpeg(cv::Mat& frame);
  void skip(const std::string& message);
};

}  // namespace lidarseg::vision
