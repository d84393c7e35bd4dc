// One pixel's inspection as a VTK multiblock (see inspect_vtk.h).
#include "viz/inspect_vtk.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCompositeDataSet.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkInformation.h>
#include <vtkIntArray.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLMultiBlockDataWriter.h>

#include "app/png.h"
#include "core/error.h"
#include "scene/camera.h"
#include "viz/enclosure_vtk.h"
#include "viz/scene_render.h"
#include "viz/soup_vtk.h"

namespace iaa::viz {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

template <class A>
vtkSmartPointer<A> named(const char* name, int components = 1) {
  auto a = vtkSmartPointer<A>::New();
  a->SetName(name);
  a->SetNumberOfComponents(components);
  return a;
}

/// The beams of the trace that the picture shows: the pixel's own quadtree (level >= 0); when the
/// pixel was decided above it, the screen block that decided it.
std::vector<int> shown_beams(const PixelTrace& tr) {
  std::vector<int> out;
  for (std::size_t i = 0; i < tr.beams.size(); ++i) {
    if (tr.beams[i].level >= 0) out.push_back(static_cast<int>(i));
  }
  if (out.empty() && !tr.beams.empty()) out.push_back(static_cast<int>(tr.beams.size()) - 1);
  return out;
}

/// Cell arrays shared by the frusta and the slabs.
struct BeamArrays {
  vtkSmartPointer<vtkIntArray> result = named<vtkIntArray>(kResultArray);
  vtkSmartPointer<vtkIntArray> level = named<vtkIntArray>("level");
  vtkSmartPointer<vtkIntArray> beam = named<vtkIntArray>("beam");
  vtkSmartPointer<vtkIntArray> decision = named<vtkIntArray>("decision");
  vtkSmartPointer<vtkDoubleArray> t_near = named<vtkDoubleArray>("t_near");
  vtkSmartPointer<vtkDoubleArray> t_far = named<vtkDoubleArray>("t_far");

  void add(const BeamTrace& b, int index) {
    result->InsertNextValue(static_cast<int>(b.result));
    level->InsertNextValue(b.level);
    beam->InsertNextValue(index);
    decision->InsertNextValue(static_cast<int>(b.decision));
    t_near->InsertNextValue(b.result == BeamResult::kMiss ? kNaN : b.t_near);
    t_far->InsertNextValue(b.result == BeamResult::kFull ? b.t_far : kNaN);
  }
  void attach(vtkDataSet* d) const {
    vtkCellData* cd = d->GetCellData();
    for (vtkDataArray* a : {static_cast<vtkDataArray*>(result), static_cast<vtkDataArray*>(level),
                            static_cast<vtkDataArray*>(beam), static_cast<vtkDataArray*>(decision),
                            static_cast<vtkDataArray*>(t_near), static_cast<vtkDataArray*>(t_far)})
      cd->AddArray(a);
    cd->SetActiveScalars(kResultArray);
  }
};

/// The four corners of a pixel rectangle, in the order of a VTK quad.
std::array<std::array<double, 2>, 4> corners(const PixelRect& r) {
  return {{{r.u0, r.v0}, {r.u1, r.v0}, {r.u1, r.v1}, {r.u0, r.v1}}};
}

vtkSmartPointer<vtkUnstructuredGrid> frusta(const PixelTrace& tr, const std::vector<int>& shown,
                                            const CameraFrame& frame, double t_end) {
  auto g = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  BeamArrays arr;
  for (int i : shown) {
    const BeamTrace& b = tr.beams[static_cast<std::size_t>(i)];
    vtkIdType ids[5];
    int k = 0;
    for (const auto& c : corners(b.rect)) {
      const Vec3 p = frame.eye + t_end * frame.dir(c[0], c[1]);
      ids[k++] = pts->InsertNextPoint(p.x, p.y, p.z);
    }
    ids[4] = pts->InsertNextPoint(frame.eye.x, frame.eye.y, frame.eye.z);
    g->InsertNextCell(VTK_PYRAMID, 5, ids);
    arr.add(b, i);
  }
  g->SetPoints(pts);
  arr.attach(g);
  return g;
}

/// Depth range of the slab of a shaded beam (see the header).
Interval slab_range(const BeamTrace& b) {
  if (b.result == BeamResult::kFull) return Interval(b.t_near, b.t_far);
  for (auto it = b.pieces.rbegin(); it != b.pieces.rend(); ++it) {
    if (it->kept && it->t.lo() == b.t_near) return it->t;
  }
  return Interval(b.t_near, b.t_far);
}

vtkSmartPointer<vtkUnstructuredGrid> slabs(const PixelTrace& tr, const std::vector<int>& shown,
                                           const CameraFrame& frame) {
  auto g = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  BeamArrays arr;
  for (int i : shown) {
    const BeamTrace& b = tr.beams[static_cast<std::size_t>(i)];
    if (b.decision != BeamDecision::kShadeFull && b.decision != BeamDecision::kShadeLeaf) continue;
    const Interval t = slab_range(b);
    vtkIdType ids[8];
    int k = 0;
    for (double depth : {t.lo(), t.hi()}) {
      for (const auto& c : corners(b.rect)) {
        const Vec3 p = frame.eye + depth * frame.dir(c[0], c[1]);
        ids[k++] = pts->InsertNextPoint(p.x, p.y, p.z);
      }
    }
    g->InsertNextCell(VTK_HEXAHEDRON, 8, ids);
    arr.add(b, i);
  }
  g->SetPoints(pts);
  arr.attach(g);
  return g;
}

/// A depth piece longer than this many beam widths (at its far end) is "coarse": one of the
/// search's first, long pieces, which run through much of the scene.
constexpr double kCoarseRatio = 16.0;

bool is_coarse(const DepthPieceTrace& p, const BeamTrace& b, const CameraFrame& frame) {
  const double lateral = std::max(b.rect.width(), b.rect.height()) * frame.scale * p.t.hi();
  return p.t.width() > kCoarseRatio * lateral;
}

/// The depth boxes of the shown beams, the coarse ones or the others.
vtkSmartPointer<vtkUnstructuredGrid> depth_boxes(const PixelTrace& tr,
                                                 const std::vector<int>& shown,
                                                 const CameraFrame& frame, bool coarse) {
  auto g = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  auto verdict = named<vtkIntArray>(kVerdictArray);
  auto beam = named<vtkIntArray>("beam");
  auto level = named<vtkIntArray>("level");
  auto order = named<vtkIntArray>("order");
  auto t = named<vtkDoubleArray>("t", 2);
  auto f = named<vtkDoubleArray>("f", 2);
  auto fm = named<vtkDoubleArray>("f_mean_value", 2);
  auto partial = named<vtkIntArray>("partial_domain");
  for (int i : shown) {
    const BeamTrace& b = tr.beams[static_cast<std::size_t>(i)];
    for (std::size_t k = 0; k < b.pieces.size(); ++k) {
      const DepthPieceTrace& p = b.pieces[k];
      if (p.box.is_empty() || p.mean_value || is_coarse(p, b, frame) != coarse) continue;
      // The mean-value test of the same piece, when one follows, decides the verdict.
      const DepthPieceTrace* mv = nullptr;
      if (k + 1 < b.pieces.size() && b.pieces[k + 1].mean_value) mv = &b.pieces[k + 1];
      vtkIdType ids[8];
      for (int c = 0; c < 8; ++c) {
        ids[c] = pts->InsertNextPoint((c & 1) ? p.box.x.hi() : p.box.x.lo(),
                                      (c & 2) ? p.box.y.hi() : p.box.y.lo(),
                                      (c & 4) ? p.box.z.hi() : p.box.z.lo());
      }
      g->InsertNextCell(VTK_VOXEL, 8, ids);
      const bool kept = mv ? mv->kept : p.kept;
      verdict->InsertNextValue(kept ? kVerdictKept : kVerdictExcluded);
      beam->InsertNextValue(i);
      level->InsertNextValue(b.level);
      order->InsertNextValue(static_cast<int>(k));
      t->InsertNextTuple2(p.t.lo(), p.t.hi());
      f->InsertNextTuple2(p.f.lo(), p.f.hi());
      if (mv) {
        fm->InsertNextTuple2(mv->f.lo(), mv->f.hi());
      } else {
        fm->InsertNextTuple2(kNaN, kNaN);
      }
      partial->InsertNextValue(p.partial ? 1 : 0);
    }
  }
  g->SetPoints(pts);
  vtkCellData* cd = g->GetCellData();
  for (vtkDataArray* a : {static_cast<vtkDataArray*>(verdict), static_cast<vtkDataArray*>(beam),
                          static_cast<vtkDataArray*>(level), static_cast<vtkDataArray*>(order),
                          static_cast<vtkDataArray*>(t), static_cast<vtkDataArray*>(f),
                          static_cast<vtkDataArray*>(fm), static_cast<vtkDataArray*>(partial)})
    cd->AddArray(a);
  cd->SetActiveScalars(kVerdictArray);
  return g;
}

vtkSmartPointer<vtkPolyData> hit_points(const PixelTrace& tr, const std::vector<int>& shown) {
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  vtkNew<vtkCellArray> verts;
  auto normals = named<vtkDoubleArray>("normal", 3);
  auto color = named<vtkUnsignedCharArray>("color", 3);
  auto beam = named<vtkIntArray>("beam");
  auto centre = named<vtkIntArray>("center_ray_hit");
  auto add = [&](const Vec3& p, const Vec3& n, const Vec3& c, int b, bool hit) {
    const vtkIdType id = pts->InsertNextPoint(p.x, p.y, p.z);
    verts->InsertNextCell(1, &id);
    normals->InsertNextTuple3(n.x, n.y, n.z);
    color->InsertNextTuple3(app::to_byte(c.x), app::to_byte(c.y), app::to_byte(c.z));
    beam->InsertNextValue(b);
    centre->InsertNextValue(hit ? 1 : 0);
  };
  for (int i : shown) {
    const BeamTrace& b = tr.beams[static_cast<std::size_t>(i)];
    if (b.decision != BeamDecision::kShadeFull && b.decision != BeamDecision::kShadeLeaf) continue;
    add(b.point, b.normal, b.color, i, b.center_ray_hit);
  }
  for (const RayTrace& r : tr.rays) {
    if (r.hit) add(r.point, r.normal, r.color, -1, true);
  }
  pd->SetPoints(pts);
  pd->SetVerts(verts);
  pd->GetPointData()->SetNormals(normals);
  pd->GetPointData()->AddArray(color);
  pd->GetPointData()->AddArray(beam);
  pd->GetPointData()->AddArray(centre);
  return pd;
}

vtkSmartPointer<vtkPolyData> sample_rays(const PixelTrace& tr, const CameraFrame& frame,
                                         double t_end) {
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  vtkNew<vtkCellArray> lines;
  auto hit = named<vtkIntArray>("hit");
  auto certified = named<vtkIntArray>("certified");
  for (const RayTrace& r : tr.rays) {
    const Vec3 end = r.hit ? r.point : frame.eye + t_end * frame.dir(r.u, r.v);
    const vtkIdType ids[2] = {pts->InsertNextPoint(frame.eye.x, frame.eye.y, frame.eye.z),
                              pts->InsertNextPoint(end.x, end.y, end.z)};
    lines->InsertNextCell(2, ids);
    hit->InsertNextValue(r.hit ? 1 : 0);
    certified->InsertNextValue(r.certified ? 1 : 0);
  }
  pd->SetPoints(pts);
  pd->SetLines(lines);
  pd->GetCellData()->AddArray(hit);
  pd->GetCellData()->AddArray(certified);
  return pd;
}

/// The field data every block and the multiblock carry.
void describe(vtkDataObject* d, const InspectionInput& in) {
  ViewCamera cam;
  cam.eye = in.scene->camera.eye;
  cam.look_at = in.scene->camera.look_at;
  cam.up = in.scene->camera.up;
  cam.fov_deg = in.scene->camera.fov_deg;
  attach_camera(d, cam);
  vtkFieldData* fd = d->GetFieldData();
  auto format = named<vtkStringArray>("format");
  format->InsertNextValue(kInspectFormat);
  fd->AddArray(format);
  auto pixel = named<vtkIntArray>("pixel");
  pixel->InsertNextValue(in.trace->x);
  pixel->InsertNextValue(in.trace->y);
  fd->AddArray(pixel);
  auto scene = named<vtkStringArray>("scene");
  scene->InsertNextValue(in.scene->name);
  fd->AddArray(scene);
  auto method = named<vtkStringArray>("method");
  method->InsertNextValue(std::string(method_name(in.settings.method)));
  fd->AddArray(method);
}

}  // namespace

vtkSmartPointer<vtkMultiBlockDataSet> inspection_to_multiblock(const InspectionInput& in) {
  IAA_CHECK(in.scene != nullptr && in.trace != nullptr);
  const PixelTrace& tr = *in.trace;
  const CameraFrame frame(in.scene->camera, in.scene->width, in.scene->height);
  const Interval depth = depth_range(frame, in.scene->bounds);
  const double t_end = depth.is_empty() ? 1.0 : depth.hi();
  const std::vector<int> shown = shown_beams(tr);

  std::vector<std::pair<const char*, vtkSmartPointer<vtkDataSet>>> blocks = {
      {kBeamsBlock, frusta(tr, shown, frame, t_end)},
      {kSlabsBlock, slabs(tr, shown, frame)},
      {kDepthBoxesBlock, depth_boxes(tr, shown, frame, false)},
      {kCoarseDepthBoxesBlock, depth_boxes(tr, shown, frame, true)},
      {kHitPointsBlock, hit_points(tr, shown)},
  };
  if (!tr.rays.empty()) blocks.push_back({kSampleRaysBlock, sample_rays(tr, frame, t_end)});
  if (in.enclosure) {
    blocks.push_back({kEnclosureBlock,
                      enclosure_to_grid(*in.enclosure,
                                        EnclosureInfo{in.scene->expression, in.enclose_settings})});
  }
  if (in.mesh) blocks.push_back({kMeshBlock, soup_to_polydata(*in.mesh)});

  auto mb = vtkSmartPointer<vtkMultiBlockDataSet>::New();
  mb->SetNumberOfBlocks(static_cast<unsigned>(blocks.size()));
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    const auto n = static_cast<unsigned>(i);
    describe(blocks[i].second, in);
    mb->SetBlock(n, blocks[i].second);
    mb->GetMetaData(n)->Set(vtkCompositeDataSet::NAME(), blocks[i].first);
  }
  describe(mb, in);
  return mb;
}

void write_vtm_atomically(const std::string& path, vtkMultiBlockDataSet* data) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    throw Error("cannot write '" + path + "': directory '" + dir.string() + "' does not exist");
  }
  if (fs::is_directory(target, ec)) throw Error("cannot write '" + path + "': it is a directory");
  // The writer puts the pieces in a directory named after the file's stem, next to it, and the
  // .vtm refers to them by that relative name: write both under their final names inside a
  // temporary directory, then move the pieces' directory and, last, the .vtm into place.
  // Names built with append rather than "." + ...: GCC 12 warns falsely (-Wrestrict, PR 105651).
  auto hidden = [&](const char* what) {
    std::string name(1, '.');
    name.append(target.stem().string()).append(what).append(std::to_string(::getpid()));
    return dir / name;
  };
  const fs::path tmp = hidden(".tmp");
  fs::remove_all(tmp, ec);
  if (!fs::create_directory(tmp, ec)) {
    throw Error("cannot write '" + path + "': cannot create a temporary directory in '" +
                dir.string() + "'" + (ec ? ": " + ec.message() : ""));
  }
  const fs::path pieces = dir / target.stem();
  const fs::path old = hidden(".old");
  try {
    vtkNew<vtkXMLMultiBlockDataWriter> w;
    w->SetFileName((tmp / target.filename()).string().c_str());
    w->SetInputData(data);
    w->SetDataModeToAppended();
    w->EncodeAppendedDataOff();
    w->SetCompressorTypeToZLib();
    if (w->Write() != 1 || w->GetErrorCode() != 0) {
      throw Error("cannot write '" + path + "': the VTK writer failed");
    }
    if (!fs::exists(tmp / target.filename(), ec)) {
      throw Error("writing '" + path + "' produced no file");
    }
    // Replace an older pieces' directory (moved aside first: a rename cannot replace a
    // non-empty directory).
    if (fs::exists(pieces, ec)) {
      if (!fs::is_directory(pieces, ec)) {
        throw Error("cannot write '" + path + "': '" + pieces.string() +
                    "' (where its pieces go) exists and is not a directory");
      }
      fs::rename(pieces, old, ec);
      if (ec) throw Error("cannot replace '" + pieces.string() + "': " + ec.message());
    }
    if (fs::exists(tmp / target.stem(), ec)) {
      fs::rename(tmp / target.stem(), pieces, ec);
      if (ec) throw Error("cannot write '" + pieces.string() + "': " + ec.message());
    }
    fs::rename(tmp / target.filename(), target, ec);
    if (ec) throw Error("cannot write '" + path + "': " + ec.message());
  } catch (...) {
    fs::remove_all(tmp, ec);
    if (fs::exists(old, ec) && !fs::exists(pieces, ec)) fs::rename(old, pieces, ec);
    throw;
  }
  fs::remove_all(tmp, ec);
  fs::remove_all(old, ec);
}

}  // namespace iaa::viz
