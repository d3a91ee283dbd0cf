#include "lidarseg/vision/PeopleComparison.h"

#include <chrono>
#include <cmath>

namespace lidarseg::vision {

namespace {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace

double PeopleReport::recallInRegions() const {
  return people_in_regions == 0
             ? std::nan("")
             : static_cast<double>(people_still_found) / static_cast<double>(people_in_regions);
}

PeopleComparison::PeopleComparison(const PeopleDetector& detector, double match_iou,
                                   PeopleReport& report)
    : detector_(detector), match_iou_(match_iou), report_(report) {}

PeopleComparison::FrameDetections PeopleComparison::add(const cv::Mat& frame,
                                                        const std::vector<cv::Rect>& rois) {
  report_.frame_size = frame.size();
  auto t0 = Clock::now();
  FrameDetections d{detector_.detectFullFrame(frame), {}};
  full_ms_.push_back(millisecondsSince(t0));
  t0 = Clock::now();
  d.inside = detector_.detectInRegions(frame, rois);
  rois_ms_.push_back(millisecondsSince(t0));
  fraction_.push_back(d.inside.analysed_fraction);
  if (full_ms_.back() > 0) ratio_.push_back(rois_ms_.back() / full_ms_.back());
  ++report_.frames;
  countPeople(d.full.people, d.inside.people, rois);
  return d;
}

void PeopleComparison::summarise() const {
  report_.full_ms = summarize(full_ms_);
  report_.rois_ms = summarize(rois_ms_);
  report_.analysed_fraction = summarize(fraction_);
  report_.time_ratio = summarize(ratio_);
}

void PeopleComparison::countPeople(const std::vector<Person>& full,
                                   const std::vector<Person>& inside,
                                   const std::vector<cv::Rect>& rois) {
  report_.people_full += full.size();
  report_.people_rois += inside.size();
  for (const Person& p : full) {
    if (!centredIn(p.box, rois)) continue;
    ++report_.people_in_regions;
    if (overlapsAny(p.box, inside, match_iou_)) ++report_.people_still_found;
  }
  for (const Person& p : inside) {
    if (overlapsAny(p.box, full, match_iou_)) ++report_.people_rois_confirmed;
  }
}

}  // namespace lidarseg::vision
