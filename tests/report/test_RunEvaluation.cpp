#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "lidarseg/report/RunEvaluation.h"

namespace lidarseg::report {
namespace {

// A truth that pairs with no scan: the warning names the file and the tolerance as a user
// reads it, not as the float it was computed from.
TEST(TruthPairingProblem, NamesTheFileAndATolerancePrintedShort) {
  const eval::StampedTrajectory truth = {{100.0, {}}, {100.1, {}}, {100.2, {}}};
  const std::vector<double> stamps = {5.0, 5.1, 5.2};
  const std::string text = truthPairingProblem("other.gt.tum", truth, stamps, 0.004999995231628418);
  EXPECT_NE(text.find("ground truth 'other.gt.tum': 0 of the 3 scans have a pose within 0.005 s"), std::string::npos)
      << text;
  EXPECT_EQ(text.find("0.00499"), std::string::npos) << text;
}

TEST(TruthPairingProblem, IsEmptyWhenTwoScansPair) {
  const eval::StampedTrajectory truth = {{5.0, {}}, {5.1, {}}, {5.2, {}}};
  EXPECT_EQ(truthPairingProblem("gt.tum", truth, {5.0, 5.1}, 0.005), "");
}

}  // namespace
}  // namespace lidarseg::report
