// Shared VTK rendering of iaa overlays (see scene_render.h).
#include "scene_render.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <set>

#include <vtkActor.h>
#include <vtkArrowSource.h>
#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCommand.h>
#include <vtkCompositeDataSet.h>
#include <vtkDataArray.h>
#include <vtkDataObjectTreeIterator.h>
#include <vtkDataSet.h>
#include <vtkDataSetMapper.h>
#include <vtkDataSetReader.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkGlyph3D.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInteractorStyleTrackballCamera.h>
#include <vtkLegendBoxActor.h>
#include <vtkLookupTable.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkOBJReader.h>
#include <vtkPLYReader.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataNormals.h>
#include <vtkProperty.h>
#include <vtkProperty2D.h>
#include <vtkRenderWindow.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkVariant.h>
#include <vtkWindowToImageFilter.h>
#include <vtkXMLMultiBlockDataReader.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "core/error.h"

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

// ---- Categories -------------------------------------------------------------------------------

const std::vector<Category>& categories_of(const std::string& name) {
  static const std::vector<Category> kResult = {
      {kResultMiss, "miss", {0.55, 0.55, 0.6}},
      {kResultFull, "full", {0.15, 0.65, 0.25}},
      {kResultPartial, "partial", {1.0, 0.55, 0.05}},
  };
  static const std::vector<Category> kVerdict = {
      {kVerdictExcluded, "excluded (0 not in F)", {0.3, 0.5, 0.95}},
      {kVerdictKept, "kept (0 in F)", {0.9, 0.15, 0.15}},
  };
  static const std::vector<Category> kClass = {
      {kClassCrossing, "crossing", {0.1, 0.55, 0.6}},
      {kClassPossible, "possible", {0.95, 0.75, 0.1}},
  };
  static const std::vector<Category> kNone;
  if (name == kResultArray) return kResult;
  if (name == kVerdictArray) return kVerdict;
  if (name == kClassArray) return kClass;
  return kNone;
}

namespace {

bool has_cell_array(vtkDataSet* d, const char* name) {
  return d && d->GetCellData() && d->GetCellData()->GetArray(name) != nullptr;
}

bool name_has(const std::string& name, const char* what) {
  std::string lower = name;
  for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return lower.find(what) != std::string::npos;
}

/// The categorical array a layer is coloured by, or empty.
std::string colour_array(const Layer& l) {
  switch (l.role) {
    case LayerRole::kFrusta:
    case LayerRole::kSlabs:
      return has_cell_array(l.data, kResultArray) ? kResultArray : "";
    case LayerRole::kDepthBoxes:
      return has_cell_array(l.data, kVerdictArray) ? kVerdictArray : "";
    case LayerRole::kEnclosure:
      return has_cell_array(l.data, kClassArray) ? kClassArray : "";
    default:
      break;
  }
  for (const char* a : {kVerdictArray, kResultArray, kClassArray}) {
    if (has_cell_array(l.data, a)) return a;
  }
  return "";
}

/// Distinct integer codes present in a cell array.
std::set<int> codes_in(vtkDataSet* d, const std::string& array) {
  std::set<int> out;
  vtkDataArray* a = d->GetCellData()->GetArray(array.c_str());
  if (!a) return out;
  for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i) {
    out.insert(static_cast<int>(std::lround(a->GetTuple1(i))));
  }
  return out;
}

const char* role_label(LayerRole r) {
  switch (r) {
    case LayerRole::kFrusta:
      return "beam";
    case LayerRole::kSlabs:
      return "hit slab";
    case LayerRole::kDepthBoxes:
      return "depth box";
    case LayerRole::kPoints:
      return "hit point + normal";
    case LayerRole::kEnclosure:
      return "box";
    case LayerRole::kMesh:
      return "mesh";
    case LayerRole::kGeneric:
      return "";
  }
  return "";
}

double default_opacity(LayerRole r) {
  switch (r) {
    case LayerRole::kFrusta:
      return 0.12;
    case LayerRole::kSlabs:
      return 0.9;
    case LayerRole::kDepthBoxes:
      return 0.15;
    case LayerRole::kEnclosure:
      return 0.45;
    default:
      return 1.0;
  }
}

/// Colours for layers that have no categorical array, in order.
Vec3 plain_colour(LayerRole r, int index) {
  if (r == LayerRole::kMesh) return {0.78, 0.78, 0.84};
  if (r == LayerRole::kPoints) return {0.1, 0.1, 0.1};
  if (r == LayerRole::kFrusta) return {0.45, 0.45, 0.55};
  static const Vec3 kPalette[] = {
      {0.8, 0.8, 0.85}, {0.55, 0.7, 0.9}, {0.85, 0.6, 0.5}, {0.6, 0.8, 0.55}, {0.8, 0.6, 0.85}};
  return kPalette[index % 5];
}

/// Collects VTK error text while a reader runs, instead of letting VTK print it.
class ErrorCatcher {
 public:
  explicit ErrorCatcher(vtkObject* o) : object_(o) {
    cb_->SetClientData(this);
    cb_->SetCallback(&ErrorCatcher::on_error);
    tag_ = o->AddObserver(vtkCommand::ErrorEvent, cb_);
    warn_tag_ = o->AddObserver(vtkCommand::WarningEvent, cb_);
  }
  ~ErrorCatcher() {
    object_->RemoveObserver(tag_);
    object_->RemoveObserver(warn_tag_);
  }
  const std::string& text() const { return text_; }

 private:
  static void on_error(vtkObject*, unsigned long, void* self, void* call_data) {
    auto* me = static_cast<ErrorCatcher*>(self);
    if (me->text_.empty() && call_data) {
      std::string t = static_cast<const char*>(call_data);
      while (!t.empty() && (t.back() == '\n' || t.back() == ' ')) t.pop_back();
      me->text_ = t;
    }
  }
  vtkObject* object_;
  vtkNew<vtkCallbackCommand> cb_;
  unsigned long tag_ = 0, warn_tag_ = 0;
  std::string text_;
};

std::string lower_extension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  if (!e.empty() && e[0] == '.') e.erase(0, 1);
  for (char& ch : e) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return e;
}

/// Runs a reader and returns its output; throws iaa::Error with VTK's message on failure.
template <class Reader>
vtkSmartPointer<vtkDataObject> run_reader(Reader* r, const std::string& path) {
  r->SetFileName(path.c_str());
  ErrorCatcher catcher(r);
  r->Update();
  vtkDataObject* out = r->GetOutputDataObject(0);
  if (!catcher.text().empty() || !out) {
    std::string why = catcher.text();
    // VTK's messages start with a location ("ERROR: In .../vtkXMLReader.cxx, line 123 ..."):
    // keep the last line, which says what is wrong.
    const auto nl = why.find_last_of('\n');
    if (nl != std::string::npos) why = why.substr(nl + 1);
    throw Error("cannot read '" + path +
                "': " + (why.empty() ? "the reader produced no data" : why));
  }
  return out;
}

}  // namespace

LayerRole guess_role(const std::string& name, vtkDataSet* d) {
  if (name_has(name, "frust") || name_has(name, "beam")) return LayerRole::kFrusta;
  if (name_has(name, "slab")) return LayerRole::kSlabs;
  if (name_has(name, "depth")) return LayerRole::kDepthBoxes;
  if (name_has(name, "point") || name_has(name, "hit")) return LayerRole::kPoints;
  // The arrays say more than a loose file name such as "boxes.vtu".
  if (has_cell_array(d, kVerdictArray)) return LayerRole::kDepthBoxes;
  if (has_cell_array(d, kClassArray)) return LayerRole::kEnclosure;
  if (has_cell_array(d, kResultArray)) return LayerRole::kSlabs;
  if (name_has(name, "enclos") || name_has(name, "octree") || name_has(name, "box")) {
    return LayerRole::kEnclosure;
  }
  if (name_has(name, "mesh")) return LayerRole::kMesh;
  if (auto* pd = vtkPolyData::SafeDownCast(d); pd && pd->GetNumberOfPolys() > 0) {
    return LayerRole::kMesh;
  }
  return LayerRole::kGeneric;
}

std::string known_extensions() {
  return ".vtm, .vtu, .vtp, .vtk, .ply, .obj";
}

std::vector<Layer> load_layers(const std::string& path, std::optional<ViewCamera>* camera) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const std::string ext = lower_extension(path);
  static const std::set<std::string> kKnown = {"vtm", "vtu", "vtp", "vtk", "ply", "obj"};
  if (!kKnown.count(ext)) {
    throw Error("'" + path + "': unknown file type" + (ext.empty() ? "" : " '." + ext + "'") +
                "; iaa-viz reads " + known_extensions());
  }
  if (!fs::exists(path, ec)) throw Error("cannot read '" + path + "': no such file");
  if (fs::is_directory(path, ec)) throw Error("cannot read '" + path + "': it is a directory");

  vtkSmartPointer<vtkDataObject> obj;
  if (ext == "vtm") {
    vtkNew<vtkXMLMultiBlockDataReader> r;
    obj = run_reader(r.Get(), path);
  } else if (ext == "vtu") {
    vtkNew<vtkXMLUnstructuredGridReader> r;
    obj = run_reader(r.Get(), path);
  } else if (ext == "vtp") {
    vtkNew<vtkXMLPolyDataReader> r;
    obj = run_reader(r.Get(), path);
  } else if (ext == "vtk") {
    vtkNew<vtkDataSetReader> r;
    obj = run_reader(r.Get(), path);
  } else if (ext == "ply") {
    if (!vtkPLYReader::CanReadFile(path.c_str())) {
      throw Error("cannot read '" + path + "': not a PLY file");
    }
    vtkNew<vtkPLYReader> r;
    obj = run_reader(r.Get(), path);
  } else {
    vtkNew<vtkOBJReader> r;
    obj = run_reader(r.Get(), path);
  }

  const std::string stem = fs::path(path).filename().string();
  std::vector<Layer> layers;
  auto add = [&](vtkDataSet* d, const std::string& name) {
    if (camera && !*camera) *camera = recorded_camera(d);
    if (!d || d->GetNumberOfPoints() == 0) return;
    Layer l;
    l.name = name;
    l.data = d;
    l.role = guess_role(name, d);
    layers.push_back(std::move(l));
  };
  if (auto* mb = vtkMultiBlockDataSet::SafeDownCast(obj)) {
    if (camera && !*camera) *camera = recorded_camera(mb);
    vtkSmartPointer<vtkDataObjectTreeIterator> it;
    it.TakeReference(mb->NewTreeIterator());
    it->VisitOnlyLeavesOn();
    it->SkipEmptyNodesOn();
    int index = 0;
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem(), ++index) {
      std::string name = "block " + std::to_string(index);
      if (it->HasCurrentMetaData() && it->GetCurrentMetaData()->Has(vtkCompositeDataSet::NAME())) {
        name = it->GetCurrentMetaData()->Get(vtkCompositeDataSet::NAME());
      }
      add(vtkDataSet::SafeDownCast(it->GetCurrentDataObject()), name);
    }
  } else if (auto* ds = vtkDataSet::SafeDownCast(obj)) {
    add(ds, stem);
  } else {
    throw Error("cannot read '" + path + "': not a data set VTK can draw");
  }
  if (layers.empty()) throw Error("'" + path + "' holds no points to draw");
  // In a pixel inspection the slabs, depth boxes near the hits and the points are the subject;
  // the search's coarse pieces and the enclosure boxes around them are context, outlined.
  bool inspection = false;
  for (const Layer& l : layers)
    inspection |= l.role == LayerRole::kSlabs || l.role == LayerRole::kPoints;
  if (inspection) {
    for (Layer& l : layers)
      l.outline = name_has(l.name, "coarse") || l.role == LayerRole::kEnclosure ||
                  l.role == LayerRole::kFrusta;
  }
  return layers;
}

// ---- Camera -----------------------------------------------------------------------------------

namespace {

struct Bounds {
  Vec3 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
          std::numeric_limits<double>::infinity()};
  Vec3 hi{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
          -std::numeric_limits<double>::infinity()};
  bool empty() const { return !(lo.x <= hi.x); }
  void add(const double b[6]) {
    if (!(b[0] <= b[1])) return;
    for (int i = 0; i < 3; ++i) {
      lo[i] = std::min(lo[i], b[2 * i]);
      hi[i] = std::max(hi[i], b[2 * i + 1]);
    }
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
    double b[6];
    l.data->GetBounds(b);
    all.add(b);
    const bool subject = l.role == LayerRole::kSlabs || l.role == LayerRole::kPoints ||
                         l.role == LayerRole::kDepthBoxes;
    if (subject && !l.outline) focus.add(b);
  }
  // A focus of a single point (one hit point and nothing else) is no scale to frame.
  if (focus.empty() || !(focus.radius() > 0)) return all;
  return focus;
}

}  // namespace

ViewCamera auto_camera(const std::vector<Layer>& layers, const std::optional<ViewCamera>& hint,
                       double aspect) {
  const Bounds b = focus_bounds(layers);
  ViewCamera c;
  c.fov_deg = 30;
  if (b.empty()) return c;
  const Vec3 centre = b.center();
  double r = b.radius();
  if (!(r > 0)) r = 1;
  Vec3 to_eye = normalize(Vec3{0.55, 0.45, 1.0});
  Vec3 up{0, 1, 0};
  if (hint) {
    // Look at the beam from its side, turned 35 degrees towards the original eye, so its depth
    // extent is visible rather than seen end-on.
    const Vec3 d = normalize(hint->look_at - hint->eye);
    Vec3 side = cross(d, hint->up);
    if (length(side) < 1e-12) side = cross(d, Vec3{1, 0, 0});
    side = normalize(side);
    const double a = 35.0 * M_PI / 180.0;
    to_eye = normalize(std::cos(a) * side - std::sin(a) * d);
    up = normalize(cross(side, d));
    if (dot(up, hint->up) < 0) up = -up;
  }
  const double half = 0.5 * c.fov_deg * M_PI / 180.0;
  const double half_h = std::atan(std::tan(half) * std::min(1.0, aspect));
  const double dist = 1.08 * r / std::sin(std::min(half, half_h));
  c.look_at = centre;
  c.eye = centre + dist * to_eye;
  c.up = up;
  return c;
}

// ---- Rendering --------------------------------------------------------------------------------

namespace {

vtkSmartPointer<vtkLookupTable> lookup_table(const std::string& array) {
  auto lut = vtkSmartPointer<vtkLookupTable>::New();
  const auto& cats = categories_of(array);
  lut->IndexedLookupOn();
  lut->SetNumberOfTableValues(static_cast<vtkIdType>(cats.size()));
  for (std::size_t i = 0; i < cats.size(); ++i) {
    const Vec3& c = cats[i].color;
    lut->SetTableValue(static_cast<vtkIdType>(i), c.x, c.y, c.z, 1.0);
    lut->SetAnnotation(vtkVariant(cats[i].code), cats[i].label);
  }
  lut->SetNanColor(0.5, 0.5, 0.5, 1.0);
  return lut;
}

struct LegendEntry {
  std::string label;
  Vec3 color;
};

/// A filled unit square: the legend's symbol.
vtkSmartPointer<vtkPolyData> square_symbol() {
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> pts;
  pts->InsertNextPoint(0, 0, 0);
  pts->InsertNextPoint(1, 0, 0);
  pts->InsertNextPoint(1, 1, 0);
  pts->InsertNextPoint(0, 1, 0);
  vtkNew<vtkCellArray> polys;
  const vtkIdType q[4] = {0, 1, 2, 3};
  polys->InsertNextCell(4, q);
  pd->SetPoints(pts);
  pd->SetPolys(polys);
  return pd;
}

/// Builds every actor of the scene into `ren`; returns the legend entries.
std::vector<LegendEntry> build_scene(vtkRenderer* ren, const std::vector<Layer>& layers,
                                     const std::vector<Layer>& all) {
  std::vector<LegendEntry> legend;
  std::set<std::string> seen;
  auto add_legend = [&](const std::string& label, Vec3 c) {
    if (seen.insert(label).second) legend.push_back({label, c});
  };
  const Bounds focus = focus_bounds(all);
  const double focus_r = focus.empty() || !(focus.radius() > 0) ? 1.0 : focus.radius();

  int plain_index = 0;
  for (const Layer& l : layers) {
    const double opacity = l.opacity >= 0 ? l.opacity : default_opacity(l.role);
    const std::string array = colour_array(l);

    if (l.role == LayerRole::kPoints) {
      // Hit points as spheres, coloured by their shaded colour when recorded, and their normals
      // as arrows.
      vtkNew<vtkDataSetMapper> m;
      m->SetInputData(l.data);
      vtkNew<vtkActor> a;
      a->SetMapper(m);
      a->GetProperty()->SetRepresentationToPoints();
      a->GetProperty()->SetRenderPointsAsSpheres(true);
      a->GetProperty()->SetPointSize(11);
      a->GetProperty()->SetColor(0.1, 0.1, 0.1);
      vtkDataArray* col = l.data->GetPointData()->GetArray("color");
      const bool coloured =
          col && col->GetNumberOfComponents() == 3 && vtkUnsignedCharArray::SafeDownCast(col);
      if (coloured) {
        m->SetScalarModeToUsePointFieldData();
        m->SelectColorArray("color");
        m->SetColorModeToDirectScalars();
        m->ScalarVisibilityOn();
      } else {
        m->ScalarVisibilityOff();
      }
      ren->AddActor(a);
      // Legend text is drawn in the entry's colour on a dark box: black would not show.
      add_legend(coloured ? "hit point (in its shaded colour)" : "hit point (black)",
                 {0.85, 0.85, 0.85});
      if (l.data->GetPointData()->GetNormals()) {
        vtkNew<vtkArrowSource> arrow;
        arrow->SetTipResolution(16);
        arrow->SetShaftResolution(12);
        vtkNew<vtkGlyph3D> glyph;
        glyph->SetInputData(l.data);
        glyph->SetSourceConnection(arrow->GetOutputPort());
        glyph->SetVectorModeToUseNormal();
        glyph->SetScaleModeToDataScalingOff();
        glyph->SetScaleFactor(0.3 * focus_r);
        glyph->OrientOn();
        vtkNew<vtkPolyDataMapper> gm;
        gm->SetInputConnection(glyph->GetOutputPort());
        gm->ScalarVisibilityOff();
        vtkNew<vtkActor> ga;
        ga->SetMapper(gm);
        ga->GetProperty()->SetColor(0.05, 0.05, 0.05);
        ren->AddActor(ga);
        add_legend("normal at hit (black arrow)", {0.85, 0.85, 0.85});
      }
      continue;
    }

    vtkNew<vtkActor> a;
    vtkSmartPointer<vtkMapper> mapper;
    auto* pd = vtkPolyData::SafeDownCast(l.data);
    if (l.role == LayerRole::kMesh && pd && pd->GetNumberOfPolys() > 0 &&
        !pd->GetPointData()->GetNormals()) {
      vtkNew<vtkPolyDataNormals> normals;
      normals->SetInputData(pd);
      normals->SplittingOff();
      normals->ConsistencyOn();
      auto pm = vtkSmartPointer<vtkPolyDataMapper>::New();
      pm->SetInputConnection(normals->GetOutputPort());
      mapper = pm;
    } else {
      auto dm = vtkSmartPointer<vtkDataSetMapper>::New();
      dm->SetInputData(l.data);
      mapper = dm;
    }
    a->SetMapper(mapper);
    vtkProperty* p = a->GetProperty();
    p->SetOpacity(l.outline && l.opacity < 0 ? 0.6 : opacity);
    if (!array.empty()) {
      mapper->SetScalarModeToUseCellFieldData();
      mapper->SelectColorArray(array.c_str());
      mapper->SetLookupTable(lookup_table(array));
      mapper->UseLookupTableScalarRangeOn();
      mapper->ScalarVisibilityOn();
      const std::string prefix =
          std::string(l.outline && l.role == LayerRole::kDepthBoxes ? "coarse " : "") +
          role_label(l.role);
      const std::set<int> present = codes_in(l.data, array);
      for (const Category& c : categories_of(array)) {
        if (present.count(c.code)) {
          add_legend((prefix.empty() ? std::string(array) : prefix) + ": " + c.label, c.color);
        }
      }
    } else {
      mapper->ScalarVisibilityOff();
      const Vec3 c = plain_colour(l.role, plain_index++);
      p->SetColor(c.x, c.y, c.z);
      add_legend(role_label(l.role)[0] ? role_label(l.role) : l.name, c);
    }
    if (l.outline) {
      p->SetRepresentationToWireframe();
      p->SetLineWidth(1.5);
      p->LightingOff();
      ren->AddActor(a);
      continue;
    }
    switch (l.role) {
      case LayerRole::kFrusta:
        p->SetEdgeVisibility(true);
        p->SetEdgeColor(0.25, 0.25, 0.3);
        p->SetLineWidth(1.5);
        p->LightingOff();
        break;
      case LayerRole::kSlabs:
      case LayerRole::kDepthBoxes:
        p->SetEdgeVisibility(true);
        p->SetEdgeColor(0.15, 0.15, 0.15);
        p->SetLineWidth(1.0);
        break;
      case LayerRole::kEnclosure:
        // Edges help to tell a few boxes apart; on thousands they only darken the picture.
        if (l.data->GetNumberOfCells() <= 3000) {
          p->SetEdgeVisibility(true);
          p->SetEdgeColor(0.2, 0.2, 0.2);
        }
        break;
      case LayerRole::kMesh:
        p->SetSpecular(0.25);
        p->SetSpecularPower(30);
        // Some light on faces seen at a grazing angle (a pixel's beam is looked at from its side).
        p->SetAmbient(0.3);
        p->SetDiffuse(0.75);
        if (pd && pd->GetNumberOfPolys() > 0 && pd->GetNumberOfPolys() < 6000) {
          p->SetEdgeVisibility(true);
          p->SetEdgeColor(0.5, 0.5, 0.56);
        }
        break;
      default:
        break;
    }
    ren->AddActor(a);
  }
  return legend;
}

void set_camera(vtkRenderer* ren, const ViewCamera& c) {
  vtkCamera* cam = ren->GetActiveCamera();
  cam->SetPosition(c.eye.x, c.eye.y, c.eye.z);
  cam->SetFocalPoint(c.look_at.x, c.look_at.y, c.look_at.z);
  cam->SetViewUp(c.up.x, c.up.y, c.up.z);
  cam->SetViewAngle(c.fov_deg);
  cam->OrthogonalizeViewUp();
  ren->ResetCameraClippingRange();
}

/// Renderers, window and overlays shared by the image and the interactive paths.
struct Stage {
  std::vector<vtkSmartPointer<vtkRenderer>> views;
  vtkNew<vtkRenderWindow> win;
  vtkNew<vtkLegendBoxActor> legend;
  vtkNew<vtkTextActor> title;
  std::vector<vtkSmartPointer<vtkTextActor>> captions;
};

void setup_stage(Stage& s, const std::vector<Layer>& layers, const ViewSettings& v) {
  const int n = std::clamp(v.viewports, 1, 4);
  s.win->SetAlphaBitPlanes(1);
  s.win->SetMultiSamples(0);
  s.win->SetSize(v.width, v.height);
  std::vector<LegendEntry> entries;
  for (int i = 0; i < n; ++i) {
    auto ren = vtkSmartPointer<vtkRenderer>::New();
    ren->SetViewport(double(i) / n, 0.0, double(i + 1) / n, 1.0);
    ren->SetBackground(v.background.x, v.background.y, v.background.z);
    // Translucent frusta and boxes need depth peeling to blend in the right order.
    ren->SetUseDepthPeeling(1);
    ren->SetMaximumNumberOfPeels(12);
    ren->SetOcclusionRatio(0.0);
    ren->UseFXAAOn();
    if (i > 0) ren->SetActiveCamera(s.views[0]->GetActiveCamera());
    s.win->AddRenderer(ren);
    s.views.push_back(ren);
    std::vector<Layer> mine;
    for (const Layer& l : layers) {
      if (std::clamp(l.viewport, 0, n - 1) == i) mine.push_back(l);
    }
    for (LegendEntry& e : build_scene(ren, mine, layers)) {
      bool dup = false;
      for (const LegendEntry& f : entries) dup |= f.label == e.label;
      if (!dup) entries.push_back(std::move(e));
    }
    if (i < static_cast<int>(v.captions.size()) && !v.captions[i].empty()) {
      auto cap = vtkSmartPointer<vtkTextActor>::New();
      cap->SetInput(v.captions[i].c_str());
      cap->GetTextProperty()->SetColor(0.05, 0.05, 0.05);
      cap->GetTextProperty()->SetFontSize(15);
      cap->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
      cap->GetPositionCoordinate()->SetValue(0.015, 0.015);
      ren->AddActor2D(cap);
      s.captions.push_back(cap);
    }
  }
  vtkRenderer* last = s.views.back();
  const double view_w = double(v.width) / n;
  if (v.legend && !entries.empty()) {
    auto symbol = square_symbol();
    s.legend->SetNumberOfEntries(static_cast<int>(entries.size()));
    for (std::size_t i = 0; i < entries.size(); ++i) {
      double c[3] = {entries[i].color.x, entries[i].color.y, entries[i].color.z};
      s.legend->SetEntry(static_cast<int>(i), symbol, entries[i].label.c_str(), c);
    }
    // VTK draws each entry's text in its colour: a dark box keeps every colour readable.
    s.legend->GetEntryTextProperty()->SetFontSize(14);
    s.legend->GetEntryTextProperty()->ShadowOff();
    s.legend->UseBackgroundOn();
    s.legend->SetBackgroundColor(0.18, 0.18, 0.2);
    s.legend->SetBackgroundOpacity(0.9);
    s.legend->BorderOn();
    s.legend->GetProperty()->SetColor(0.3, 0.3, 0.3);
    // Top right; its size in pixels converted to viewport units, so text keeps its size.
    const double h = std::min(0.9, (20.0 * static_cast<double>(entries.size()) + 10) / v.height);
    const double w = std::min(0.6, 270.0 / view_w);
    s.legend->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    s.legend->GetPositionCoordinate()->SetValue(0.99 - w, 0.99 - h);
    s.legend->GetPosition2Coordinate()->SetValue(w, h);
    last->AddActor2D(s.legend);
  }
  if (!v.title.empty()) {
    s.title->SetInput(v.title.c_str());
    s.title->GetTextProperty()->SetColor(0.05, 0.05, 0.05);
    s.title->GetTextProperty()->SetFontSize(16);
    s.title->SetDisplayPosition(10, v.height - 26);
    s.views[0]->AddActor2D(s.title);
  }
  const ViewCamera cam =
      v.camera ? *v.camera : auto_camera(layers, std::nullopt, view_w / double(v.height));
  set_camera(s.views[0], cam);
  // One camera for all views: its clipping range must hold every layer, not one view's.
  Bounds all;
  for (const Layer& l : layers) {
    double b[6];
    l.data->GetBounds(b);
    all.add(b);
  }
  if (!all.empty()) {
    double b[6] = {all.lo.x, all.hi.x, all.lo.y, all.hi.y, all.lo.z, all.hi.z};
    s.views[0]->ResetCameraClippingRange(b);
  }
}

}  // namespace

RgbImage render_to_image(const std::vector<Layer>& layers, const ViewSettings& v) {
  Stage s;
  s.win->SetOffScreenRendering(1);
  setup_stage(s, layers, v);
  s.win->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(s.win);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  vtkImageData* img = grab->GetOutput();
  int dims[3];
  img->GetDimensions(dims);
  RgbImage out;
  out.width = dims[0];
  out.height = dims[1];
  out.rgb.resize(std::size_t(out.width) * out.height * 3);
  auto* src = static_cast<const std::uint8_t*>(img->GetScalarPointer());
  const int comps = img->GetNumberOfScalarComponents();
  // VTK's rows start at the bottom; images start at the top.
  for (int y = 0; y < out.height; ++y) {
    const std::uint8_t* row = src + std::size_t(out.height - 1 - y) * out.width * comps;
    for (int x = 0; x < out.width; ++x) {
      for (int c = 0; c < 3; ++c)
        out.rgb[(std::size_t(y) * out.width + x) * 3 + c] = row[x * comps + c];
    }
  }
  return out;
}

void show_interactive(const std::vector<Layer>& layers, const ViewSettings& v) {
  Stage s;
  setup_stage(s, layers, v);
  s.win->SetWindowName(v.title.empty() ? "iaa-viz" : v.title.c_str());
  vtkNew<vtkRenderWindowInteractor> iren;
  vtkNew<vtkInteractorStyleTrackballCamera> style;
  iren->SetRenderWindow(s.win);
  iren->SetInteractorStyle(style);
  s.win->Render();
  iren->Initialize();
  iren->Start();
}

}  // namespace iaa::viz
