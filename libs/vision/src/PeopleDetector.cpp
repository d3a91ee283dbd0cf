#include "lidarseg/vision/PeopleDetector.h"
#include "lidarseg/core/NumberText.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <opencv2/imgproc.hpp>

#include "lidarseg/vision/ImageFile.h"
#include "lidarseg/vision/RegionsOfInterest.h"

namespace lidarseg::vision {

namespace {
[[noreturn]] void fail(const std::string& key, const std::string& need, double value) {
  throw std::invalid_argument(key + " must be " + need + " (got " + numberText(value) + ")");
}
}  // namespace

void PeopleDetectorParams::validate() const {
  if (!std::isfinite(hit_threshold)) fail("hit_threshold", "finite", hit_threshold);
  if (win_stride_px < 8 || win_stride_px % 8 != 0) fail("win_stride_px", "a multiple of 8", win_stride_px);
  if (!(std::isfinite(scale_step) && scale_step > 1.0)) fail("scale_step", "finite and > 1", scale_step);
  if (group_threshold < 0) fail("group_threshold", ">= 0", group_threshold);
  if (!(std::isfinite(roi_margin) && roi_margin >= 0.0 && roi_margin <= 10.0)) fail("roi_margin", "in [0, 10]", roi_margin);
  if (!(std::isfinite(image_scale) && image_scale >= 0.25 && image_scale <= 4.0)) {
    fail("image_scale", "in [0.25, 4]", image_scale);
  }
}

PeopleDetector::PeopleDetector(const PeopleDetectorParams& params) : params_(params) {
  params_.validate();
  hog_.setSVMDetector(cv::HOGDescriptor::getDefaultPeopleDetector());
}

std::vector<Person> PeopleDetector::detect(const cv::Mat& image) const {
  cv::Mat input = image;
  // The resized image obeys the images' own cap: 8192 px at a scale of 4 asked for 16 GB
  // (issue 16).
  const double longest = params_.image_scale * std::max(image.cols, image.rows);
  if (longest > static_cast<double>(kMaxImageSidePx)) {
    throw std::invalid_argument("[people] image_scale " + numberText(params_.image_scale) + " makes this " +
                                std::to_string(image.cols) + "x" + std::to_string(image.rows) + " image " +
                                numberText(std::round(longest)) + " px on its longest side, beyond the " +
                                std::to_string(kMaxImageSidePx) + " px cap: lower image_scale");
  }
  if (params_.image_scale != 1.0) {
    cv::resize(image, input, cv::Size(), params_.image_scale, params_.image_scale, cv::INTER_LINEAR);
  }
  std::vector<Person> out;
  if (input.cols < hog_.winSize.width || input.rows < hog_.winSize.height) return out;
  std::vector<cv::Rect> boxes;
  std::vector<double> scores;
  hog_.detectMultiScale(input, boxes, scores, params_.hit_threshold,
                        cv::Size(params_.win_stride_px, params_.win_stride_px), cv::Size(), params_.scale_step,
                        params_.group_threshold);
  const double k = 1.0 / params_.image_scale;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const cv::Rect& b = boxes[i];
    Person p;
    p.box = cv::Rect(static_cast<int>(std::lround(b.x * k)), static_cast<int>(std::lround(b.y * k)),
                     static_cast<int>(std::lround(b.width * k)), static_cast<int>(std::lround(b.height * k)));
    p.score = i < scores.size() ? scores[i] : 0.0;
    out.push_back(p);
  }
  return out;
}

PeopleDetection PeopleDetector::detectFullFrame(const cv::Mat& image) const {
  PeopleDetection d;
  d.people = detect(image);
  d.analysed = {cv::Rect(0, 0, image.cols, image.rows)};
  d.analysed_fraction = image.empty() ? 0.0 : 1.0;
  return d;
}

std::vector<cv::Rect> PeopleDetector::analysedRegions(const std::vector<cv::Rect>& regions,
                                                      const cv::Size& image) const {
  const cv::Rect frame(cv::Point(0, 0), image);
  // The smallest region that holds one detection window, in input-image pixels.
  const int min_w = static_cast<int>(std::ceil(hog_.winSize.width / params_.image_scale));
  const int min_h = static_cast<int>(std::ceil(hog_.winSize.height / params_.image_scale));
  std::vector<cv::Rect> crops;
  for (const cv::Rect& r : regions) {
    if ((r & frame).area() == 0) continue;
    cv::Rect g = grow(r, params_.roi_margin, image);
    if (g.width < min_w) g.x -= (min_w - g.width) / 2, g.width = min_w;
    if (g.height < min_h) g.y -= (min_h - g.height) / 2, g.height = min_h;
    // Shift back inside the image rather than cut below the window size.
    g.x = std::clamp(g.x, 0, std::max(0, image.width - g.width));
    g.y = std::clamp(g.y, 0, std::max(0, image.height - g.height));
    // Start on the window-stride grid of the whole image, so that the crop's windows at
    // the first pyramid level are the whole frame's windows.
    const int stride = static_cast<int>(std::lround(params_.win_stride_px / params_.image_scale));
    const int x0 = g.x - g.x % std::max(stride, 1), y0 = g.y - g.y % std::max(stride, 1);
    g = cv::Rect(x0, y0, g.width + (g.x - x0), g.height + (g.y - y0));
    g &= frame;
    if (g.area() > 0) crops.push_back(g);
  }
  return mergeOverlapping(std::move(crops));
}

PeopleDetection PeopleDetector::detectInRegions(const cv::Mat& image, const std::vector<cv::Rect>& regions) const {
  PeopleDetection d;
  d.analysed = analysedRegions(regions, image.size());
  double area = 0;
  for (const cv::Rect& crop : d.analysed) {
    area += crop.area();
    for (Person p : detect(image(crop))) {
      p.box.x += crop.x;
      p.box.y += crop.y;
      d.people.push_back(p);
    }
  }
  d.analysed_fraction = image.empty() ? 0.0 : area / (static_cast<double>(image.cols) * image.rows);
  return d;
}

std::vector<cv::Rect> mergeOverlapping(std::vector<cv::Rect> boxes) {
  for (bool merged = true; merged;) {
    merged = false;
    for (std::size_t i = 0; i < boxes.size() && !merged; ++i) {
      for (std::size_t j = i + 1; j < boxes.size(); ++j) {
        if ((boxes[i] & boxes[j]).area() > 0) {
          boxes[i] |= boxes[j];
          boxes.erase(boxes.begin() + static_cast<std::ptrdiff_t>(j));
          merged = true;
          break;
        }
      }
    }
  }
  return boxes;
}

bool centredIn(const cv::Rect& box, const std::vector<cv::Rect>& regions) {
  const cv::Point c(box.x + box.width / 2, box.y + box.height / 2);
  return std::any_of(regions.begin(), regions.end(), [&](const cv::Rect& r) { return r.contains(c); });
}

bool overlapsAny(const cv::Rect& box, const std::vector<Person>& people, double iou) {
  return std::any_of(people.begin(), people.end(),
                     [&](const Person& p) { return intersectionOverUnion(box, p.box) >= iou; });
}

}  // namespace lidarseg::vision
