// The look of each layer (see scene_actors.h).
#include "scene_actors.h"

#include <cmath>

#include <vtkActor.h>
#include <vtkArrowSource.h>
#include <vtkCellCenters.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkDataSetMapper.h>
#include <vtkGlyph3D.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataNormals.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkUnsignedCharArray.h>
#include <vtkVariant.h>

namespace iaa::viz {

namespace {

// ---- Colours and labels by role ---------------------------------------------------------------

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
    case LayerRole::kUncertified:
      return "";  // one colour: where they are matters, not why
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
    case LayerRole::kUncertified:
      return "uncertified cell";
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

/// The layer's own opacity, else 0.6 for an outline, else its role's.
double layer_opacity(const Layer& l) {
  if (l.opacity >= 0) return l.opacity;
  return l.outline ? 0.6 : default_opacity(l.role);
}

/// Colours for layers that have no categorical array, in order.
Vec3 plain_colour(LayerRole r, int index) {
  if (r == LayerRole::kMesh) return {0.78, 0.78, 0.84};
  if (r == LayerRole::kPoints) return {0.1, 0.1, 0.1};
  if (r == LayerRole::kFrusta) return {0.45, 0.45, 0.55};
  if (r == LayerRole::kUncertified) return {0.9, 0.1, 0.1};
  static const Vec3 kPalette[] = {
      {0.8, 0.8, 0.85}, {0.55, 0.7, 0.9}, {0.85, 0.6, 0.5}, {0.6, 0.8, 0.55}, {0.8, 0.6, 0.85}};
  return kPalette[index % 5];
}

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

// ---- Hit points -------------------------------------------------------------------------------

/// The normals of `points` as black arrows of length `scale`.
vtkSmartPointer<vtkActor> normal_arrows(vtkDataSet* points, double scale) {
  vtkNew<vtkArrowSource> arrow;
  arrow->SetTipResolution(16);
  arrow->SetShaftResolution(12);
  vtkNew<vtkGlyph3D> glyph;
  glyph->SetInputData(points);
  glyph->SetSourceConnection(arrow->GetOutputPort());
  glyph->SetVectorModeToUseNormal();
  glyph->SetScaleModeToDataScalingOff();
  glyph->SetScaleFactor(scale);
  glyph->OrientOn();
  vtkNew<vtkPolyDataMapper> m;
  m->SetInputConnection(glyph->GetOutputPort());
  m->ScalarVisibilityOff();
  auto a = vtkSmartPointer<vtkActor>::New();
  a->SetMapper(m);
  a->GetProperty()->SetColor(0.05, 0.05, 0.05);
  return a;
}

/// Hit points as spheres, in their shaded colour when recorded (else black), and their normals
/// as arrows.
void add_point_actors(vtkRenderer* ren, const Layer& l, double focus_radius, Legend& legend) {
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
  legend.add(coloured ? "hit point (in its shaded colour)" : "hit point (black)",
             {0.85, 0.85, 0.85});
  if (l.data->GetPointData()->GetNormals()) {
    ren->AddActor(normal_arrows(l.data, 0.3 * focus_radius));
    legend.add("normal at hit (black arrow)", {0.85, 0.85, 0.85});
  }
}

// ---- Uncertified cells -------------------------------------------------------------------------

/// A red dot of fixed screen size at each cell's centre: the cells themselves are often smaller
/// than a pixel (the neck of a teardrop, a node of chubs).
void add_cell_markers(vtkRenderer* ren, const Layer& l) {
  vtkNew<vtkCellCenters> centres;
  centres->SetInputData(l.data);
  centres->VertexCellsOn();  // the mapper draws cells, not bare points
  vtkNew<vtkPolyDataMapper> m;
  m->SetInputConnection(centres->GetOutputPort());
  m->ScalarVisibilityOff();
  vtkNew<vtkActor> a;
  a->SetMapper(m);
  vtkProperty* p = a->GetProperty();
  p->SetRepresentationToPoints();
  p->SetRenderPointsAsSpheres(true);
  p->SetPointSize(7);
  const Vec3 c = plain_colour(LayerRole::kUncertified, 0);
  p->SetColor(c.x, c.y, c.z);
  ren->AddActor(a);
}

// ---- Cells ------------------------------------------------------------------------------------

/// The layer's data as vtkPolyData when it has polygons, else null.
vtkPolyData* polygons_of(const Layer& l) {
  auto* pd = vtkPolyData::SafeDownCast(l.data);
  return pd && pd->GetNumberOfPolys() > 0 ? pd : nullptr;
}

/// A mapper for the layer's cells; a mesh without normals gets smooth ones computed.
vtkSmartPointer<vtkMapper> cell_mapper(const Layer& l) {
  vtkPolyData* pd = polygons_of(l);
  if (l.role == LayerRole::kMesh && pd && !pd->GetPointData()->GetNormals()) {
    vtkNew<vtkPolyDataNormals> normals;
    normals->SetInputData(pd);
    normals->SplittingOff();
    normals->ConsistencyOn();
    auto pm = vtkSmartPointer<vtkPolyDataMapper>::New();
    pm->SetInputConnection(normals->GetOutputPort());
    return pm;
  }
  auto dm = vtkSmartPointer<vtkDataSetMapper>::New();
  dm->SetInputData(l.data);
  return dm;
}

/// Colours the cells by the categories of `array`; the legend gets those present.
void colour_by_category(vtkMapper* mapper, const Layer& l, const std::string& array,
                        Legend& legend) {
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
      legend.add((prefix.empty() ? std::string(array) : prefix) + ": " + c.label, c.color);
    }
  }
}

/// The edges, lighting and shading of the cells of a layer that is not outlined, by role.
void style_by_role(vtkProperty* p, const Layer& l) {
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
      if (vtkPolyData* pd = polygons_of(l); pd && pd->GetNumberOfPolys() < 6000) {
        p->SetEdgeVisibility(true);
        p->SetEdgeColor(0.5, 0.5, 0.56);
      }
      break;
    default:
      break;
  }
}

/// The cells of a layer, coloured by category or else in the next plain colour
/// (`plain_index`), outlined or styled by role.
void add_cell_actor(vtkRenderer* ren, const Layer& l, int& plain_index, Legend& legend) {
  vtkSmartPointer<vtkMapper> mapper = cell_mapper(l);
  vtkNew<vtkActor> a;
  a->SetMapper(mapper);
  vtkProperty* p = a->GetProperty();
  p->SetOpacity(layer_opacity(l));
  if (const std::string array = colour_array(l); !array.empty()) {
    colour_by_category(mapper, l, array, legend);
  } else {
    mapper->ScalarVisibilityOff();
    const Vec3 c = plain_colour(l.role, plain_index++);
    p->SetColor(c.x, c.y, c.z);
    legend.add(role_label(l.role)[0] ? role_label(l.role) : l.name, c);
  }
  if (l.outline) {
    p->SetRepresentationToWireframe();
    p->SetLineWidth(1.5);
    p->LightingOff();
  } else {
    style_by_role(p, l);
  }
  ren->AddActor(a);
}

}  // namespace

void add_layer_actors(vtkRenderer* ren, const std::vector<Layer>& layers, double focus_radius,
                      Legend& legend) {
  int plain_index = 0;
  for (const Layer& l : layers) {
    if (l.role == LayerRole::kPoints) {
      add_point_actors(ren, l, focus_radius, legend);
    } else {
      add_cell_actor(ren, l, plain_index, legend);
      if (l.role == LayerRole::kUncertified) add_cell_markers(ren, l);
    }
  }
}

}  // namespace iaa::viz
