// vtkSampleFunction + vtkFlyingEdges3D over the point evaluator; see vtk_mesher.h.
#include "viz/vtk_mesher.h"

#include <vtkCellArray.h>
#include <vtkFlyingEdges3D.h>
#include <vtkImplicitFunction.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSampleFunction.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>

#include "core/error.h"
#include "core/interval.h"
#include "expr/eval_point.h"
#include "expr/eval_point_grad.h"

namespace iaa::viz {

void VtkMeshSettings::validate() const {
  if (!bounds.valid() ||
      !(bounds.lo.x < bounds.hi.x && bounds.lo.y < bounds.hi.y && bounds.lo.z < bounds.hi.z)) {
    throw SettingError("vtk mesh: the bounds must be a finite box with positive extent");
  }
  if (grid < 2 || grid > 2048) {
    throw SettingError("vtk mesh: grid must be in 2..2048 cells per axis, got " +
                       std::to_string(grid));
  }
}

namespace {

// f as a VTK implicit function. vtkSampleFunction evaluates it from vtkSMPTools (TBB) workers, so
// each thread keeps its own evaluator. Undefined values become a large positive number.
class TapeFunction : public vtkImplicitFunction {
 public:
  static TapeFunction* New();
  // clang-format off
  vtkTypeMacro(TapeFunction, vtkImplicitFunction)
      // clang-format on
      const Tape* tape = nullptr;
  std::uint64_t run = 0;  ///< unique per mesh_vtk() call: a tape's address may be reused

  using vtkImplicitFunction::EvaluateFunction;
  double EvaluateFunction(double x[3]) override {
    const double f = evaluator().eval(x[0], x[1], x[2]);
    return std::isfinite(f) ? f : 1e30;
  }
  void EvaluateGradient(double x[3], double g[3]) override {
    PointGradEval pg(*tape);
    const PGrad r = pg.eval({x[0], x[1], x[2]});
    g[0] = r.g.x, g[1] = r.g.y, g[2] = r.g.z;
  }

 private:
  PointEval& evaluator() {
    thread_local std::uint64_t cached = 0;
    thread_local std::unique_ptr<PointEval> pe;
    if (cached != run || !pe) {
      pe = std::make_unique<PointEval>(*tape);
      cached = run;
    }
    return *pe;
  }
};
vtkStandardNewMacro(TapeFunction);

}  // namespace

TriangleSoup mesh_vtk(const Tape& tape, const VtkMeshSettings& s, const Exec& exec) {
  s.validate();
  NearestScope nearest;
  vtkNew<TapeFunction> fn;
  static std::atomic<std::uint64_t> next_run{1};
  fn->tape = &tape;
  fn->run = next_run++;
  vtkNew<vtkSampleFunction> sample;
  sample->SetImplicitFunction(fn);
  sample->SetModelBounds(s.bounds.lo.x, s.bounds.hi.x, s.bounds.lo.y, s.bounds.hi.y, s.bounds.lo.z,
                         s.bounds.hi.z);
  sample->SetSampleDimensions(s.grid + 1, s.grid + 1, s.grid + 1);
  sample->SetOutputScalarTypeToDouble();
  sample->ComputeNormalsOff();
  sample->CappingOff();
  vtkNew<vtkFlyingEdges3D> contour;
  contour->SetInputConnection(sample->GetOutputPort());
  contour->SetValue(0, 0.0);
  contour->ComputeNormalsOff();
  contour->ComputeGradientsOff();
  contour->ComputeScalarsOff();
  exec.run([&] { contour->Update(); });
  vtkPolyData* out = contour->GetOutput();

  TriangleSoup soup;
  vtkPoints* pts = out->GetPoints();
  const vtkIdType np = pts ? pts->GetNumberOfPoints() : 0;
  soup.vertices.resize(std::size_t(np));
  for (vtkIdType i = 0; i < np; ++i) {
    double p[3];
    pts->GetPoint(i, p);
    soup.vertices[std::size_t(i)] = {p[0], p[1], p[2]};
  }
  vtkCellArray* polys = out->GetPolys();
  if (polys) {
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    for (polys->InitTraversal(); polys->GetNextCell(n, ids);) {
      if (n != 3) continue;
      soup.triangles.push_back(
          {std::uint32_t(ids[0]), std::uint32_t(ids[1]), std::uint32_t(ids[2])});
    }
  }
  // Flying edges orients consistently; flip all triangles if most normals point to decreasing f.
  PointGradEval pg(tape);
  double agree = 0;
  for (const auto& t : soup.triangles) {
    const Vec3 a = soup.vertices[t[0]], b = soup.vertices[t[1]], c = soup.vertices[t[2]];
    const PGrad g = pg.eval((a + b + c) / 3.0);
    const double d = dot(cross(b - a, c - a), g.g);
    if (std::isfinite(d)) agree += d > 0 ? 1 : (d < 0 ? -1 : 0);
  }
  if (agree < 0) {
    for (auto& t : soup.triangles) std::swap(t[1], t[2]);
  }
  return soup;
}

void run_vtk_mesher(const app::meshing::Surface& s, const app::meshing::MeshParams& p,
                    const Exec& exec, app::meshing::MeshRun& run) {
  const auto t0 = std::chrono::steady_clock::now();
  VtkMeshSettings vs;
  vs.bounds = s.bounds;
  vs.grid = p.grid > 0 ? p.grid : p.resolution;
  run.soup = mesh_vtk(*s.tape, vs, exec);
  run.seconds = app::meshing::seconds_since(t0);
  run.details = {{"grid", vs.grid}};
  run.summary = "vtk flying edges, grid " + std::to_string(vs.grid) + "^3";
}

}  // namespace iaa::viz
