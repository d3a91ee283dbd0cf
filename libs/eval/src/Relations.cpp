#include "lidarseg/eval/Relations.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace lidarseg::eval {

std::vector<Relation> readRelations(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open relations '" + path + "'");
  std::vector<Relation> out;
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    std::string token;
    double v[8];
    std::size_t count = 0;
    while (fields >> token) {
      if (count == 8) {
        throw std::runtime_error(path + ":" + std::to_string(line_no) +
                                 ": more than 8 fields (expected 't1 t2 x y z roll pitch yaw')");
      }
      char* end = nullptr;
      v[count] = std::strtod(token.c_str(), &end);
      if (end == token.c_str() || *end != '\0' || !std::isfinite(v[count])) {
        throw std::runtime_error(path + ":" + std::to_string(line_no) + ": field " +
                                 std::to_string(count + 1) + " '" + token + "' is not a finite number");
      }
      ++count;
    }
    if (count != 8) {
      throw std::runtime_error(path + ":" + std::to_string(line_no) + ": " + std::to_string(count) +
                               " fields (expected 8: 't1 t2 x y z roll pitch yaw')");
    }
    out.push_back({v[0], v[1], {v[2], v[3], v[7]}});
  }
  return out;
}

void writeRelations(std::ostream& os, const std::vector<Relation>& relations) {
  os << std::fixed;
  for (const auto& r : relations) {
    os << std::setprecision(6) << r.t1_s << ' ' << r.t2_s << ' ' << std::setprecision(9) << r.delta.x
       << ' ' << r.delta.y << " 0 0 0 " << r.delta.yaw << '\n';
  }
}

std::vector<Relation> relationsFrom(const StampedTrajectory& reference, double min_distance_m,
                                    double min_angle_rad, std::size_t stride) {
  std::vector<Relation> out;
  if (stride == 0) stride = 1;
  for (std::size_t i = 0; i < reference.size(); i += stride) {
    for (std::size_t j = i + 1; j < reference.size(); ++j) {
      const Pose2D d = relative(reference[j].pose, reference[i].pose);
      if (std::hypot(d.x, d.y) >= min_distance_m || std::abs(d.yaw) >= min_angle_rad) {
        out.push_back({reference[i].stamp_s, reference[j].stamp_s, d});
        break;
      }
    }
  }
  return out;
}

RelationErrors evaluateRelations(const StampedTrajectory& estimate,
                                 const std::vector<Relation>& relations, double tolerance_s) {
  RelationErrors out;
  out.relations = relations.size();
  std::vector<double> et, er;
  for (const auto& r : relations) {
    const auto a = nearestIndex(estimate, r.t1_s, tolerance_s);
    const auto b = nearestIndex(estimate, r.t2_s, tolerance_s);
    if (!a || !b) continue;
    const Pose2D est = relative(estimate[*b].pose, estimate[*a].pose);
    const Pose2D err = compose(inverse(est), r.delta);
    et.push_back(std::hypot(err.x, err.y));
    er.push_back(std::abs(wrapAngle(err.yaw)));
  }
  out.evaluated = et.size();
  out.translation_m = summarize(std::move(et));
  out.rotation_rad = summarize(std::move(er));
  return out;
}

}  // namespace lidarseg::eval
