// The stage and its two displays (see scene_stage.h).
#include "scene_stage.h"

#include <algorithm>

#include <vtkCellArray.h>
#include <vtkImageData.h>
#include <vtkInteractorStyleTrackballCamera.h>
#include <vtkLegendBoxActor.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkProperty2D.h>
#include <vtkRenderWindow.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkWindowToImageFilter.h>

#include "viz/scene_actors.h"

namespace iaa::viz {

namespace {

/// Renderers, window and overlays shared by the image and the interactive displays.
struct Stage {
  std::vector<vtkSmartPointer<vtkRenderer>> views;
  vtkNew<vtkRenderWindow> win;
  vtkNew<vtkLegendBoxActor> legend;
  vtkNew<vtkTextActor> title;
  std::vector<vtkSmartPointer<vtkTextActor>> captions;
};

/// View `i` of `n` side by side, empty.
vtkSmartPointer<vtkRenderer> new_view(int i, int n, const ViewSettings& v) {
  auto ren = vtkSmartPointer<vtkRenderer>::New();
  ren->SetViewport(double(i) / n, 0.0, double(i + 1) / n, 1.0);
  ren->SetBackground(v.background.x, v.background.y, v.background.z);
  // Translucent frusta and boxes need depth peeling to blend in the right order.
  ren->SetUseDepthPeeling(1);
  ren->SetMaximumNumberOfPeels(12);
  ren->SetOcclusionRatio(0.0);
  ren->UseFXAAOn();
  return ren;
}

/// The layers drawn in view `i` of `n` (a layer's viewport is clamped to the views there are).
std::vector<Layer> layers_in_view(const std::vector<Layer>& layers, int i, int n) {
  std::vector<Layer> mine;
  for (const Layer& l : layers) {
    if (std::clamp(l.viewport, 0, n - 1) == i) mine.push_back(l);
  }
  return mine;
}

/// Draws view `i`'s caption, if it has one, at the view's bottom left.
void add_caption(Stage& s, vtkRenderer* ren, int i, const ViewSettings& v) {
  if (i >= static_cast<int>(v.captions.size()) || v.captions[i].empty()) return;
  auto cap = vtkSmartPointer<vtkTextActor>::New();
  cap->SetInput(v.captions[i].c_str());
  cap->GetTextProperty()->SetColor(0.05, 0.05, 0.05);
  cap->GetTextProperty()->SetFontSize(15);
  cap->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  cap->GetPositionCoordinate()->SetValue(0.015, 0.015);
  ren->AddActor2D(cap);
  s.captions.push_back(cap);
}

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

/// Draws the legend at the top right of the last view, `view_w` pixels wide.
void add_legend_box(Stage& s, const std::vector<LegendEntry>& entries, const ViewSettings& v,
                    double view_w) {
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
  // Its size in pixels converted to viewport units, so that the text keeps its size.
  const double h = std::min(0.9, (20.0 * static_cast<double>(entries.size()) + 10) / v.height);
  const double w = std::min(0.6, 270.0 / view_w);
  s.legend->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  s.legend->GetPositionCoordinate()->SetValue(0.99 - w, 0.99 - h);
  s.legend->GetPosition2Coordinate()->SetValue(w, h);
  s.views.back()->AddActor2D(s.legend);
}

/// Draws the title at the top left of the first view.
void add_title(Stage& s, const ViewSettings& v) {
  s.title->SetInput(v.title.c_str());
  s.title->GetTextProperty()->SetColor(0.05, 0.05, 0.05);
  s.title->GetTextProperty()->SetFontSize(16);
  s.title->SetDisplayPosition(10, v.height - 26);
  s.views[0]->AddActor2D(s.title);
}

/// Builds the window, its views with their layers and captions, the legend, the title and the
/// camera that all views share.
void setup_stage(Stage& s, const std::vector<Layer>& layers, const ViewSettings& v) {
  const int n = std::clamp(v.viewports, 1, 4);
  s.win->SetAlphaBitPlanes(1);
  s.win->SetMultiSamples(0);
  s.win->SetSize(v.width, v.height);
  const double radius = focus_radius(layers);
  Legend legend;
  for (int i = 0; i < n; ++i) {
    vtkSmartPointer<vtkRenderer> ren = new_view(i, n, v);
    if (i > 0) ren->SetActiveCamera(s.views[0]->GetActiveCamera());
    s.win->AddRenderer(ren);
    s.views.push_back(ren);
    add_layer_actors(ren, layers_in_view(layers, i, n), radius, legend);
    add_caption(s, ren, i, v);
  }
  const double view_w = double(v.width) / n;
  if (v.legend && !legend.entries().empty()) add_legend_box(s, legend.entries(), v, view_w);
  if (!v.title.empty()) add_title(s, v);
  const ViewCamera cam =
      v.camera ? *v.camera : auto_camera(layers, std::nullopt, view_w / double(v.height));
  apply_camera(s.views[0], cam, layers);
}

/// The window's back buffer as an RgbImage (VTK's rows start at the bottom, the image's at the
/// top).
RgbImage grab_image(vtkRenderWindow* win) {
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(win);
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
  for (int y = 0; y < out.height; ++y) {
    const std::uint8_t* row = src + std::size_t(out.height - 1 - y) * out.width * comps;
    for (int x = 0; x < out.width; ++x) {
      for (int c = 0; c < 3; ++c)
        out.rgb[(std::size_t(y) * out.width + x) * 3 + c] = row[x * comps + c];
    }
  }
  return out;
}

}  // namespace

RgbImage render_to_image(const std::vector<Layer>& layers, const ViewSettings& v) {
  Stage s;
  s.win->SetOffScreenRendering(1);
  setup_stage(s, layers, v);
  s.win->Render();
  return grab_image(s.win);
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
