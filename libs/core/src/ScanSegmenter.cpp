#include "lidarseg/core/ScanSegmenter.h"

namespace lidarseg {

void SegmentationParams::validate() const {
  noise.validate();
  wall_danielsson.validate();
  cascade.validate();
}

ScanSegmenter::ScanSegmenter(const SegmentationParams& params)
    : params_(params),
      wall_danielsson_(params.wall_danielsson, params.noise),
      cascade_(params.cascade, params.noise) {}

void ScanSegmenter::process(const Scan& scan, Segmentation& out) const {
  wall_danielsson_.segment(scan, out);
  cascade_.apply(out);
}

void ScanSegmenter::process(const Scan& scan, Segmentation& out, const Twist2D& motion) const {
  wall_danielsson_.segment(scan, out, motion);
  cascade_.apply(out);
}

Segmentation ScanSegmenter::process(const Scan& scan) const {
  Segmentation out;
  process(scan, out);
  return out;
}

}  // namespace lidarseg
