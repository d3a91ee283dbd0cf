#include "lidarseg/core/CorrelativeSearch.h"
#include "lidarseg/core/Angles.h"

#include <algorithm>
#include <cmath>

#include "Validation.h"

namespace lidarseg {

namespace {


struct Grid {
  double x0 = 0.0, y0 = 0.0, res = 0.05;
  int w = 0, h = 0;
  std::vector<float> fine;    // likelihood, 0..1
  std::vector<float> coarse;  // max of fine over [i, i + k) x [j, j + k)
  std::vector<float> tmp;
  float at(const std::vector<float>& g, int i, int j) const {
    return (i < 0 || j < 0 || i >= w || j >= h) ? 0.0f : g[static_cast<std::size_t>(j) * w + i];
  }
};

struct Coarse {
  float bound;
  int rot, ix, iy;
};

struct Workspace {
  Grid grid;
  std::vector<Eigen::Vector2d> pts;
  std::vector<int> cells;  // per rotation: (ci, cj) of every used point, at the prior translation
  std::vector<Coarse> candidates;
};

bool finite(const Eigen::Vector2d& p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }

void buildGrid(const std::vector<Eigen::Vector2d>& key, const SearchParams& P, Grid& g) {
  double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
  for (const auto& p : key) {
    if (!finite(p)) continue;
    xmin = std::min(xmin, p.x());
    xmax = std::max(xmax, p.x());
    ymin = std::min(ymin, p.y());
    ymax = std::max(ymax, p.y());
  }
  g.res = P.resolution_m;
  const double margin = 3.0 * P.sigma_m + P.resolution_m;
  const double half = 0.5 * static_cast<double>(P.max_grid_cells) * g.res;
  // Clipped around the sensor: beyond, points are ignored (bounded memory).
  xmin = std::max(xmin - margin, -half);
  ymin = std::max(ymin - margin, -half);
  xmax = std::min(xmax + margin, half);
  ymax = std::min(ymax + margin, half);
  g.x0 = xmin;
  g.y0 = ymin;
  g.w = std::max(1, static_cast<int>(std::ceil((xmax - xmin) / g.res)));
  g.h = std::max(1, static_cast<int>(std::ceil((ymax - ymin) / g.res)));
  const std::size_t cells = static_cast<std::size_t>(g.w) * static_cast<std::size_t>(g.h);
  g.fine.assign(cells, 0.0f);
  const int r = static_cast<int>(std::ceil(3.0 * P.sigma_m / g.res));
  const double inv2s2 = 1.0 / (2.0 * P.sigma_m * P.sigma_m);
  for (const auto& p : key) {
    if (!finite(p)) continue;
    const double fx = (p.x() - g.x0) / g.res, fy = (p.y() - g.y0) / g.res;
    if (fx < -r || fy < -r || fx > g.w + r || fy > g.h + r) continue;
    const int ci = static_cast<int>(std::floor(fx)), cj = static_cast<int>(std::floor(fy));
    for (int j = std::max(0, cj - r); j <= std::min(g.h - 1, cj + r); ++j) {
      for (int i = std::max(0, ci - r); i <= std::min(g.w - 1, ci + r); ++i) {
        const double dx = (i + 0.5) * g.res + g.x0 - p.x(), dy = (j + 0.5) * g.res + g.y0 - p.y();
        const float v = static_cast<float>(std::exp(-(dx * dx + dy * dy) * inv2s2));
        float& cell = g.fine[static_cast<std::size_t>(j) * g.w + i];
        cell = std::max(cell, v);
      }
    }
  }
  // Sliding maximum over k cells, rows then columns.
  const int k = static_cast<int>(P.coarse_cells);
  g.tmp.assign(cells, 0.0f);
  g.coarse.assign(cells, 0.0f);
  for (int j = 0; j < g.h; ++j) {
    for (int i = 0; i < g.w; ++i) {
      float m = 0.0f;
      for (int d = 0; d < k && i + d < g.w; ++d) m = std::max(m, g.fine[static_cast<std::size_t>(j) * g.w + i + d]);
      g.tmp[static_cast<std::size_t>(j) * g.w + i] = m;
    }
  }
  for (int j = 0; j < g.h; ++j) {
    for (int i = 0; i < g.w; ++i) {
      float m = 0.0f;
      for (int d = 0; d < k && j + d < g.h; ++d) m = std::max(m, g.tmp[static_cast<std::size_t>(j + d) * g.w + i]);
      g.coarse[static_cast<std::size_t>(j) * g.w + i] = m;
    }
  }
}

}  // namespace

void SearchParams::validate() const {
  detail::requireInRange("linear_window_m", linear_window_m, 0.0, 20.0);
  detail::requireInRange("angular_window_rad", angular_window_rad, 0.0, 3.15);
  detail::requireInRange("resolution_m", resolution_m, 0.005, 1.0);
  detail::requirePositive("sigma_m", sigma_m);
  if (sigma_m > 20.0 * resolution_m) detail::failKey("sigma_m", "<= 20 * resolution_m", sigma_m);
  detail::requireInRange("angular_step_rad", angular_step_rad, 0.0, 0.5);
  if (max_points < 3 || max_points > 5000) detail::failKey("max_points", "in [3, 5000]", static_cast<double>(max_points));
  if (coarse_cells < 1 || coarse_cells > 32) detail::failKey("coarse_cells", "in [1, 32]", static_cast<double>(coarse_cells));
  if (max_grid_cells < 16 || max_grid_cells > 4000) {
    detail::failKey("max_grid_cells", "in [16, 4000]", static_cast<double>(max_grid_cells));
  }
  if (linear_window_m / resolution_m > 400.0) {
    detail::failKey("linear_window_m", "<= 400 * resolution_m", linear_window_m);
  }
}

CorrelativeSearch::CorrelativeSearch(const SearchParams& params) : params_(params) { params_.validate(); }

SearchResult CorrelativeSearch::search(const std::vector<Eigen::Vector2d>& keyframe_points,
                                       const std::vector<Eigen::Vector2d>& current_points,
                                       const Pose2D& prior) const {
  const SearchParams& P = params_;
  SearchResult result;
  result.T_key_curr = prior;
  thread_local Workspace ws;
  ws.pts.clear();
  std::size_t valid = 0;
  for (const auto& p : current_points) valid += finite(p);
  if (valid < 3) return result;
  const double stride = std::max(1.0, static_cast<double>(valid) / static_cast<double>(P.max_points));
  double next = 0.0, max_range = 0.0;
  std::size_t k = 0;
  for (const auto& p : current_points) {
    if (!finite(p)) continue;
    if (static_cast<double>(k++) >= next) {
      ws.pts.push_back(p);
      max_range = std::max(max_range, p.norm());
      next += stride;
    }
  }
  buildGrid(keyframe_points, P, ws.grid);
  const Grid& g = ws.grid;
  double step = P.angular_step_rad;
  if (!(step > 0.0)) step = std::clamp(P.resolution_m / std::max(max_range, 1e-3), 0.5 * kDegToRad, 2.0 * kDegToRad);
  const int A = static_cast<int>(std::floor(P.angular_window_rad / step + 1e-9));
  const int W = static_cast<int>(std::floor(P.linear_window_m / P.resolution_m + 1e-9));
  const int K = static_cast<int>(P.coarse_cells);
  const int n = static_cast<int>(ws.pts.size());
  const float inv_n = 1.0f / static_cast<float>(n);
  const int rotations = 2 * A + 1;

  // Cells of every point at each rotation and at the prior translation.
  ws.cells.resize(static_cast<std::size_t>(rotations) * n * 2);
  for (int a = 0; a < rotations; ++a) {
    const double yaw = prior.yaw + (a - A) * step;
    const double c = std::cos(yaw), s = std::sin(yaw);
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector2d& p = ws.pts[static_cast<std::size_t>(i)];
      const double x = prior.x + c * p.x() - s * p.y(), y = prior.y + s * p.x() + c * p.y();
      const double fx = std::clamp((x - g.x0) / g.res, -1e6, 1e6), fy = std::clamp((y - g.y0) / g.res, -1e6, 1e6);
      ws.cells[(static_cast<std::size_t>(a) * n + i) * 2] = static_cast<int>(std::floor(fx));
      ws.cells[(static_cast<std::size_t>(a) * n + i) * 2 + 1] = static_cast<int>(std::floor(fy));
    }
  }
  const auto score = [&](const std::vector<float>& grid, int a, int dx, int dy) {
    float sum = 0.0f;
    const int* c = &ws.cells[static_cast<std::size_t>(a) * n * 2];
    for (int i = 0; i < n; ++i) sum += g.at(grid, c[2 * i] + dx, c[2 * i + 1] + dy);
    return sum * inv_n;
  };
  result.prior_score = score(g.fine, A, 0, 0);

  // Coarse bounds: block (ix, iy) covers offsets [ix, ix + K) x [iy, iy + K).
  ws.candidates.clear();
  for (int a = 0; a < rotations; ++a) {
    for (int iy = -W; iy <= W; iy += K) {
      for (int ix = -W; ix <= W; ix += K) {
        ws.candidates.push_back({score(g.coarse, a, ix, iy), a, ix, iy});
      }
    }
  }
  result.bounds = ws.candidates.size();
  std::sort(ws.candidates.begin(), ws.candidates.end(), [](const Coarse& l, const Coarse& r) {
    return l.bound > r.bound || (l.bound == r.bound && std::abs(l.rot) < std::abs(r.rot));
  });
  float best = -1.0f;
  double best_cost = 0.0;
  int best_a = A, best_x = 0, best_y = 0;
  for (const Coarse& c : ws.candidates) {
    if (c.bound < best) break;
    for (int dy = c.iy; dy < std::min(c.iy + K, W + 1); ++dy) {
      for (int dx = c.ix; dx < std::min(c.ix + K, W + 1); ++dx) {
        const float s = score(g.fine, c.rot, dx, dy);
        ++result.evaluated;
        // Ties go to the pose nearest the prior.
        const double cost = std::hypot(dx * P.resolution_m, dy * P.resolution_m) + std::abs(c.rot - A) * step;
        if (s > best || (s == best && cost < best_cost)) {
          best = s;
          best_cost = cost;
          best_a = c.rot;
          best_x = dx;
          best_y = dy;
        }
      }
    }
  }
  result.found = best > 0.0f;
  result.score = std::max(0.0f, best);
  result.T_key_curr = {prior.x + best_x * P.resolution_m, prior.y + best_y * P.resolution_m,
                       wrapAngle(prior.yaw + (best_a - A) * step)};
  return result;
}

}  // namespace lidarseg
