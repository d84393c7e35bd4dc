// The viewer's camera (see scene_camera.h).
#include "scene_camera.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <vtkCamera.h>
#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkRenderer.h>

namespace iaa::viz {

// ---- Recorded camera --------------------------------------------------------------------------

void attach_camera(vtkDataObject* data, const ViewCamera& c) {
  vtkNew<vtkDoubleArray> a;
  a->SetName(kCameraArray);
  a->SetNumberOfTuples(10);
  const double v[10] = {c.eye.x,     c.eye.y, c.eye.z, c.look_at.x, c.look_at.y,
                        c.look_at.z, c.up.x,  c.up.y,  c.up.z,      c.fov_deg};
  for (int i = 0; i < 10; ++i) a->SetValue(i, v[i]);
  data->GetFieldData()->AddArray(a);
}

std::optional<ViewCamera> recorded_camera(vtkDataObject* data) {
  if (!data || !data->GetFieldData()) return std::nullopt;
  vtkDataArray* a = data->GetFieldData()->GetArray(kCameraArray);
  if (!a || a->GetNumberOfComponents() != 1 || a->GetNumberOfTuples() != 10) return std::nullopt;
  double v[10];
  for (int i = 0; i < 10; ++i) {
    v[i] = a->GetTuple1(i);
    if (!std::isfinite(v[i])) return std::nullopt;
  }
  ViewCamera c;
  c.eye = {v[0], v[1], v[2]};
  c.look_at = {v[3], v[4], v[5]};
  c.up = {v[6], v[7], v[8]};
  c.fov_deg = v[9];
  return c;
}

// ---- Framing ----------------------------------------------------------------------------------

namespace {

/// An axis-aligned box grown by data sets' bounds; empty until something is added.
struct Bounds {
  Vec3 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
          std::numeric_limits<double>::infinity()};
  Vec3 hi{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
          -std::numeric_limits<double>::infinity()};
  bool empty() const { return !(lo.x <= hi.x); }
  /// Adds VTK bounds (xmin, xmax, ymin, ymax, zmin, zmax); VTK's empty bounds add nothing.
  void add(const double b[6]) {
    if (!(b[0] <= b[1])) return;
    for (int i = 0; i < 3; ++i) {
      lo[i] = std::min(lo[i], b[2 * i]);
      hi[i] = std::max(hi[i], b[2 * i + 1]);
    }
  }
  void add(vtkDataSet* d) {
    double b[6];
    d->GetBounds(b);
    add(b);
  }
  Vec3 center() const { return 0.5 * (lo + hi); }
  double radius() const { return 0.5 * length(hi - lo); }
};

/// Bounds of the layers that matter most (see auto_camera): in a pixel inspection the hit slabs,
/// hit points and the depth boxes that are not outlined (the coarse pieces of the search run
/// through much of the scene and would frame it all); else everything.
Bounds focus_bounds(const std::vector<Layer>& layers) {
  Bounds focus, all;
  for (const Layer& l : layers) {
    all.add(l.data);
    const bool subject = l.role == LayerRole::kSlabs || l.role == LayerRole::kPoints ||
                         l.role == LayerRole::kDepthBoxes;
    if (subject && !l.outline) focus.add(l.data);
  }
  // A focus of a single point (one hit point and nothing else) is no scale to frame.
  if (focus.empty() || !(focus.radius() > 0)) return all;
  return focus;
}

/// Where the eye sits, as a unit direction from the target, and which way is up.
struct Direction {
  Vec3 to_eye;
  Vec3 up;
};

/// Looks at a beam from its side, turned 35 degrees towards `hint`'s eye, so that its depth
/// extent is visible rather than seen end-on.
Direction beside(const ViewCamera& hint) {
  const Vec3 d = normalize(hint.look_at - hint.eye);
  Vec3 side = cross(d, hint.up);
  if (length(side) < 1e-12) side = cross(d, Vec3{1, 0, 0});
  side = normalize(side);
  const double a = 35.0 * M_PI / 180.0;
  Direction out{normalize(std::cos(a) * side - std::sin(a) * d), normalize(cross(side, d))};
  if (dot(out.up, hint.up) < 0) out.up = -out.up;
  return out;
}

}  // namespace

ViewCamera auto_camera(const std::vector<Layer>& layers, const std::optional<ViewCamera>& hint,
                       double aspect) {
  const Bounds b = focus_bounds(layers);
  ViewCamera c;
  c.fov_deg = 30;
  if (b.empty()) return c;
  double r = b.radius();
  if (!(r > 0)) r = 1;
  const Direction dir =
      hint ? beside(*hint) : Direction{normalize(Vec3{0.55, 0.45, 1.0}), {0, 1, 0}};
  // Far enough that a sphere of radius r (with a margin) fits the narrower field of view.
  const double half = 0.5 * c.fov_deg * M_PI / 180.0;
  const double half_h = std::atan(std::tan(half) * std::min(1.0, aspect));
  const double dist = 1.08 * r / std::sin(std::min(half, half_h));
  c.look_at = b.center();
  c.eye = c.look_at + dist * dir.to_eye;
  c.up = dir.up;
  return c;
}

double focus_radius(const std::vector<Layer>& layers) {
  const Bounds focus = focus_bounds(layers);
  return focus.empty() || !(focus.radius() > 0) ? 1.0 : focus.radius();
}

void apply_camera(vtkRenderer* ren, const ViewCamera& c, const std::vector<Layer>& layers) {
  vtkCamera* cam = ren->GetActiveCamera();
  cam->SetPosition(c.eye.x, c.eye.y, c.eye.z);
  cam->SetFocalPoint(c.look_at.x, c.look_at.y, c.look_at.z);
  cam->SetViewUp(c.up.x, c.up.y, c.up.z);
  cam->SetViewAngle(c.fov_deg);
  cam->OrthogonalizeViewUp();
  ren->ResetCameraClippingRange();
  Bounds all;
  for (const Layer& l : layers) all.add(l.data);
  if (!all.empty()) {
    double b[6] = {all.lo.x, all.hi.x, all.lo.y, all.hi.y, all.lo.z, all.hi.z};
    ren->ResetCameraClippingRange(b);
  }
}

}  // namespace iaa::viz
