#include "lidarseg/report/FeatureCsv.h"

#include <cmath>
#include <iomanip>

namespace lidarseg::report {

void writeFeatureCsvHeader(std::ostream& os) {
  os << "t,type,x,y,theta,width,confidence,scan,var_x,var_y,cov_xy,var_theta,var_width\n";
}

void writeFeatureCsvRows(std::ostream& os, double stamp_s, std::size_t scan, const Pose2D& T_robot_sensor,
                         const std::vector<Feature>& features) {
  const double c = std::cos(T_robot_sensor.yaw), s = std::sin(T_robot_sensor.yaw);
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  R.topLeftCorner<2, 2>() << c, -s, s, c;
  for (const Feature& f : features) {
    const Pose2D p = compose(T_robot_sensor, {f.position.x(), f.position.y(), f.theta_rad});
    const Eigen::Matrix3d cov = R * f.covariance * R.transpose();
    os << std::setprecision(16) << stamp_s << ',' << toString(f.type) << std::setprecision(6) << ',' << p.x << ','
       << p.y << ',' << p.yaw << ',' << f.width_m << ',' << f.confidence << ',' << scan << ',' << cov(0, 0) << ','
       << cov(1, 1) << ',' << cov(0, 1) << ',' << cov(2, 2) << ',' << f.width_variance_m2 << '\n';
  }
}

}  // namespace lidarseg::report
