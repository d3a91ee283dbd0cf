#pragma once
/// @file Relations.h
/// Relative-pose ("relations") evaluation of a trajectory, after Kümmerle et al. 2009,
/// "On measuring the accuracy of SLAM algorithms": each relation is the true pose of the
/// robot at t2 expressed in its frame at t1.

#include <cstddef>
#include <string>
#include <vector>

#include "lidarseg/core/Statistics.h"
#include "lidarseg/eval/StampedTrajectory.h"

namespace lidarseg::eval {

/// One relation: pose at t2 in the frame at t1.
struct Relation {
  double t1_s = 0.0;
  double t2_s = 0.0;
  Pose2D delta;
};

/// Reads a Freiburg relations file: `t1 t2 x y z roll pitch yaw` per line (`#` comments);
/// z, roll and pitch are ignored.
/// @throws std::runtime_error naming the file and line for an unreadable file or a line
/// without 8 finite numbers.
std::vector<Relation> readRelations(const std::string& path);

/// Writes relations in the same format.
void writeRelations(std::ostream& os, const std::vector<Relation>& relations);

/// Relations between every pose and the first later pose at least `min_distance_m` or
/// `min_angle_rad` away from it, from a reference trajectory (e.g. simulated ground truth
/// or a log's corrected poses). Poses are taken every `stride` poses.
std::vector<Relation> relationsFrom(const StampedTrajectory& reference, double min_distance_m,
                                    double min_angle_rad, std::size_t stride = 1);

/// Errors of a trajectory on a set of relations.
struct RelationErrors {
  std::size_t relations = 0;   ///< relations given
  std::size_t evaluated = 0;   ///< relations whose two times both found an estimated pose
  Summary translation_m;       ///< |translation of (estimated delta)^-1 (+) true delta|
  Summary rotation_rad;        ///< |its rotation|
};

/// Evaluates `estimate` on `relations`; a relation whose t1 or t2 has no estimated pose
/// within `tolerance_s` is not evaluated (counted).
RelationErrors evaluateRelations(const StampedTrajectory& estimate,
                                 const std::vector<Relation>& relations, double tolerance_s = 0.005);

}  // namespace lidarseg::eval
