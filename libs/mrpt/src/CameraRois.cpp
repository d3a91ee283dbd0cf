#include "lidarseg/mrpt/CameraRois.h"

#include <filesystem>
#include <iomanip>
#include <ostream>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "lidarseg/mrpt/VisionConfig.h"
#include "lidarseg/vision/ImageFile.h"

namespace lidarseg::mrpt_adapter {

namespace {
// Where a rawlog's externally stored images are: "<name>_Images" beside it (MRPT's
// convention, name without .rawlog / .rawlog.gz), else "Images" beside it.
std::string imagesDirectoryOf(const std::string& log_path) {
  namespace fs = std::filesystem;
  std::string stem = log_path;
  for (const char* ext : {".gz", ".rawlog"}) {
    const std::string e(ext);
    if (stem.size() > e.size() && stem.compare(stem.size() - e.size(), e.size(), e) == 0) stem.resize(stem.size() - e.size());
  }
  const std::string named = stem + "_Images";
  if (fs::is_directory(named)) return named;
  const fs::path beside = fs::path(log_path).parent_path() / "Images";
  return fs::is_directory(beside) ? beside.string() : named;
}
}  // namespace

CameraRois::CameraRois(std::string log_path, std::optional<vision::CameraParams> camera, const vision::RoiParams& rois)
    : images_dir_(imagesDirectoryOf(log_path)), camera_(std::move(camera)), rois_(rois) {
  rois_.validate();
  if (camera_) camera_->validate();
}

std::vector<vision::Roi> CameraRois::project(const mrpt::obs::CObservationImage& image,
                                             const mrpt::poses::CPose3D& lidar_on_robot,
                                             const std::vector<Feature>& features) const {
  const vision::CameraModel model = camera_ ? vision::CameraModel(*camera_) : mrpt_adapter::cameraOf(image, lidar_on_robot);
  return vision::RoiProjector(model, rois_).project(features);
}

std::string CameraRois::fileOf(const mrpt::obs::CObservationImage& image) {
  return image.image.isExternallyStored() ? image.image.getExternalStorageFile() : std::string();
}

cv::Mat CameraRois::pixels(const mrpt::obs::CObservationImage& image) const {
  if (image.image.isExternallyStored()) {
    const std::string path = images_dir_ + "/" + image.image.getExternalStorageFile();
    return vision::readImage(path);
  }
  // The pixels are in memory already (MRPT read them with the log), but are copied, converted
  // and drawn on: held to the cap of image files.
  vision::requireImageSize(image.image.getWidth(), image.image.getHeight(),
                           "image observation '" + image.sensorLabel + "'", "embedded image");
  cv::Mat m = image.image.asCvMat<cv::Mat>(mrpt::img::DEEP_COPY);
  if (m.channels() == 1) cv::cvtColor(m, m, cv::COLOR_GRAY2BGR);
  return m;
}

void drawRois(cv::Mat& bgr, const std::vector<vision::Roi>& rois) {
  for (const vision::Roi& r : rois) {
    const cv::Scalar colour = isDoor(r.type) ? cv::Scalar(0, 0, 230) : cv::Scalar(0, 190, 0);
    cv::rectangle(bgr, r.box, colour, 2);
    cv::putText(bgr, toString(r.type), r.box.tl() + cv::Point(3, 14), cv::FONT_HERSHEY_SIMPLEX, 0.45, colour, 1,
                cv::LINE_AA);
  }
}

void writeRoiCsvHeader(std::ostream& os) {
  os << "image,scan,t,file,feature,type,u_min,v_min,u_max,v_max,clipped\n";
}

void writeRoiCsvRows(std::ostream& os, std::size_t image, std::size_t scan, double t, const std::string& file,
                     const std::vector<vision::Roi>& rois) {
  for (const vision::Roi& r : rois) {
    os << image << ',' << scan << ',' << std::fixed << std::setprecision(6) << t << std::defaultfloat << ',' << file << ',' << r.feature << ','
       << toString(r.type) << ',' << r.box.x << ',' << r.box.y << ',' << r.box.x + r.box.width - 1 << ','
       << r.box.y + r.box.height - 1 << ',' << (r.clipped ? 1 : 0) << '\n';
  }
}

}  // namespace lidarseg::mrpt_adapter
