#include "lidarseg/report/BatchResults.h"
#include "lidarseg/report/Baselines.h"
#include "lidarseg/core/NumberText.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "lidarseg/eval/Csv.h"
#include "lidarseg/report/OutputFiles.h"
#include "lidarseg/report/Plots.h"

namespace lidarseg::report {

namespace fs = std::filesystem;

namespace {

// The seed a run folder's name gives: run_<seed> with the seed in decimal, exactly.
std::optional<std::uint64_t> folderSeed(const std::string& name) {
  if (name.rfind("run_", 0) != 0 || name.size() == 4) return std::nullopt;
  std::uint64_t seed = 0;
  const char* first = name.data() + 4;
  const char* last = name.data() + name.size();
  const auto [end, error] = std::from_chars(first, last, seed);
  if (error != std::errc() || end != last || (*first == '0' && name.size() > 5)) return std::nullopt;
  return seed;
}

// The metrics.csv of every finished run in OUT, with its folder's seed: run_<seed>/, not
// run_<seed>.partial/. A run folder without one, or named otherwise, is a warning.
std::vector<std::pair<std::uint64_t, fs::path>> finishedMetricsFiles(const std::string& out_dir,
                                                                     std::vector<std::string>& warnings) {
  if (!fs::is_directory(out_dir)) throw std::runtime_error("'" + out_dir + "' is not a folder");
  std::vector<std::pair<std::uint64_t, fs::path>> files;
  for (const auto& entry : fs::directory_iterator(out_dir)) {
    const auto name = entry.path().filename().string();
    if (!entry.is_directory() || name.rfind("run_", 0) != 0 || name.find('.') != std::string::npos) continue;
    const std::optional<std::uint64_t> seed = folderSeed(name);
    if (!seed) {
      warnings.push_back("'" + entry.path().string() + "' is not named run_SEED (SEED from 0 to 18446744073709551615); left out");
    } else if (!fs::exists(entry.path() / "metrics.csv")) {
      warnings.push_back("'" + entry.path().string() + "' holds no metrics.csv (a run not finished); left out");
    } else {
      files.emplace_back(*seed, entry.path() / "metrics.csv");
    }
  }
  return files;
}

// Whether a metric may be negative: the means of signed motion errors.
bool signedMetric(const std::string& name) {
  return name.find("_edx_m") != std::string::npos || name.find("_edy_m") != std::string::npos ||
         name.find("_edtheta_rad") != std::string::npos;
}

// A metric's value, checked: finite, within kMaxMetric (kMaxFrames for frames), not negative
// unless signed. Throws naming FILE:LINE:COLUMN.
double checkedMetric(const std::string& cell, const std::string& name, const std::string& where) {
  const ParsedNumber parsed = parseNumber(cell);
  if (parsed.status == ParsedNumber::Status::not_a_number) throw std::runtime_error(where + ": '" + cell + "' is not a number");
  // A NEES has no bound a run's figure could be checked against (a covariance far too small
  // gives millions): any finite, non-negative value.
  const double cap = name == "frames"                         ? kMaxBatchFrames
                     : name.rfind("lidarseg_nees_", 0) == 0 ? std::numeric_limits<double>::max()
                                                            : kMaxBatchMetric;
  const double v = parsed.value;
  if (!parsed.ok() || !std::isfinite(v) || std::abs(v) > cap || (v < 0 && !signedMetric(name))) {
    throw std::runtime_error(where + ": " + name + " = '" + cell + "' is not a run's figure (finite, " +
                             (signedMetric(name) ? "within +-" : "from 0 to ") + numberText(cap) + ")");
  }
  return v;
}

// The data line of one metrics.csv of the folder of `seed`: the seed, then one value per
// metric; the seed read exactly (a double rounds seeds beyond 2^53).
std::vector<double> readMetricsRow(std::uint64_t seed, const fs::path& f) {
  std::ifstream in(f);
  eval::CsvReader reader(in, f.string());
  std::vector<std::string> cells;
  if (!reader.next(cells) || !reader.next(cells)) {
    throw std::runtime_error(f.string() + ":2: missing the data line");
  }
  const std::size_t columns = batchMetricNames().size() + 1;
  if (cells.size() != columns) {
    throw std::runtime_error(reader.where() + ": " + std::to_string(cells.size()) + " values, expected " +
                             std::to_string(columns) + " (a run of another version? remove its folder to run it again)");
  }
  std::uint64_t own = 0;
  const auto [end, error] = std::from_chars(cells[0].data(), cells[0].data() + cells[0].size(), own);
  if (error != std::errc() || end != cells[0].data() + cells[0].size() || own != seed) {
    throw std::runtime_error(reader.where() + ":1: seed '" + cells[0] + "' is not its folder's (run_" +
                             std::to_string(seed) + ")");
  }
  std::vector<double> row = {static_cast<double>(seed)};
  for (std::size_t c = 1; c < cells.size(); ++c) {
    const std::string where = reader.where() + ":" + std::to_string(c + 1);
    row.push_back(cells[c].empty() ? std::nan("") : checkedMetric(cells[c], batchMetricNames()[c - 1], where));
  }
  return row;
}

}  // namespace

// The per-run figures aggregated over runs, in metrics.csv's column order.
const std::vector<std::string>& batchMetricNames() {
  // clang-format off
  static const std::vector<std::string> names = {
      "frames",
      "lidarseg_final_error_m", "lidarseg_ate_rmse_m", "lidarseg_t_ms", "lidarseg_sigma_t_ms",
      "lidarseg_median_ms", "lidarseg_p99_ms", "lidarseg_edx_m", "lidarseg_sigma_edx_m", "lidarseg_edy_m",
      "lidarseg_sigma_edy_m", "lidarseg_edtheta_rad", "lidarseg_sigma_edtheta_rad",
      "icp_final_error_m", "icp_ate_rmse_m", "icp_t_ms", "icp_sigma_t_ms", "icp_median_ms", "icp_p99_ms",
      "icp_edx_m", "icp_sigma_edx_m", "icp_edy_m", "icp_sigma_edy_m", "icp_edtheta_rad",
      "icp_sigma_edtheta_rad", "speedup_median", "path_length_m", "lidarseg_nees_mean",
      "lidarseg_nees_median", "lidarseg_nees_share_95"};
  // clang-format on
  return names;
}

// The column of a metric in a MetricRows row (column 0 is the seed).
std::size_t metricColumn(const std::string& name) {
  const auto& names = batchMetricNames();
  return 1 + static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin());
}

// One run's figures in batchMetricNames() order; NaN for what was not measured.
std::vector<double> runMetrics(const OdometryReport& r) {
  const auto method = [](const MethodReport* m, std::vector<double>& out) {
    if (!m || !m->errors) {
      out.insert(out.end(), 12, std::nan(""));
      return;
    }
    const auto& e = *m->errors;
    const auto& t = m->time_summary_us;
    out.insert(out.end(), {e.final_position_error_m, e.ate_rmse_m, t.mean * 1e-3, t.stddev * 1e-3,
                           t.median * 1e-3, t.p99 * 1e-3, e.motion.dx_m.mean, e.motion.dx_m.stddev,
                           e.motion.dy_m.mean, e.motion.dy_m.stddev, e.motion.dtheta_rad.mean,
                           e.motion.dtheta_rad.stddev});
  };
  std::vector<double> out = {static_cast<double>(r.frames)};
  method(&r.lidarseg, out);
  const MethodReport* icp = r.baseline(kSpeedupBaseline);
  method(icp, out);
  out.push_back(icp ? r.speedup_median : std::nan(""));  // no ratio without ICP
  out.push_back(r.lidarseg.errors ? r.lidarseg.errors->path_length_m : std::nan(""));
  const bool nees = r.lidarseg.nees && r.lidarseg.nees->evaluated > 0;
  out.push_back(nees ? r.lidarseg.nees->mean : std::nan(""));
  out.push_back(nees ? r.lidarseg.nees->median : std::nan(""));
  out.push_back(nees ? r.lidarseg.nees->share_within_95 : std::nan(""));
  return out;
}

// The header line of metrics.csv and aggregate.csv: "seed", then batchMetricNames().
std::string metricsHeader() {
  std::string header = "seed";
  for (const auto& n : batchMetricNames()) header += ',' + n;
  return header + '\n';
}

// A line of metrics.csv and aggregate.csv: the seed, then the figures (10 significant
// digits); a figure not measured (a baseline not run) is an empty cell, never "nan".
std::string metricsLine(std::uint64_t seed, const std::vector<double>& values) {
  std::ostringstream line;
  line << seed << std::setprecision(10);
  for (double v : values) {
    line << ',';
    if (std::isfinite(v)) line << v;
  }
  line << '\n';
  return line.str();
}

// Every finished run's row, in seed order, with its exact seed.
FinishedRuns readFinishedRuns(const std::string& out_dir) {
  FinishedRuns runs;
  auto files = finishedMetricsFiles(out_dir, runs.warnings);
  std::sort(files.begin(), files.end());
  for (const auto& [seed, f] : files) {
    runs.rows.push_back(readMetricsRow(seed, f));
    runs.seeds.push_back(seed);
  }
  if (runs.rows.empty())
    throw std::runtime_error("no finished run (run_*/metrics.csv) in '" + out_dir + "'");
  return runs;
}

// Mean (and spread) of each metric over the runs; NaN values are left out.
MetricStats metricStats(const MetricRows& rows) {
  MetricStats stats;
  for (std::size_t c = 0; c < batchMetricNames().size(); ++c) {
    std::vector<double> v;
    for (const auto& r : rows) {
      if (std::isfinite(r[c + 1])) v.push_back(r[c + 1]);
    }
    stats[batchMetricNames()[c]] = summarize(v);
  }
  return stats;
}

// table1.md: the paper's Table I, one row per method that ran, then the median times per scan.
std::string table1Markdown(const std::string& title, const std::vector<std::uint64_t>& seeds,
                           const MetricStats& stats) {
  std::ostringstream md;
  md << std::fixed;
  md << "## " << title << "\n\n"
     << seeds.size() << " runs (seeds " << seeds.front() << "–" << seeds.back()
     << "), mean over runs of each run's figures (paper Table I).\n\n";
  md << "| method | t (ms) | σt (ms) | edx (mm) | σedx (mm) | edy (mm) | σedy (mm) | edθ (mrad) | "
        "σedθ (mrad) | final error (m): mean | median | max | ATE RMSE (m) |\n";
  md << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const std::string m : {"lidarseg", "icp"}) {
    const auto g = [&](const std::string& k) { return stats.at(m + "_" + k); };
    if (g("final_error_m").count == 0) continue;
    md << "| " << (m == "icp" ? "MRPT ICP" : m) << std::setprecision(4) << " | " << g("t_ms").mean
       << " | " << g("sigma_t_ms").mean << std::setprecision(2) << " | " << g("edx_m").mean * 1e3
       << " | " << g("sigma_edx_m").mean * 1e3 << " | " << g("edy_m").mean * 1e3 << " | "
       << g("sigma_edy_m").mean * 1e3 << " | " << g("edtheta_rad").mean * 1e3 << " | "
       << g("sigma_edtheta_rad").mean * 1e3 << std::setprecision(3) << " | "
       << g("final_error_m").mean << " | " << g("final_error_m").median << " | "
       << g("final_error_m").max << " | " << g("ate_rmse_m").mean << " |\n";
  }
  if (stats.at("speedup_median").count > 0) {
    md << "\nMedian time per scan: lidarseg " << std::setprecision(4)
       << stats.at("lidarseg_median_ms").median * 1e3 << " µs, MRPT ICP "
       << stats.at("icp_median_ms").median * 1e3 << " µs; speed-up (median over runs of each "
       << "run's median ratio) " << std::setprecision(1) << stats.at("speedup_median").median
       << "x. Path length " << std::setprecision(1) << stats.at("path_length_m").mean << " m.\n";
  } else if (stats.at("lidarseg_median_ms").count > 0) {  // --no-icp: no ratio to give
    md << "\nMedian time per scan: lidarseg " << std::setprecision(4)
       << stats.at("lidarseg_median_ms").median * 1e3 << " µs (MRPT ICP not run). Path length "
       << std::setprecision(1) << stats.at("path_length_m").mean << " m.\n";
  }
  if (stats.at("lidarseg_nees_mean").count > 0) {
    md << "\nlidarseg's covariance against the ground truth (NEES of each scan's motion from its keyframe; "
          "chi-square(3): mean 3, median 2.37, 95 % at or below 7.81): mean over runs of each run's mean "
       << std::setprecision(2) << stats.at("lidarseg_nees_mean").mean << ", of its median "
       << stats.at("lidarseg_nees_median").mean << ", of its share at or below 7.81 " << std::setprecision(1)
       << 100.0 * stats.at("lidarseg_nees_share_95").mean << " %.\n";
  }
  return md.str();
}

// aggregate.csv: every run's metrics.csv line under one header.
std::string aggregateCsv(const FinishedRuns& runs) {
  std::string csv = metricsHeader();
  for (std::size_t i = 0; i < runs.rows.size(); ++i) {
    const auto& r = runs.rows[i];
    csv += metricsLine(runs.seeds[i], {r.begin() + 1, r.end()});
  }
  return csv;
}

std::vector<std::uint64_t> parseSeeds(const std::string& text) {
  constexpr std::uint64_t kMaxRuns = 100000;
  std::vector<std::uint64_t> seeds;
  for (const std::string& part : eval::splitCsvLine(text)) {
    std::uint64_t lo = 0, count = 1;  // the seeds lo, lo + 1, ..., lo + count - 1
    try {
      const auto dash = part.find('-');
      const std::string a = part.substr(0, dash);
      std::size_t ua = 0;
      lo = std::stoull(a, &ua);
      if (ua != a.size()) throw std::invalid_argument(part);
      if (dash != std::string::npos) {
        const std::string b = part.substr(dash + 1);
        std::size_t ub = 0;
        const auto hi = std::stoull(b, &ub);
        if (ub != b.size() || hi < lo || hi - lo > kMaxRuns) throw std::invalid_argument(part);
        count = hi - lo + 1;
      }
    } catch (const std::exception&) {
      throw std::invalid_argument("seeds: '" + part + "' is not a seed or a range like 1-50");
    }
    // Counted before a range is expanded: a long list of ranges must not fill memory before
    // the cap is checked (issue 16; a seed asked for twice counts twice).
    if (seeds.size() + count > kMaxRuns) throw std::invalid_argument("seeds: more than 100000 runs asked for");
    for (std::uint64_t k = 0; k < count; ++k) seeds.push_back(lo + k);  // no wrap at the top of uint64
  }
  if (seeds.empty()) throw std::invalid_argument("seeds: none given");
  std::sort(seeds.begin(), seeds.end());
  seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
  return seeds;
}

void claimExperiment(const std::string& out_dir, const std::string& mine) {
  const std::string path = (fs::path(out_dir) / "experiment.txt").string();
  std::ifstream in(path);
  if (in) {
    const std::string theirs((std::istreambuf_iterator<char>(in)), {});
    if (theirs != mine) {
      throw std::runtime_error("'" + out_dir + "' holds the runs of another experiment (" + path +
                               " differs: world, trajectory, sensor, configurations or baselines); "
                               "choose another --out");
    }
    return;
  }
  fs::create_directories(out_dir);
  writeFileAtomically(path, mine);
}

std::string finalErrorsPng(const MetricRows& rows, bool with_icp, const std::string& title) {
  const std::size_t lidarseg = metricColumn("lidarseg_final_error_m");
  const std::size_t icp = metricColumn("icp_final_error_m");
  PlotSeries a = makeSeries("lidarseg", kLidarsegColour, PlotStyle::kMarkers);
  PlotSeries b = makeSeries("MRPT ICP keyframed", kIcpColour, PlotStyle::kMarkers);
  for (const auto& r : rows) {
    a.x.push_back(r[0]);
    a.y.push_back(r[lidarseg]);
    b.x.push_back(r[0]);
    b.y.push_back(r[icp]);
  }
  std::vector<PlotSeries> series = {a};
  if (with_icp) series.push_back(b);
  return plotXYPng(series, "Final position error per run: " + title, "seed", "final error (m)", true);
}

}  // namespace lidarseg::report
