#pragma once
/// @file SimulationFiles.h
/// The files of a simulated run (lidarseg-simulate, lidarseg-batch): PREFIX.rawlog (wheel
/// odometry, scans and camera images as MRPT observations), PREFIX_Images/, PREFIX.gt.tum,
/// PREFIX.odom.tum, PREFIX.features.csv, PREFIX.rois.csv and optionally PREFIX.carmen.log,
/// written scan by scan under temporary names and put in place together.

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>

#include "lidarseg/mrpt/GzipOutputStream.h"
#include "lidarseg/report/OutputFiles.h"
#include "lidarseg/sim/Simulation.h"
#include "lidarseg/sim/World.h"

namespace lidarseg::pipeline {

/// What a simulated run wrote so far.
struct SimulationCounts {
  std::size_t scans = 0;             ///< scans written
  std::size_t images = 0;            ///< camera images written (PREFIX_Images/)
  std::size_t door_sightings = 0;    ///< rows of PREFIX.features.csv that are doors
  std::size_t corner_sightings = 0;  ///< rows of PREFIX.features.csv that are corners
};

/// Creates the folder of `prefix`, and an empty PREFIX_Images.tmp/ when the run has a camera,
/// registered for the SIGINT/SIGTERM cleanup like the files' temporaries. Its name is fixed
/// (the folder lock keeps a second run away): a killed run's is removed by the next.
void prepareSimulationFolders(const std::string& prefix, bool camera);

/// Every output of a simulated run, written scan by scan under temporary names; commit()
/// publishes them, PREFIX.rawlog last (docs/reliability.md, "Publishing a set"). Destroyed
/// without commit(), it leaves no temporary.
class SimulationFiles {
 public:
  /// Opens every output (PREFIX.rawlog last) and writes the text files' headers.
  /// `world_path` and params.seed are named in the CARMEN log's comment.
  /// @throws std::runtime_error naming a file that cannot be written.
  SimulationFiles(const std::string& prefix, const sim::SimulationParams& params,
                  const sim::World& world, const std::string& world_path, bool write_carmen);
  /// Scan `i` with its truth, odometry, sightings and image, in every output.
  void write(std::size_t i, const sim::SimulatedFrame& f);
  /// Renames every output to its final name: removes the PREFIX.rawlog it replaces, then puts
  /// PREFIX_Images/, the text files and `companions` (e.g. a generated building's files) in
  /// place, and the rawlog last. A reader who finds PREFIX.rawlog finds its images beside it.
  /// @throws std::runtime_error "cannot write 'PREFIX.rawlog': why" when the end of the
  ///         rawlog's gzip stream cannot be written (nothing is then published), or
  ///         (std::filesystem::filesystem_error) naming the file that could not be replaced;
  ///         the folder then holds no PREFIX.rawlog.
  void commit(const std::vector<report::PendingFile*>& companions = {});
  /// What was written so far.
  const SimulationCounts& counts() const { return counts_; }
  ~SimulationFiles();
  SimulationFiles(const SimulationFiles&) = delete;
  SimulationFiles& operator=(const SimulationFiles&) = delete;

 private:
  void writeRawlogScan(const sim::SimulatedFrame& f);
  void writeImage(std::size_t i, const sim::SimulatedFrame& f, std::size_t image);
  void publishImages();

  bool committed_ = false;
  SimulationCounts counts_;
  std::string prefix_;
  const sim::SimulationParams& params_;
  const sim::World& world_;
  const mrpt::poses::CPose3D lidar_pose_;
  report::PendingFile gt_, odom_, features_, rois_;
  std::unique_ptr<report::PendingFile> carmen_;
  std::string rawlog_tmp_;  // registered for the SIGINT/SIGTERM cleanup
  mrpt_adapter::GzipOutputStream rawlog_;  // every write and the stream's end checked
  mrpt::serialization::CArchiveStreamBase<mrpt_adapter::GzipOutputStream> archive_{rawlog_};
};

}  // namespace lidarseg::pipeline
