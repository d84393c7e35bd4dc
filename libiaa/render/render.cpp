// The renderer: screen-block elimination, then one kernel per method for each pixel (kernel.h).
//
// Work is organised as a fixed quadtree of screen blocks aligned to the image origin (32, 16, 8,
// 4, 2 pixels, then the pixel). Every block is a beam: when EvalRaySet calls it a Miss, all its
// pixels are certified background at the cost of one search; otherwise its children search from
// its t_near (no ray of the block hits before it). The quadtree does not depend on Exec, so the
// result is the same for any thread count, and render_pixel() can walk the chain of blocks above
// one pixel and run exactly the code the full render ran.
#include "render/render.h"

#include <algorithm>
#include <chrono>
#include <optional>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "core/spread.h"
#include "render/beam.h"
#include "render/context.h"
#include "render/kernel.h"
#include "scene/camera.h"

namespace iaa {

namespace {

/// Edge of the root screen blocks (the unit of parallel work) and of the smallest block above a
/// pixel.
constexpr int kRootBlock = 32;
constexpr int kMinBlock = 2;

bool may_be_partial(const Tape& tape) {
  for (const Instr& in : tape.instrs()) {
    switch (in.op) {
      case Op::kDiv:
      case Op::kPow:
      case Op::kSqrt:
      case Op::kLog:
      case Op::kTan:
        return true;
      default:
        break;
    }
  }
  return false;
}

/// Window of the render: the settings' window or the whole image.
PixelWindow effective_window(const RenderSettings& s, int w, int h) {
  if (s.window.x0 == 0 && s.window.y0 == 0 && s.window.x1 == 0 && s.window.y1 == 0)
    return {0, 0, w, h};
  return s.window;
}

PixelRect block_rect(int bx, int by, int size, int w, int h) {
  return {double(bx), double(by), double(std::min(bx + size, w)), double(std::min(by + size, h))};
}

int block_level(int size) {
  int l = 0;
  while ((1 << l) < size) ++l;
  return -l;
}

/// One root block of a render: its quadtree of screen blocks down to the pixels' kernels. The
/// pixels go into the Film; the blocks' evaluations are summed here.
struct BlockTask {
  RenderContext& ctx;
  Film& film;
  const PixelWindow& win;
  AdaptiveCorners* corners;  ///< the adaptive method's corner rays of this root block, else null
  std::uint64_t block_evals = 0;

  void store(int x, int y, const PixelResult& r) {
    const std::size_t i = film.index(x, y);
    film.color[i] = r.color;
    film.certificate[i] = r.certificate;
    film.leaves[i] = r.leaves;
    film.evals[i] = r.evals;
    film.coverage[i] = r.coverage;
  }
  void fill_background(int bx, int by, int size) {
    const PixelResult bg = background_pixel(ctx);
    for (int y = std::max(by, win.y0); y < std::min(by + size, win.y1); ++y) {
      for (int x = std::max(bx, win.x0); x < std::min(bx + size, win.x1); ++x) store(x, y, bg);
    }
  }
  bool intersects_window(int bx, int by, int size) const {
    return bx < win.x1 && bx + size > win.x0 && by < win.y1 && by + size > win.y0;
  }
  /// The block of edge `size` at (bx, by), searched over `range` after the block above (`full`
  /// when that one is Full, its budget `mv`): background, or passed on to its four children.
  /// `first`, when not null: the block's (or pixel's) depth search made ahead with its
  /// siblings', and `mv` the budget after it.
  void run(int bx, int by, int size, Interval range, const BeamSearch* full,
           const MeanValueBudget& mv, FirstPiece* first = nullptr) {
    if (size < kMinBlock) {
      store(bx, by, run_kernel(ctx, PixelJob{bx, by, range, full, mv, first}, corners, nullptr));
      return;
    }
    const std::uint64_t e0 = ctx.evals;
    const BeamSearch s = search_block(ctx, block_rect(bx, by, size, film.width, film.height),
                                      block_level(size), range, full, mv, nullptr, -1, first);
    const MeanValueBudget after = ctx.mv.inherited();
    block_evals += ctx.evals - e0;
    if (s.result == BeamResult::kMiss) {
      fill_background(bx, by, size);
      return;
    }
    const Interval sub = child_range(s, range);
    if (size == kRootBlock && corners) corners->range = sub;
    const int h = size / 2;
    const BeamSearch* kid_full = s.result == BeamResult::kFull ? &s : nullptr;
    int kx[4], ky[4], n = 0;
    for (int k = 0; k < 4; ++k) {
      const int cx = bx + (k & 1) * h, cy = by + (k >> 1) * h;
      if (cx >= film.width || cy >= film.height || !intersects_window(cx, cy, h)) continue;
      kx[n] = cx;
      ky[n++] = cy;
    }
    // The children's depth searches side by side, each from its own copy of the budget: the
    // same searches as one at a time (first_pieces), four boxes per pass of the batched
    // evaluators. Blocks search whatever the block above found; an IAA pixel searches when the
    // block above is not Full (else it takes the block's proof first, kernel_iaa.cpp).
    FirstPiece firsts[4];
    MeanValueBudget budgets[4] = {after, after, after, after};
    const bool pixels = h < kMinBlock;
    const bool together =
        ctx.batched && n >= 2 &&
        (!pixels || (!kid_full && ctx.setup.settings.method == RenderMethod::kIaa));
    if (together) {
      PixelRect rects[4];
      for (int k = 0; k < n; ++k) {
        rects[k] =
            pixels ? PixelRect{double(kx[k]), double(ky[k]), double(kx[k] + 1), double(ky[k] + 1)}
                   : block_rect(kx[k], ky[k], h, film.width, film.height);
      }
      const std::uint64_t e1 = ctx.evals;
      first_pieces(ctx, rects, n, sub, false, firsts, budgets);
      if (!pixels) block_evals += ctx.evals - e1;  // a pixel's count holds its own (run_kernel)
    }
    for (int k = 0; k < n; ++k) {
      run(kx[k], ky[k], h, sub, kid_full, together ? budgets[k] : after,
          together ? &firsts[k] : nullptr);
    }
  }
};

/// What a root block counts besides its pixels' records.
struct RootCounts {
  std::uint64_t block_evals = 0;   ///< evaluations of its screen blocks
  std::uint64_t pruned_evals = 0;  ///< its evaluations with a pruned tape
};

/// Renders the root block at (bx, by) into the film.
RootCounts render_root(RenderContext& ctx, Film& film, int bx, int by) {
  const RenderSetup& su = ctx.setup;
  std::optional<AdaptiveCorners> corners;
  if (su.settings.method == RenderMethod::kAdaptive) {
    const int g = 1 << su.settings.max_level;
    corners.emplace(bx * g, by * g, kRootBlock * g + 1);
  }
  // Each root block starts without regions or specialized tapes, so that what it evaluates (and
  // counts) does not depend on the blocks before it.
  ctx.se.reset();
  const std::uint64_t p0 = ctx.se.specialized_evals();
  BlockTask task{ctx, film, film.window, corners ? &*corners : nullptr};
  if (su.depth.is_empty()) {
    task.fill_background(bx, by, kRootBlock);
  } else {
    task.run(bx, by, kRootBlock, su.depth, nullptr, MeanValueBudget{});
  }
  return {task.block_evals, ctx.se.specialized_evals() - p0};
}

/// Searches the chain of screen blocks above the pixel (job.x, job.y) as render() does, each
/// block with the depth range, the Full result and the mean-value budget of the one above, and
/// leaves in `job` what the last one leaves to the pixel (job.full points to `prev`). Returns the
/// range the root block leaves, or nothing when a block is a Miss. Adds the blocks' evaluations
/// to `evals`.
std::optional<Interval> blocks_above(RenderContext& ctx, PixelJob& job, BeamSearch& prev,
                                     PixelTrace* trace, std::uint32_t& evals) {
  const Scene& scene = *ctx.setup.scene;
  Interval root_range;
  for (int size = kRootBlock; size >= kMinBlock; size /= 2) {
    const int bx = (job.x / size) * size, by = (job.y / size) * size;
    const std::uint64_t e0 = ctx.evals;
    const BeamSearch s =
        search_block(ctx, block_rect(bx, by, size, scene.width, scene.height), block_level(size),
                     job.range, job.full, job.mv, trace, last_beam(trace));
    job.mv = ctx.mv.inherited();
    evals += static_cast<std::uint32_t>(ctx.evals - e0);
    if (s.result == BeamResult::kMiss) return std::nullopt;
    job.range = child_range(s, job.range);
    if (size == kRootBlock) root_range = job.range;
    prev = s;
    job.full = s.result == BeamResult::kFull ? &prev : nullptr;
  }
  return root_range;
}

/// Root blocks that meet the window, in row-major order.
std::vector<std::pair<int, int>> root_blocks(const PixelWindow& win) {
  std::vector<std::pair<int, int>> roots;
  for (int by = (win.y0 / kRootBlock) * kRootBlock; by < win.y1; by += kRootBlock) {
    for (int bx = (win.x0 / kRootBlock) * kRootBlock; bx < win.x1; bx += kRootBlock)
      roots.push_back({bx, by});
  }
  return roots;
}

/// The pixels of the root block at (bx, by) that the film's window holds, in row-major order.
template <class F>
void for_root_pixels(const Film& film, int bx, int by, F&& f) {
  const PixelWindow& win = film.window;
  for (int y = std::max(by, win.y0); y < std::min(by + kRootBlock, win.y1); ++y) {
    for (int x = std::max(bx, win.x0); x < std::min(bx + kRootBlock, win.x1); ++x)
      f(film.index(x, y));
  }
}

/// A root block's result as bytes for another process (core/spread.h): its counts, then its
/// pixels' records. Also returns its evaluations (blocks and pixels), the spread's measure of work.
std::string pack_root(const Film& film, int bx, int by, const RootCounts& c, std::uint64_t* work) {
  std::string out;
  put_bytes(out, c);
  *work = c.block_evals;
  for_root_pixels(film, bx, by, [&](std::size_t i) {
    put_bytes(out, film.color[i]);
    put_bytes(out, film.certificate[i]);
    put_bytes(out, film.leaves[i]);
    put_bytes(out, film.evals[i]);
    put_bytes(out, film.coverage[i]);
    *work += film.evals[i];
  });
  return out;
}

/// Stores a root block that pack_root() packed into the film; returns its counts.
RootCounts unpack_root(Film& film, int bx, int by, const std::string& in) {
  std::size_t pos = 0;
  const RootCounts c = take_bytes<RootCounts>(in, pos);
  for_root_pixels(film, bx, by, [&](std::size_t i) {
    film.color[i] = take_bytes<Rgb>(in, pos);
    film.certificate[i] = take_bytes<PixelCertificate>(in, pos);
    film.leaves[i] = take_bytes<std::uint32_t>(in, pos);
    film.evals[i] = take_bytes<std::uint32_t>(in, pos);
    film.coverage[i] = take_bytes<float>(in, pos);
  });
  IAA_CHECK(pos == in.size());
  return c;
}

/// Renders the root blocks that `spread` hands to this process with its threads, then takes the
/// other processes' blocks from it: afterwards the film and `counts` hold every block.
void render_spread(const RenderSetup& setup, Film& film,
                   const std::vector<std::pair<int, int>>& roots, std::vector<RootCounts>& counts,
                   const ProgressPhase& phase, const Exec& exec) {
  Spread& spread = *exec.spread;
  spread.begin(roots.size(), &phase);
  std::vector<char> mine(roots.size(), 0);
  const int threads = exec.resolved_threads();
  exec.run([&] {
    tbb::parallel_for(0, threads, [&](int) {
      RoundingScope scope;
      RenderContext ctx(setup);
      try {
        for (std::int64_t i = spread.next(); i >= 0; i = spread.next()) {
          const auto k = static_cast<std::size_t>(i);
          counts[k] = render_root(ctx, film, roots[k].first, roots[k].second);
          mine[k] = 1;
          phase.advance(1);
        }
      } catch (...) {
        spread.fail();  // the process's other threads stop too
        throw;
      }
    });
  });
  std::vector<std::string> results(roots.size());
  std::vector<std::uint64_t> work(roots.size(), 0);
  for (std::size_t k = 0; k < roots.size(); ++k) {
    if (mine[k]) results[k] = pack_root(film, roots[k].first, roots[k].second, counts[k], &work[k]);
  }
  film.balance = spread.finish(results, work);
  for (std::size_t k = 0; k < roots.size(); ++k) {
    if (!mine[k]) counts[k] = unpack_root(film, roots[k].first, roots[k].second, results[k]);
  }
}

/// Sums the per-pixel records of the window into film.stats, in a fixed order so that the
/// totals do not depend on the threads.
void sum_pixel_stats(Film& film) {
  FilmStats& s = film.stats;
  const PixelWindow& win = film.window;
  for (int y = win.y0; y < win.y1; ++y) {
    for (int x = win.x0; x < win.x1; ++x) {
      const std::size_t i = film.index(x, y);
      ++s.pixels;
      s.evals += film.evals[i];
      s.leaves += film.leaves[i];
      s.covered_area += film.coverage[i];
      switch (film.certificate[i]) {
        case PixelCertificate::kEmpty:
          ++s.empty;
          break;
        case PixelCertificate::kCovered:
          ++s.covered;
          break;
        case PixelCertificate::kUncertain:
          ++s.uncertain;
          break;
        case PixelCertificate::kNotRendered:
          break;
      }
    }
  }
}

}  // namespace

BeamSearch search_block(RenderContext& ctx, const PixelRect& rect, int level, Interval range,
                        const BeamSearch* full, const MeanValueBudget& mv, PixelTrace* trace,
                        int parent, FirstPiece* first) {
  BeamTrace bt;
  const std::uint64_t e0 = ctx.evals;
  ctx.mv = mv;
  const BeamSearch s = eval_ray_set(ctx, rect, range, full, trace ? &bt : nullptr, true, first);
  if (trace) {
    const BeamDecision d =
        s.result == BeamResult::kMiss ? BeamDecision::kBackground : BeamDecision::kDescend;
    record_beam(*trace, std::move(bt), rect, level, parent, d, ctx.evals - e0);
  }
  return s;
}

RenderSetup::RenderSetup(const Scene& sc, const RenderSettings& st)
    : scene(&sc), settings(st), frame(sc.camera, sc.width, sc.height) {
  IAA_CHECK(sc.tape != nullptr);
  settings.validate();
  if (sc.width < 1 || sc.height < 1) throw SettingError("image size must be at least 1x1");
  if (!sc.bounds.valid()) throw Error("scene bounds are not a valid box");
  depth = depth_range(frame, sc.bounds);
  may_partial = may_be_partial(*sc.tape);
  diag = length(sc.bounds.size());
  ray_tol = 1e-9 * std::max(diag, depth.is_empty() ? 1.0 : depth.hi());
  shadow_eps = 1e-4 * diag;
}

Film render(const Scene& scene, const RenderSettings& settings, const Exec& exec) {
  const auto t0 = std::chrono::steady_clock::now();
  settings.validate_window(scene.width, scene.height);
  const RenderSetup setup(scene, settings);
  Film film(scene.width, scene.height);
  film.settings = settings;
  film.window = effective_window(settings, scene.width, scene.height);

  const std::vector<std::pair<int, int>> roots = root_blocks(film.window);
  std::vector<RootCounts> counts(roots.size());
  ProgressPhase phase(exec.progress, "render", static_cast<std::uint64_t>(roots.size()));
  if (exec.spread) {
    // Shared with other processes: every block is rendered (cancellation is not checked, since
    // the other processes wait for this one's blocks).
    render_spread(setup, film, roots, counts, phase, exec);
  } else {
    const auto run_roots = [&](const tbb::blocked_range<std::size_t>& br) {
      RoundingScope scope;  // once per task, not per operation
      RenderContext ctx(setup);
      for (std::size_t i = br.begin(); i != br.end(); ++i) {
        if (phase.cancelled()) return;
        counts[i] = render_root(ctx, film, roots[i].first, roots[i].second);
        phase.advance(1);
      }
    };
    exec.run(
        [&] { tbb::parallel_for(tbb::blocked_range<std::size_t>(0, roots.size(), 1), run_roots); });
  }

  // Totals, in a fixed order so that they do not depend on the threads.
  FilmStats& s = film.stats;
  for (const RootCounts& c : counts) {
    s.block_evals += c.block_evals;
    s.pruned_evals += c.pruned_evals;
  }
  s.evals = s.block_evals;
  sum_pixel_stats(film);
  film.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return film;
}

PixelResult render_pixel(const Scene& scene, const RenderSettings& settings, int x, int y,
                         PixelTrace* trace) {
  if (x < 0 || y < 0 || x >= scene.width || y >= scene.height) {
    throw SettingError("pixel " + std::to_string(x) + "," + std::to_string(y) + " is outside the " +
                       std::to_string(scene.width) + "x" + std::to_string(scene.height) + " image");
  }
  const RenderSetup setup(scene, settings);
  RoundingScope scope;
  RenderContext ctx(setup);
  if (trace) {
    trace->x = x;
    trace->y = y;
  }
  PixelResult out = background_pixel(ctx);
  if (setup.depth.is_empty()) return out;
  PixelJob job{x, y, setup.depth, nullptr, MeanValueBudget{}};
  BeamSearch prev;
  const std::optional<Interval> root_range = blocks_above(ctx, job, prev, trace, out.block_evals);
  if (!root_range) {
    if (trace) trace->color = scene.background;
    return out;
  }
  const std::uint32_t block_evals = out.block_evals;
  // The adaptive method's corner rays, shared within the pixel as render() shares them (render()
  // also shares them with the pixels around, so its ray and evaluation counts can be lower).
  std::optional<AdaptiveCorners> corners;
  if (settings.method == RenderMethod::kAdaptive) {
    const int g = 1 << settings.max_level;
    corners.emplace(x * g, y * g, g + 1);
    corners->range = *root_range;
  }
  out = run_kernel(ctx, job, corners ? &*corners : nullptr, trace);
  out.block_evals = block_evals;
  return out;
}

}  // namespace iaa
