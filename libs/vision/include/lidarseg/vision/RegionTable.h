#pragma once
/// @file RegionTable.h
/// Regions of interest per camera frame, as `lidarseg-people` reads them: from the CSV that
/// `lidarseg-features --rois-out` writes, and from "u_min,v_min,u_max,v_max" options.

#include <cstddef>
#include <istream>
#include <map>
#include <string>
#include <vector>

#include <opencv2/core/types.hpp>

namespace lidarseg::vision {

/// Largest pixel coordinate accepted in a region (larger than any camera image; keeps the
/// box arithmetic far from integer overflow).
inline constexpr long kMaxRegionPixel = 1000000;

/// Parses "u_min,v_min,u_max,v_max" (inclusive pixels, 0 <= min <= max <= kMaxRegionPixel).
/// @throws std::invalid_argument naming `what` and the text.
cv::Rect parseRegion(const std::string& text, const std::string& what);

/// Regions of interest per frame (pixels of the frame's image).
class RegionTable {
 public:
  /// A region used in every frame.
  void addEveryFrame(const cv::Rect& region) { every_.push_back(region); }

  /// Reads a CSV: a header naming u_min,v_min,u_max,v_max (inclusive pixels) and the frame
  /// as `frame` or `image` (0-based index; -1 or * = every frame) and/or `file` (image file
  /// name, used when not empty); one region per line; blank lines are skipped.
  /// @param source the name used in messages (the file's path).
  /// @throws std::runtime_error "source:line: ..." naming the column for a missing column,
  /// a wrong field count, a value that is not a whole number or a box out of range.
  void read(std::istream& in, const std::string& source);
  /// As above, from a file. @throws std::runtime_error naming the file when unreadable.
  void read(const std::string& path);

  /// The regions of frame `index` read from file `file` (every-frame regions first).
  std::vector<cv::Rect> of(std::size_t index, const std::string& file) const;
  bool empty() const { return every_.empty() && by_index_.empty() && by_file_.empty(); }
  /// Number of regions held.
  std::size_t size() const;

 private:
  std::vector<cv::Rect> every_;
  std::map<std::size_t, std::vector<cv::Rect>> by_index_;
  std::map<std::string, std::vector<cv::Rect>> by_file_;
};

}  // namespace lidarseg::vision
