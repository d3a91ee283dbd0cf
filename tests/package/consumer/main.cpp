// Aligns scans 17 and 19 of MRPT's Telecom Faculty log with lidarseg's SegmentAlignment,
// then with mrpt::slam::CICP on the same maps from the same initial guess (the odometry),
// and fails unless the two agree within 5 cm and 0.5 degrees.
#include <cmath>
#include <iostream>

#include <mrpt/config/CConfigFile.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/slam/CICP.h>

#include <lidarseg/mrpt/RawlogScanReader.h>
#include <lidarseg/mrpt/SegmentAlignment.h>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: " << argv[0] << " TELECOM.rawlog [options.ini]\n";
    return 2;
  }
  // Two scans as point maps in the robot frame, and the odometry's motion between them.
  mrpt::maps::CSimplePointsMap previous_points, current_points;
  mrpt::poses::CPose2D previous_odometry, current_odometry;
  lidarseg::mrpt_adapter::RawlogScanReader reader(argv[1]);
  while (auto scan = reader.next()) {
    if (scan->scan_index == 17) {
      previous_points.insertObservation(*scan->observation);
      previous_odometry = scan->odometry.value();
    } else if (scan->scan_index == 19) {
      current_points.insertObservation(*scan->observation);
      current_odometry = scan->odometry.value();
      break;
    }
  }
  if (current_points.empty()) {
    std::cerr << argv[1] << ": fewer than 20 scans\n";
    return 1;
  }
  const mrpt::poses::CPosePDFGaussian initial_guess(current_odometry - previous_odometry);

  lidarseg::mrpt_adapter::SegmentAlignment align;  // where mrpt::slam::CICP icp; would be
  if (argc > 2) {  // as with CICP::TConfigParams, a missing section keeps the defaults
    align.options.loadFromConfigFile(mrpt::config::CConfigFile(argv[2]), "segment_alignment");
  }
  lidarseg::mrpt_adapter::SegmentAlignment::TReturnInfo info;
  const auto pdf = align.AlignPDF(&previous_points, &current_points, initial_guess, info);
  const mrpt::poses::CPose2D T_previous_current = pdf->getMeanVal();

  mrpt::slam::CICP icp;
  mrpt::slam::CICP::TReturnInfo icp_info;
  const mrpt::poses::CPose2D T_previous_current_icp =
      icp.AlignPDF(&previous_points, &current_points, initial_guess, icp_info)->getMeanVal();

  std::cout << "initial guess     " << initial_guess.mean << "\n"
            << "SegmentAlignment  " << T_previous_current << "  " << lidarseg::toString(info.status)
            << ", " << info.matches << " segment couples, goodness " << info.goodness << ", "
            << info.nIterations << " iterations, " << info.executionTime * 1e3 << " ms\n"
            << "CICP              " << T_previous_current_icp << "  goodness " << icp_info.goodness
            << ", " << icp_info.nIterations << " iterations, " << icp_info.executionTime * 1e3
            << " ms\n";
  const double dxy_m = std::hypot(T_previous_current.x() - T_previous_current_icp.x(),
                                  T_previous_current.y() - T_previous_current_icp.y());
  const double dyaw_deg =
      mrpt::RAD2DEG(mrpt::math::wrapToPi(T_previous_current.phi() - T_previous_current_icp.phi()));
  std::cout << "difference        " << dxy_m * 100 << " cm, " << dyaw_deg
            << " deg (at most 5 cm, 0.5 deg)\n";
  return dxy_m <= 0.05 && std::abs(dyaw_deg) <= 0.5 ? 0 : 1;
}
