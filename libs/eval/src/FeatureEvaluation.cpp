#include "lidarseg/eval/FeatureEvaluation.h"
#include "lidarseg/eval/Csv.h"
#include "lidarseg/core/NumberText.h"
#include "lidarseg/core/ScanRecord.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <tuple>
#include <utility>

namespace lidarseg::eval {

namespace {
double ratio(std::size_t num, std::size_t den) {
  return den == 0 ? std::numeric_limits<double>::quiet_NaN() : static_cast<double>(num) / static_cast<double>(den);
}

[[noreturn]] void fail(const std::string& path, std::size_t line, const std::string& what) {
  std::ostringstream os;
  os << path << ":" << line << ": " << what;
  throw std::runtime_error(os.str());
}
}  // namespace

double DetectionCounts::recall() const { return ratio(truths_found, truths); }
double DetectionCounts::precision() const { return ratio(detections_right, detections); }
double DetectionCounts::visibleRecall() const { return ratio(visible_found, visible); }

std::map<std::size_t, std::vector<TrueFeature>> readTrueFeatures(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open the feature file");
  std::map<std::size_t, std::vector<TrueFeature>> out;
  static const char* kColumns[] = {"scan", "t", "type", "x", "y", "theta", "width", "id", "resolvable", "seen_as"};
  CsvReader reader(in, path, true);
  std::vector<std::string> cols;
  std::map<std::tuple<std::size_t, bool, std::size_t>, std::size_t> first_line;  // (scan, door?, id) -> line
  while (reader.next(cols)) {
    const std::size_t number = reader.lineNumber();
    if (number == 1 && cols.size() > 1 && cols[0] == "scan") continue;  // header
    // Another file's header (a --features-out table, a TUM line): not a truth file at all.
    if (number == 1 && !parseNumber(cols[0]).ok()) {
      fail(path, number, "not a feature truth file: its header starts '" + cols[0].substr(0, 40) +
                             "', expected 'scan,t,type,x,y,theta,width,id[,resolvable,seen_as]' (lidarseg-simulate's "
                             "PREFIX.features.csv)");
    }
    if (cols.size() < 8) fail(path, number, "expected at least 8 columns (scan,t,type,x,y,theta,width,id)");
    auto number_at = [&](std::size_t k) {
      const ParsedNumber v = parseNumber(cols[k]);
      if (!v.ok() || !std::isfinite(v.value)) {
        fail(path, number, std::string("column '") + kColumns[k] + "' is not a finite number: '" + cols[k] + "'");
      }
      return v.value;
    };
    TrueFeature f;
    const auto type = featureTypeFromString(cols[2]);
    if (!type) fail(path, number, "column 'type': unknown feature type '" + cols[2] + "'");
    f.type = *type;
    f.seen_as = *type;
    const double scan = number_at(0);
    if (!(scan >= 0 && scan <= 1e15) || scan != std::floor(scan)) {
      fail(path, number, "column 'scan' must be an integer in [0, 1e15]");
    }
    // Positions, angles and widths past the logs' bound are no building's (1e300 reached the
    // matches table as a 300-digit number that cut its row).
    const auto bounded = [&](std::size_t k, double lo) {
      const double v = number_at(k);
      if (!(v >= lo && std::abs(v) <= kMaxLogCoordinate)) {
        fail(path, number, std::string("column '") + kColumns[k] + "' = " + cols[k] + " is not in [" +
                               (lo < 0.0 ? "-1e6" : "0") + ", 1e6]");
      }
      return v;
    };
    f.stamp_s = number_at(1);
    f.position = {bounded(3, -kMaxLogCoordinate), bounded(4, -kMaxLogCoordinate)};
    f.theta_rad = bounded(5, -kMaxLogCoordinate);
    f.width_m = bounded(6, 0.0);
    const double id = number_at(7);
    if (!(id >= 0 && id <= 1e15) || id != std::floor(id)) fail(path, number, "column 'id' must be an integer in [0, 1e15]");
    f.id = static_cast<std::size_t>(id);
    // Doors and corners are numbered apart: one of each may share a number.
    const auto [first, added] =
        first_line.emplace(std::make_tuple(static_cast<std::size_t>(scan), isDoor(f.type), f.id), number);
    if (!added) {
      fail(path, number, std::string(isDoor(f.type) ? "door " : "corner ") + std::to_string(f.id) + " of scan " +
                             std::to_string(static_cast<std::size_t>(scan)) + " given twice (first at line " +
                             std::to_string(first->second) + ")");
    }
    if (cols.size() > 8) {
      const double resolvable = number_at(8);
      if (resolvable != 0.0 && resolvable != 1.0) fail(path, number, "column 'resolvable' must be 0 or 1, not '" + cols[8] + "'");
      f.resolvable = resolvable != 0.0;
    }
    if (cols.size() > 9) {
      const auto seen = featureTypeFromString(cols[9]);
      if (!seen) fail(path, number, "column 'seen_as': unknown feature type '" + cols[9] + "'");
      f.seen_as = *seen;
    }
    out[static_cast<std::size_t>(scan)].push_back(f);
  }
  return out;
}

FeatureEvaluation::FeatureEvaluation(double gate_m) : gate_m_(gate_m) {
  if (!(gate_m > 0.0 && std::isfinite(gate_m))) throw std::invalid_argument("feature match gate must be > 0");
}

std::vector<double> FeatureEvaluation::add(const std::vector<TrueFeature>& truth,
                                           const std::vector<Feature>& detected) {
  ++scans_;
  auto right = [&](const TrueFeature& t, const Feature& d) { return d.type == t.seen_as || d.type == t.type; };
  // Candidate pairs within the gate, same family; pairs of the right type first (two
  // corners of a T share one point), then nearest first.
  std::vector<std::tuple<bool, double, std::size_t, std::size_t>> pairs;
  for (std::size_t t = 0; t < truth.size(); ++t) {
    for (std::size_t d = 0; d < detected.size(); ++d) {
      if (isDoor(truth[t].type) != isDoor(detected[d].type)) continue;
      const double dist = (truth[t].position - detected[d].position).norm();
      if (dist <= gate_m_) pairs.emplace_back(!right(truth[t], detected[d]), dist, t, d);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<int>& truth_match = truth_match_;
  std::vector<int>& det_match = det_match_;
  truth_match.assign(truth.size(), -1);
  det_match.assign(detected.size(), -1);
  std::vector<double> errors;
  for (const auto& [wrong, dist, t, d] : pairs) {
    if (truth_match[t] >= 0 || det_match[d] >= 0) continue;
    truth_match[t] = static_cast<int>(d);
    det_match[d] = static_cast<int>(t);
    errors.push_back(dist);
  }
  for (std::size_t t = 0; t < truth.size(); ++t) {
    const TrueFeature& tf = truth[t];
    DetectionCounts& family = isDoor(tf.type) ? doors_ : corners_;
    DetectionCounts& kind = by_type_[static_cast<std::size_t>(tf.seen_as)];
    ++family.visible;
    ++kind.visible;
    if (truth_match[t] >= 0) {
      const Feature& d = detected[static_cast<std::size_t>(truth_match[t])];
      ++confusion_[static_cast<std::size_t>(tf.seen_as)][static_cast<std::size_t>(d.type)];
      ++family.visible_found;
      if (right(tf, d)) ++kind.visible_found;
    }
    if (!tf.resolvable) continue;
    ++family.truths;
    ++kind.truths;
    if (truth_match[t] < 0) continue;
    ++family.truths_found;
    if (right(tf, detected[static_cast<std::size_t>(truth_match[t])])) ++kind.truths_found;
  }
  for (std::size_t d = 0; d < detected.size(); ++d) {
    const Feature& df = detected[d];
    DetectionCounts& family = isDoor(df.type) ? doors_ : corners_;
    DetectionCounts& kind = by_type_[static_cast<std::size_t>(df.type)];
    ++family.detections;
    ++kind.detections;
    if (det_match[d] < 0) continue;
    ++family.detections_right;
    if (right(truth[static_cast<std::size_t>(det_match[d])], df)) ++kind.detections_right;
  }
  errors_.insert(errors_.end(), errors.begin(), errors.end());
  return errors;
}

void writeMatchesCsvHeader(std::ostream& os) { os << "scan,role,type,seen_as,x,y,theta,width,id,resolvable,match\n"; }

void writeMatchesCsvRows(std::ostream& os, std::size_t scan, const std::vector<TrueFeature>& truth,
                         const std::vector<Feature>& detected, const FeatureEvaluation& evaluation) {
  const auto& tm = evaluation.lastTruthMatches();
  const auto& dm = evaluation.lastDetectionMatches();
  char line[1024];  // the fields are bounded (readTrueFeatures, the scans' ranges)
  for (std::size_t k = 0; k < truth.size(); ++k) {
    const TrueFeature& t = truth[k];
    std::snprintf(line, sizeof(line), "%zu,truth,%s,%s,%.4f,%.4f,%.4f,%.4f,%zu,%d,%s\n", scan, toString(t.type),
                  toString(t.seen_as), t.position.x(), t.position.y(), t.theta_rad, t.width_m, t.id,
                  t.resolvable ? 1 : 0, tm[k] < 0 ? "none" : toString(detected[static_cast<std::size_t>(tm[k])].type));
    os << line;
  }
  for (std::size_t k = 0; k < detected.size(); ++k) {
    const Feature& f = detected[k];
    const TrueFeature* t = dm[k] < 0 ? nullptr : &truth[static_cast<std::size_t>(dm[k])];
    std::snprintf(line, sizeof(line), "%zu,detection,%s,,%.4f,%.4f,%.4f,%.4f,%lld,,%s\n", scan, toString(f.type),
                  f.position.x(), f.position.y(), f.theta_rad, f.width_m, t ? static_cast<long long>(t->id) : -1LL,
                  t ? toString(t->seen_as) : "none");
    os << line;
  }
}

}  // namespace lidarseg::eval
