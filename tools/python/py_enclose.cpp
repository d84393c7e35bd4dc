// iaa.enclose: the guaranteed enclosure octree as `iaa enclose` runs it, its leaves as NumPy arrays
// (boxes, classes, depths, f bounds) and the command's report.
#include <pybind11/stl.h>

#include <chrono>
#include <optional>

#include "app/enclosing.h"
#include "py_common.h"

namespace iaa::py {
namespace {

/// The leaves as arrays, built once and owned by the arrays.
struct LeafArrays {
  std::vector<double> boxes;  ///< x0, x1, y0, y1, z0, z1 per leaf
  std::vector<std::uint8_t> classes, depths;
  std::vector<double> f;  ///< lo, hi per leaf
};

struct EncloseResult {
  pb::object boxes, classes, depths, f, report;
};

std::shared_ptr<LeafArrays> leaf_arrays(const Enclosure& enc) {
  auto a = std::make_shared<LeafArrays>();
  const std::size_t n = enc.cells.size();
  a->boxes.reserve(6 * n);
  a->f.reserve(2 * n);
  for (const Cell& c : enc.cells) {
    const Box3 b = enc.box(c);
    for (int i = 0; i < 3; ++i) {
      a->boxes.push_back(b.lo[i]);
      a->boxes.push_back(b.hi[i]);
    }
    a->classes.push_back(static_cast<std::uint8_t>(c.cls));
    a->depths.push_back(c.depth);
    a->f.push_back(c.f.lo());
    a->f.push_back(c.f.hi());
  }
  return a;
}

EncloseResult enclose_scene(const PyScene& ps, std::optional<int> depth,
                            std::optional<double> cell_size, int refine_possible,
                            std::uint64_t max_boxes, int threads, const pb::object& progress) {
  app::OctreeOptions o;
  o.depth = depth.value_or(o.depth);
  o.depth_given = depth.has_value();
  o.cell_size = cell_size.value_or(0);
  o.cell_size_given = cell_size.has_value();
  o.refine_possible = refine_possible;
  o.max_boxes = max_boxes;
  const EncloseSettings s = app::enclose_settings(ps.scene.bounds, o);
  Enclosure enc;
  app::EncloseTimes t;
  int used = 0;
  run_cancellable(
      [&](const Exec& exec) {
        const auto t0 = std::chrono::steady_clock::now();
        enc = app::run_enclose(*ps.scene.tape, s, exec);
        t.enclose = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        used = exec.resolved_threads();
      },
      threads, progress);
  EncloseResult r;
  r.report = to_python(app::enclose_report_json(ps.scene.expression, s, enc, t, used));
  const std::shared_ptr<const LeafArrays> a = leaf_arrays(enc);
  const pb::capsule base = owner_capsule(a);
  const auto n = static_cast<pb::ssize_t>(enc.cells.size());
  r.boxes = array_over(a->boxes.data(), {n, 6}, base);
  r.classes = array_over(a->classes.data(), {n}, base);
  r.depths = array_over(a->depths.data(), {n}, base);
  r.f = array_over(a->f.data(), {n, 2}, base);
  return r;
}

}  // namespace

void bind_enclose(pb::module_& m) {
  pb::class_<EncloseResult>(m, "EncloseResult", R"doc(
What iaa.enclose returns: the leaves of the enclosure octree in canonical order (by depth, then
Morton order), the same for any thread count. Every point of the surface inside the bounds lies in
one of the boxes.)doc")
      .def_readonly("boxes", &EncloseResult::boxes,
                    "(N, 6) float64: x0, x1, y0, y1, z0, z1 of each leaf, exactly the box f was "
                    "evaluated on")
      .def_readonly("classes", &EncloseResult::classes,
                    "(N,) uint8: 1 crossing (the surface certainly passes through), 2 possible")
      .def_readonly("depths", &EncloseResult::depths, "(N,) uint8: octree depth of each leaf")
      .def_readonly("f", &EncloseResult::f,
                    "(N, 2) float64: an enclosure [lo, hi] of f on each leaf")
      .def_readonly("report", &EncloseResult::report,
                    "dict: the JSON report of `iaa enclose --report`")
      .def("__repr__", [](const EncloseResult& r) {
        return "<iaa.EncloseResult " + std::to_string(pb::len(r.classes)) + " boxes>";
      });

  m.def("enclose", &enclose_scene, pb::arg("scene"), pb::arg("depth") = pb::none(), pb::kw_only(),
        pb::arg("cell_size") = pb::none(), pb::arg("refine_possible") = 0,
        pb::arg("max_boxes") = EncloseSettings{}.max_boxes, pb::arg("threads") = 0,
        pb::arg("progress") = pb::none(), R"doc(
Encloses the scene's surface in its bounds as `iaa enclose` does: boxes that provably contain
every point of f = 0 there, each crossing (certified) or possible.

depth: leaf depth, cells are the bounds / 2^depth per axis (1..21; None: 7); cell_size: choose the
depth so that cells are at most this large (instead of depth); refine_possible: refine possible
leaves up to this many levels deeper (0..8); max_boxes: fail when more leaves are needed.
threads, progress: as for render(). Raises ValueError with the command's message (naming its
options: --depth, --cell-size, --refine-possible, --max-boxes).)doc");
}

}  // namespace iaa::py
