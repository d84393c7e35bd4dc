// Reading files into layers (see scene_load.h).
#include "scene_load.h"

#include <cctype>
#include <filesystem>
#include <set>

#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkCompositeDataSet.h>
#include <vtkDataObjectTreeIterator.h>
#include <vtkDataSet.h>
#include <vtkDataSetReader.h>
#include <vtkInformation.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkOBJReader.h>
#include <vtkPLYReader.h>
#include <vtkPolyData.h>
#include <vtkSTLReader.h>
#include <vtkXMLMultiBlockDataReader.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "core/error.h"

namespace iaa::viz {

namespace {

bool name_has(const std::string& name, const char* what) {
  std::string lower = name;
  for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return lower.find(what) != std::string::npos;
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

/// Runs a new `Reader` on `path` and returns its output; throws iaa::Error with VTK's message on
/// failure.
template <class Reader>
vtkSmartPointer<vtkDataObject> read_with(const std::string& path) {
  vtkNew<Reader> r;
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

/// Throws iaa::Error unless `path` names an existing file of a known extension `ext`.
void check_readable(const std::string& path, const std::string& ext) {
  static const std::set<std::string> kKnown = {"vtm", "vtu", "vtp", "vtk", "ply", "obj", "stl"};
  if (!kKnown.count(ext)) {
    throw Error("'" + path + "': unknown file type" + (ext.empty() ? "" : " '." + ext + "'") +
                "; iaa-viz reads " + known_extensions());
  }
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw Error("cannot read '" + path + "': no such file");
  if (std::filesystem::is_directory(path, ec)) {
    throw Error("cannot read '" + path + "': it is a directory");
  }
}

/// Reads `path` with the reader for its (known) extension `ext`.
vtkSmartPointer<vtkDataObject> read_file(const std::string& path, const std::string& ext) {
  if (ext == "vtm") return read_with<vtkXMLMultiBlockDataReader>(path);
  if (ext == "vtu") return read_with<vtkXMLUnstructuredGridReader>(path);
  if (ext == "vtp") return read_with<vtkXMLPolyDataReader>(path);
  if (ext == "vtk") return read_with<vtkDataSetReader>(path);
  if (ext == "ply") {
    if (!vtkPLYReader::CanReadFile(path.c_str())) {
      throw Error("cannot read '" + path + "': not a PLY file");
    }
    return read_with<vtkPLYReader>(path);
  }
  if (ext == "stl") return read_with<vtkSTLReader>(path);  // binary or ASCII; points merged
  return read_with<vtkOBJReader>(path);
}

/// Gathers the layers of a file and the first camera recorded on any of its objects.
struct LayerCollector {
  std::optional<ViewCamera>* camera;
  std::vector<Layer> layers;

  void note_camera(vtkDataObject* d) {
    if (camera && !*camera) *camera = recorded_camera(d);
  }
  /// Adds `d` as a layer unless it is null or has no points.
  void add(vtkDataSet* d, const std::string& name) {
    note_camera(d);
    if (!d || d->GetNumberOfPoints() == 0) return;
    Layer l;
    l.name = name;
    l.data = d;
    l.role = guess_role(name, d);
    layers.push_back(std::move(l));
  }
  /// Adds every non-empty leaf of `mb`, named by its block name ("block N" when it has none).
  void add_blocks(vtkMultiBlockDataSet* mb) {
    note_camera(mb);
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
  }
};

/// In a pixel inspection the slabs, depth boxes near the hits and the points are the subject;
/// the search's coarse pieces, the beam and the enclosure boxes around them are context, outlined.
void outline_context(std::vector<Layer>& layers) {
  bool inspection = false;
  for (const Layer& l : layers)
    inspection |= l.role == LayerRole::kSlabs || l.role == LayerRole::kPoints;
  if (!inspection) return;
  for (Layer& l : layers)
    l.outline = name_has(l.name, "coarse") || l.role == LayerRole::kEnclosure ||
                l.role == LayerRole::kFrusta;
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
  if (has_cell_array(d, kReasonArray)) return LayerRole::kUncertified;
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
  return ".vtm, .vtu, .vtp, .vtk, .ply, .obj, .stl";
}

std::vector<Layer> load_layers(const std::string& path, std::optional<ViewCamera>* camera) {
  const std::string ext = lower_extension(path);
  check_readable(path, ext);
  const vtkSmartPointer<vtkDataObject> obj = read_file(path, ext);
  LayerCollector collect{camera, {}};
  if (auto* mb = vtkMultiBlockDataSet::SafeDownCast(obj)) {
    collect.add_blocks(mb);
  } else if (auto* ds = vtkDataSet::SafeDownCast(obj)) {
    collect.add(ds, std::filesystem::path(path).filename().string());
  } else {
    throw Error("cannot read '" + path + "': not a data set VTK can draw");
  }
  if (collect.layers.empty()) throw Error("'" + path + "' holds no points to draw");
  outline_context(collect.layers);
  return std::move(collect.layers);
}

}  // namespace iaa::viz
