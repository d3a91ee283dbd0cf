#include "lidarseg/core/CorrelativeSearch.h"
#include "lidarseg/core/Angles.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "Validation.h"

namespace lidarseg {

namespace {

bool finite(const Eigen::Vector2d& p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }

// Every level is stored with `pad` extra cells on each side, so that a block starting left of
// (or below) the grid still reads the maximum over the part of it inside the grid, and one
// unsigned comparison tells whether a lookup falls outside (likelihood 0).
struct Padded {
  int pad = 0, w = 0, h = 0;  // padded sides
  int at(const std::vector<SearchGrid::Cell>& g, int i, int j) const {
    const int pi = i + pad, pj = j + pad;
    return (static_cast<unsigned>(pi) >= static_cast<unsigned>(w) || static_cast<unsigned>(pj) >= static_cast<unsigned>(h))
               ? 0
               : g[static_cast<std::size_t>(pj) * static_cast<std::size_t>(w) + static_cast<std::size_t>(pi)];
  }
};

Padded paddedOf(const SearchGrid& g) { return {g.pad, g.w + 2 * g.pad, g.h + 2 * g.pad}; }

// A block of poses: rotation index, first translation offsets (cells), and the bound (or,
// for a single cell, the exact score) of every pose in it, as a sum of quantised cells.
struct Block {
  int bound;
  int rot, ix, iy;
};

// The points of each rotation, at the prior translation, in two kinds: those whose cell
// stays inside the padded grid at every translation of the window ("inside": a linear index,
// read without a test), and the others (their cell, each lookup tested). A point outside at
// every translation scores 0 and is left out. Scores are sums of integers, so the order of
// the terms changes nothing.
struct Workspace {
  std::vector<Eigen::Vector2d> pts;
  std::vector<int> linear;  // per rotation: the inside points' linear indices (padded grid), first `inside[rot]`
  std::vector<int> cells;   // per rotation: (ci, cj) of the other points, from `inside[rot]` to `used[rot]`
  std::vector<int> inside, used;
  std::vector<Block> top;
};

// The depth-first branch and bound below the top level: children best bound first, a branch
// dropped as soon as its bound is below the best score found (ties are kept, so the pose
// nearest the prior among equal scores is found as by the full search).
class BranchAndBound {
 public:
  // Only poses scoring above `floor` (a sum of cells) are looked for.
  BranchAndBound(const SearchGrid& g, const Workspace& ws, int n, int W, int A, double step, int floor,
                 SearchResult& result)
      : g_(g), pad_(paddedOf(g)), ws_(ws), n_(n), W_(W), A_(A), step_(step), result_(result), best_(floor) {}

  // The sum of the points' cells (integers: exact, so the bounds hold to the last unit), at
  // translation offsets (dx, dy) within the window (|dx|, |dy| <= W).
  int score(std::size_t level, int rot, int dx, int dy) const {
    const std::vector<SearchGrid::Cell>& grid = g_.levels[level];
    const std::size_t r = static_cast<std::size_t>(rot);
    const std::size_t first = r * static_cast<std::size_t>(n_);
    const int inside = ws_.inside[r], used = ws_.used[r];
    const int* lin = &ws_.linear[first];
    const SearchGrid::Cell* cell = grid.data();
    const int shift = dy * pad_.w + dx;  // lin[i] + shift is in the padded grid for inside points
    int sum = 0;
    for (int i = 0; i < inside; ++i) sum += cell[lin[i] + shift];
    const int* c = &ws_.cells[2 * first];
    for (int i = inside; i < used; ++i) sum += pad_.at(grid, c[2 * i] + dx, c[2 * i + 1] + dy);
    return sum;
  }
  // A score as the mean likelihood of the points, in [0, 1].
  double meanLikelihood(int sum) const { return static_cast<double>(sum) / (SearchGrid::kCellMax * static_cast<double>(n_)); }

  // A pose whose exact score is known.
  void leaf(const Block& b) {
    ++result_.evaluated;
    const double cost = std::hypot(b.ix * g_.res, b.iy * g_.res) + std::abs(b.rot - A_) * step_;
    if (b.bound > best_ || (found_ && b.bound == best_ && cost < best_cost_)) {
      best_ = b.bound;
      best_cost_ = cost;
      best_block_ = b;
      found_ = true;
    }
  }

  // Block `b` of side sides[level] (its bound already compared with the best).
  void descend(const Block& b, std::size_t level) {
    if (g_.sides[level] == 1) {
      leaf(b);
      return;
    }
    const std::size_t next = level + 1;
    const int c = g_.sides[next];
    std::array<Block, 4> children;
    int count = 0;
    for (int oy = 0; oy < 2; ++oy) {
      for (int ox = 0; ox < 2; ++ox) {
        const int ix = b.ix + ox * c, iy = b.iy + oy * c;
        if (ix > W_ || iy > W_) continue;  // 2c >= s: the children cover the block
        children[static_cast<std::size_t>(count++)] = {score(next, b.rot, ix, iy), b.rot, ix, iy};
      }
    }
    if (g_.sides[next] > 1) result_.bounds += static_cast<std::size_t>(count);
    for (int a = 1; a < count; ++a) {  // at most four: insertion sort, best bound first
      const Block key = children[static_cast<std::size_t>(a)];
      int j = a - 1;
      for (; j >= 0 && children[static_cast<std::size_t>(j)].bound < key.bound; --j) {
        children[static_cast<std::size_t>(j + 1)] = children[static_cast<std::size_t>(j)];
      }
      children[static_cast<std::size_t>(j + 1)] = key;
    }
    for (int k = 0; k < count; ++k) {
      const Block& child = children[static_cast<std::size_t>(k)];
      if (child.bound < best_) break;
      descend(child, next);
    }
  }

  int best() const { return best_; }
  bool found() const { return found_; }
  const Block& bestBlock() const { return best_block_; }

 private:
  const SearchGrid& g_;
  Padded pad_;
  const Workspace& ws_;
  int n_, W_, A_;
  double step_;
  SearchResult& result_;
  int best_ = -1;
  bool found_ = false;
  double best_cost_ = 0.0;
  Block best_block_{0, 0, 0, 0};
};

}  // namespace

void SearchParams::validate() const {
  detail::requireInRange("linear_window_m", linear_window_m, 0.0, 20.0);
  detail::requireInRange("angular_window_rad", angular_window_rad, 0.0, 3.15);
  detail::requireInRange("resolution_m", resolution_m, 0.005, 1.0);
  detail::requireSigmaM("sigma_m", sigma_m, false);
  if (sigma_m > 20.0 * resolution_m) detail::failKey("sigma_m", "<= 20 * resolution_m", sigma_m);
  // 0 = automatic; otherwise at least kMinAngularStepRad, so that the number of rotations
  // tried (2 x angular_window_rad / step + 1, at most 12,601) stays bounded (issue 16).
  if (!(std::isfinite(angular_step_rad) &&
        (angular_step_rad == 0.0 || (angular_step_rad >= kMinAngularStepRad && angular_step_rad <= 0.5)))) {
    detail::failKey("angular_step_rad", "0 (automatic) or in [0.0005, 0.5]", angular_step_rad);
  }
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

void CorrelativeSearch::prepare(const std::vector<Eigen::Vector2d>& key, SearchGrid& g) const {
  const SearchParams& P = params_;
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
  if (!(xmax > xmin)) xmin = xmax = 0.0;
  if (!(ymax > ymin)) ymin = ymax = 0.0;
  g.x0 = xmin;
  g.y0 = ymin;
  g.w = std::max(1, static_cast<int>(std::ceil((xmax - xmin) / g.res)));
  g.h = std::max(1, static_cast<int>(std::ceil((ymax - ymin) / g.res)));

  // Block sides, top level first: coarse_cells, then halved (rounded up) down to 1.
  g.sides.clear();
  for (int s = static_cast<int>(P.coarse_cells); ; s = (s + 1) / 2) {
    g.sides.push_back(s);
    if (s == 1) break;
  }
  g.levels.resize(g.sides.size());
  // At least the top-level block (a block left of the grid reads what it covers of it), and
  // the search's translation window: the points of the keyframe's outermost walls then stay
  // inside the padded grid at every translation (read without a test).
  g.pad = std::max(g.sides.front(), static_cast<int>(std::floor(P.linear_window_m / P.resolution_m + 1e-9)));
  const Padded pad = paddedOf(g);
  const std::size_t cells = static_cast<std::size_t>(pad.w) * static_cast<std::size_t>(pad.h);

  // The likelihood: a Gaussian of sigma_m around each point (the maximum where they overlap).
  // exp(-(dx^2 + dy^2) / 2s^2) is the product of one factor per axis: 2(2r + 1) exponentials
  // per point instead of (2r + 1)^2.
  std::vector<SearchGrid::Cell>& fine = g.levels.back();
  fine.assign(cells, 0);
  const int r = static_cast<int>(std::ceil(3.0 * P.sigma_m / g.res));
  const double inv2s2 = 1.0 / (2.0 * P.sigma_m * P.sigma_m);
  thread_local std::vector<double> fx_factor, fy_factor;  // per point's window; kept between calls
  fx_factor.resize(static_cast<std::size_t>(2 * r + 1));
  fy_factor.resize(static_cast<std::size_t>(2 * r + 1));
  for (const auto& p : key) {
    if (!finite(p)) continue;
    const double fx = (p.x() - g.x0) / g.res, fy = (p.y() - g.y0) / g.res;
    if (fx < -r || fy < -r || fx > g.w + r || fy > g.h + r) continue;
    const int ci = static_cast<int>(std::floor(fx)), cj = static_cast<int>(std::floor(fy));
    const int i0 = std::max(0, ci - r), i1 = std::min(g.w - 1, ci + r);
    const int j0 = std::max(0, cj - r), j1 = std::min(g.h - 1, cj + r);
    for (int i = i0; i <= i1; ++i) {
      const double dx = (i + 0.5) * g.res + g.x0 - p.x();
      fx_factor[static_cast<std::size_t>(i - i0)] = std::exp(-dx * dx * inv2s2);
    }
    for (int j = j0; j <= j1; ++j) {
      const double dy = (j + 0.5) * g.res + g.y0 - p.y();
      fy_factor[static_cast<std::size_t>(j - j0)] = std::exp(-dy * dy * inv2s2);
    }
    for (int j = j0; j <= j1; ++j) {
      SearchGrid::Cell* row =
          &fine[static_cast<std::size_t>(j + pad.pad) * static_cast<std::size_t>(pad.w) + static_cast<std::size_t>(pad.pad)];
      const double ey = fy_factor[static_cast<std::size_t>(j - j0)] * SearchGrid::kCellMax;
      for (int i = i0; i <= i1; ++i) {
        // Rounded to nearest (the product is in [0, kCellMax]): no library call per cell.
        const auto v = static_cast<SearchGrid::Cell>(fx_factor[static_cast<std::size_t>(i - i0)] * ey + 0.5);
        row[i] = std::max(row[i], v);
      }
    }
  }
  // Each coarser level from the one below: a block of side s is covered by four blocks of
  // side c = ceil(s / 2) at offsets 0 and d = s - c; the maximum of the four in two passes
  // (rows, then columns), beyond the padded grid counting as 0.
  const std::size_t PW = static_cast<std::size_t>(pad.w), PH = static_cast<std::size_t>(pad.h);
  g.scratch.resize(cells);
  for (std::size_t l = g.sides.size() - 1; l-- > 0;) {
    const std::vector<SearchGrid::Cell>& below = g.levels[l + 1];
    std::vector<SearchGrid::Cell>& level = g.levels[l];
    level.resize(cells);  // every cell is written below
    const std::size_t d = static_cast<std::size_t>(g.sides[l] - g.sides[l + 1]);
    SearchGrid::Cell* t = g.scratch.data();
    for (std::size_t j = 0; j < PH; ++j) {
      const SearchGrid::Cell* b = &below[j * PW];
      SearchGrid::Cell* row = t + j * PW;
      const std::size_t inner = PW > d ? PW - d : 0;
      for (std::size_t i = 0; i < inner; ++i) row[i] = std::max(b[i], b[i + d]);
      for (std::size_t i = inner; i < PW; ++i) row[i] = b[i];
    }
    const std::size_t inner_rows = PH > d ? PH - d : 0;
    for (std::size_t j = 0; j < inner_rows; ++j) {
      const SearchGrid::Cell* a = t + j * PW;
      const SearchGrid::Cell* c = t + (j + d) * PW;
      SearchGrid::Cell* row = &level[j * PW];
      for (std::size_t i = 0; i < PW; ++i) row[i] = std::max(a[i], c[i]);
    }
    for (std::size_t j = inner_rows; j < PH; ++j) std::copy(t + j * PW, t + (j + 1) * PW, &level[j * PW]);
  }
  g.ready = true;
}

SearchResult CorrelativeSearch::search(const std::vector<Eigen::Vector2d>& keyframe_points,
                                       const std::vector<Eigen::Vector2d>& current_points,
                                       const Pose2D& prior) const {
  thread_local SearchGrid grid;
  prepare(keyframe_points, grid);
  return search(grid, current_points, prior);
}

SearchResult CorrelativeSearch::search(const SearchGrid& g, const std::vector<Eigen::Vector2d>& current_points,
                                       const Pose2D& prior, double min_score) const {
  const SearchParams& P = params_;
  SearchResult result;
  result.T_key_curr = prior;
  // A non-finite prior has no window (its grid indices would be undefined): nothing found.
  if (!g.ready || g.levels.empty() || !(std::isfinite(prior.x) && std::isfinite(prior.y) && std::isfinite(prior.yaw))) {
    return result;
  }
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
  double step = P.angular_step_rad;
  if (!(step > 0.0)) step = std::clamp(P.resolution_m / std::max(max_range, 1e-3), 0.5 * kDegToRad, 2.0 * kDegToRad);
  const int A = static_cast<int>(std::floor(P.angular_window_rad / step + 1e-9));
  const int W = static_cast<int>(std::floor(P.linear_window_m / P.resolution_m + 1e-9));
  const int K = g.sides.front();
  const int n = static_cast<int>(ws.pts.size());
  const int rotations = 2 * A + 1;

  // Cells of every point at each rotation and at the prior translation, sorted into the
  // kinds of Workspace. Every lookup is at an offset within [-W, W] of these cells.
  const Padded pad = paddedOf(g);
  const std::size_t per_rotation = static_cast<std::size_t>(n);
  ws.linear.resize(static_cast<std::size_t>(rotations) * per_rotation);
  ws.cells.resize(static_cast<std::size_t>(rotations) * per_rotation * 2);
  ws.inside.assign(static_cast<std::size_t>(rotations), 0);
  ws.used.assign(static_cast<std::size_t>(rotations), 0);
  const auto within = [W](int padded, int side) { return padded - W >= 0 && padded + W < side; };
  const auto reachable = [W](int padded, int side) { return padded + W >= 0 && padded - W < side; };
  for (int a = 0; a < rotations; ++a) {
    const double yaw = prior.yaw + (a - A) * step;
    const double c = std::cos(yaw), s = std::sin(yaw);
    const std::size_t first = static_cast<std::size_t>(a) * per_rotation;
    int inside = 0, other = 0;
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector2d& p = ws.pts[static_cast<std::size_t>(i)];
      const double x = prior.x + c * p.x() - s * p.y(), y = prior.y + s * p.x() + c * p.y();
      const double fx = std::clamp((x - g.x0) / g.res, -1e6, 1e6), fy = std::clamp((y - g.y0) / g.res, -1e6, 1e6);
      const int ci = static_cast<int>(std::floor(fx)), cj = static_cast<int>(std::floor(fy));
      const int pi = ci + pad.pad, pj = cj + pad.pad;
      if (within(pi, pad.w) && within(pj, pad.h)) {
        ws.linear[first + static_cast<std::size_t>(inside++)] = pj * pad.w + pi;
      } else if (reachable(pi, pad.w) && reachable(pj, pad.h)) {
        const std::size_t at = (first + static_cast<std::size_t>(n - 1 - other++)) * 2;  // filled from the end
        ws.cells[at] = ci;
        ws.cells[at + 1] = cj;
      }
    }
    // The others, moved to follow the inside points.
    if (inside < n - other) std::copy(ws.cells.begin() + static_cast<std::ptrdiff_t>((first + static_cast<std::size_t>(n - other)) * 2),
              ws.cells.begin() + static_cast<std::ptrdiff_t>((first + per_rotation) * 2),
              ws.cells.begin() + static_cast<std::ptrdiff_t>((first + static_cast<std::size_t>(inside)) * 2));
    ws.inside[static_cast<std::size_t>(a)] = inside;
    ws.used[static_cast<std::size_t>(a)] = inside + other;
  }
  const int floor_sum = min_score > 0.0
                            ? static_cast<int>(std::llround(std::min(min_score, 1.0) * SearchGrid::kCellMax * static_cast<double>(n)))
                            : -1;
  BranchAndBound bnb(g, ws, n, W, A, step, floor_sum, result);
  result.prior_score = bnb.meanLikelihood(bnb.score(g.levels.size() - 1, A, 0, 0));

  // Top level: every rotation x block of K x K translations, best bound first.
  ws.top.clear();
  for (int a = 0; a < rotations; ++a) {
    for (int iy = -W; iy <= W; iy += K) {
      for (int ix = -W; ix <= W; ix += K) ws.top.push_back({bnb.score(0, a, ix, iy), a, ix, iy});
    }
  }
  result.bounds += ws.top.size();
  // A heap, not a sort: the search usually ends after a few of them.
  const auto lower = [A](const Block& l, const Block& r) {
    return l.bound < r.bound || (l.bound == r.bound && std::abs(l.rot - A) > std::abs(r.rot - A));
  };
  std::make_heap(ws.top.begin(), ws.top.end(), lower);
  for (auto end = ws.top.end(); end != ws.top.begin(); --end) {
    std::pop_heap(ws.top.begin(), end, lower);
    const Block& b = *(end - 1);
    if (b.bound < bnb.best()) break;
    bnb.descend(b, 0);
  }
  const Block& best = bnb.bestBlock();
  result.found = bnb.found() && bnb.best() > 0;
  result.score = result.found ? bnb.meanLikelihood(bnb.best()) : 0.0;
  if (result.found) {
    result.T_key_curr = {prior.x + best.ix * P.resolution_m, prior.y + best.iy * P.resolution_m,
                         wrapAngle(prior.yaw + (best.rot - A) * step)};
  }
  return result;
}

}  // namespace lidarseg
