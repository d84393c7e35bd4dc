// The categories of iaa's categorical cell arrays (see scene_layer.h).
#include "scene_layer.h"

#include <vtkCellData.h>
#include <vtkDataSet.h>

namespace iaa::viz {

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

bool has_cell_array(vtkDataSet* d, const char* name) {
  return d && d->GetCellData() && d->GetCellData()->GetArray(name) != nullptr;
}

}  // namespace iaa::viz
