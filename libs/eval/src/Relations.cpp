#include "lidarseg/eval/Relations.h"

#include "NumberLines.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <stdexcept>

namespace lidarseg::eval {

std::vector<Relation> readRelations(const std::string& path) {
  std::vector<Relation> out;
  detail::forEachLineOf8Numbers(path, "relations", "t1 t2 x y z roll pitch yaw", 2,
                                [&](std::size_t line, const std::array<double, 8>& v) {
                                  // A motion between a time and itself measures nothing (its
                                  // error would be the relation's own displacement).
                                  if (v[0] == v[1]) {
                                    throw std::runtime_error(path + ":" + std::to_string(line) +
                                                             ": a relation between a time and itself (t1 = t2)");
                                  }
                                  out.push_back({v[0], v[1], {v[2], v[3], v[7]}});
                                });
  // An empty file evaluates nothing, which "0/0" would hide.
  if (out.empty()) throw std::runtime_error(path + ": no relation (expected lines 't1 t2 x y z roll pitch yaw')");
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
