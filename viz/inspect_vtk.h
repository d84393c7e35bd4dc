// One pixel's inspection (render/trace.h) as a VTK multiblock, written as a `.vtm` through VTK's
// XML multiblock writer: what `iaa inspect --vtk OUT.vtm` writes and `iaa-viz` shows.
//
// Blocks (names are what iaa-viz keys its roles, colours and legend on, viz/scene_layer.h):
// - `beams`: one pyramid per sub-beam of the pixel (level >= 0), apex at the eye, base at the far
//   end of the scene bounds. Cell arrays `result` (0 miss, 1 full, 2 partial), `level`, `beam`
//   (index into the trace / the JSON of `iaa inspect`), `decision` (BeamDecision), `t_near`
//   (NaN for a Miss), `t_far` (Full only, else NaN). When the pixel was decided by a screen block
//   above it (a Miss block), that block's beam is shown instead.
// - `hit_slabs`: for every beam that was shaded (a leaf of the pixel's quadtree), the piece of
//   its frustum where its first hits lie: [t_near, t_far] for a Full beam, the kept depth piece
//   [t_near, ...] for a Partial one. Hexahedra with the same cell arrays as `beams`.
// - `depth_boxes`: every depth piece the search evaluated, as the axis box F was evaluated on
//   (clipped to the bounds). Cell arrays `verdict` (0 excluded, 1 kept), `beam`, `level`,
//   `order` (position in its beam's search), `t` (2: depth range), `f` (2: natural interval
//   value), `f_mean_value` (2: the mean-value form when it was also tried, else NaN),
//   `partial_domain`. A piece tested twice (natural value, then mean-value form) is one box with
//   the final verdict. Only pieces at most 16 beam widths long (at their far end) are here:
// - `coarse_depth_boxes`: the longer pieces, same arrays. They are the search's first pieces,
//   which run through much of the scene; iaa-viz outlines them so they do not hide the rest.
// - `hit_points`: shading points (IAA leaves, or point rays that hit) as vertices with point
//   normals, point arrays `color` (UInt8 RGB, the shaded colour as in the PNG), `beam` (-1 for a
//   ray), `center_ray_hit`.
// - `sample_rays` (point-sampling methods): one line per ray from the eye to its hit or to the far
//   end; cell arrays `hit`, `certified`.
// - `enclosure` (optional): enclosure boxes near the pixel (viz/enclosure_vtk.h layout, `class`).
// - `mesh` (optional): octree-mesh triangles near the pixel.
// Every leaf and the multiblock carry the scene's camera (`iaa_camera`, viz/scene_camera.h) and the
// field data `format` ("iaa-inspect 1"), `pixel` (x, y), `scene`, `method`.
#pragma once

#include <string>

#include <vtkMultiBlockDataSet.h>
#include <vtkSmartPointer.h>

#include "enclose/octree.h"
#include "mesh/triangle_soup.h"
#include "render/trace.h"
#include "scene/scene.h"
#include "scene/settings.h"
#include "viz/plugin_api.h"  // InspectionInput

namespace iaa::viz {

/// Block names of an inspection multiblock.
inline constexpr const char* kBeamsBlock = "beams";
inline constexpr const char* kSlabsBlock = "hit_slabs";
inline constexpr const char* kDepthBoxesBlock = "depth_boxes";
inline constexpr const char* kCoarseDepthBoxesBlock = "coarse_depth_boxes";
inline constexpr const char* kHitPointsBlock = "hit_points";
inline constexpr const char* kSampleRaysBlock = "sample_rays";
inline constexpr const char* kEnclosureBlock = "enclosure";
inline constexpr const char* kMeshBlock = "mesh";
/// Value of the `format` field data.
inline constexpr const char* kInspectFormat = "iaa-inspect 1";

/// Builds the multiblock described above.
vtkSmartPointer<vtkMultiBlockDataSet> inspection_to_multiblock(const InspectionInput& in);

/// Writes a multiblock with vtkXMLMultiBlockDataWriter: `path` (.vtm) and the directory of its
/// pieces beside it (`path` without the extension). Atomic: everything is written into a
/// temporary directory first and moved into place, the .vtm last, so a failure leaves neither a
/// partial file nor a partial directory behind. Throws iaa::Error naming the path on failure.
void write_vtm_atomically(const std::string& path, vtkMultiBlockDataSet* data);

}  // namespace iaa::viz
