// An Enclosure (libiaa/enclose/octree.h) as a VTK unstructured grid of voxels, written and read
// as compressed, appended, raw binary `.vtu` through VTK's own XML writer and reader.
//
// File layout (what ParaView or any VTK reader sees):
// - points: double precision, 8 per voxel in VTK_VOXEL order; they are exactly the boxes that f
//   was evaluated on (Enclosure::box), so the file itself is a certified enclosure;
// - cell arrays: `depth` (UInt8), `class` (Int8: 1 crossing, 2 possible), `f_lo`, `f_hi`
//   (Float64: the interval value of f over the voxel) and `index` (UInt32, 3 components: the
//   cell's integer position at its depth, for exact reconstruction);
// - field data: `expression` (string), `bounds` (6 doubles: x0 x1 y0 y1 z0 z1), `depth`,
//   `refine_possible`, `max_boxes`, `evaluations`, `corner_evaluations` (one value each) and
//   `format` ("iaa-enclosure 1").
#pragma once

#include <string>

#include <vtkSmartPointer.h>

#include "core/exec.h"
#include "enclose/octree.h"
#include "viz/plugin_api.h"  // EnclosureInfo, VtuWriteTimes

class vtkUnstructuredGrid;

namespace iaa::viz {

/// Builds the voxel grid of an enclosure (arrays filled directly, in parallel; no per-cell calls).
vtkSmartPointer<vtkUnstructuredGrid> enclosure_to_grid(const Enclosure& enc,
                                                       const EnclosureInfo& info);

/// Writes `enc` to `path` as compressed appended binary .vtu (LZ4). Writes `path` directly: tools
/// wrap this in write_atomically. Throws iaa::Error when VTK fails to write.
/// `progress`, when given, sees a phase "write .vtu" of 1000 units driven by VTK's own progress.
void write_enclosure_vtu(const std::string& path, const Enclosure& enc, const EnclosureInfo& info,
                         Progress* progress = nullptr);

/// An enclosure read back from a .vtu written by write_enclosure_vtu.
struct EnclosureFile {
  Enclosure enclosure;  ///< cells, bounds, counts and evaluation counts as written
  EnclosureInfo info;
  /// True when every voxel's 8 points equal Enclosure::box of its cell, bit for bit.
  bool points_match_boxes = false;
};

/// Writes any unstructured grid as .vtu with the enclosure's writer settings (appended raw
/// binary, LZ4, 64-bit headers): enclosure_to_grid's (timed in parts by the bench) and others'.
void write_grid_vtu(const std::string& path, vtkUnstructuredGrid* grid,
                    Progress* progress = nullptr);

/// write_enclosure_vtu with its two parts timed apart, for `iaa bench enclose`: the grid is built
/// inside `exec`'s arena (its threads), then written as write_enclosure_vtu writes it.
VtuWriteTimes write_enclosure_vtu_timed(const std::string& path, const Enclosure& enc,
                                        const EnclosureInfo& info, const Exec& exec);

/// Reads a .vtu written by write_enclosure_vtu with vtkXMLUnstructuredGridReader. Throws
/// iaa::Error when the file is missing, unreadable, or lacks the arrays above.
EnclosureFile read_enclosure_vtu(const std::string& path);

}  // namespace iaa::viz
