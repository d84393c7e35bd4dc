// An Enclosure (libiaa/enclose/octree.h) as a partitioned VTK file: a `.pvtu` summary and one
// `.vtu` piece per process of a run under mpirun (docs/distributed.md), written through VTK's
// parallel XML writer (vtkXMLPUnstructuredGridWriter), so that ParaView opens the `.pvtu` as one
// data set. Each piece holds a contiguous slice of the enclosure's cells in canonical order, with
// the arrays and field data of viz/enclosure_vtk.h.
#pragma once

#include <string>
#include <vector>

#include "viz/enclosure_vtk.h"

namespace iaa::viz {

// pvtu_piece_paths(path, pieces), the file names of the pieces, is in viz/plugin_api.h.

/// Writes piece `piece` of `pieces` (cells [piece * N / pieces, (piece + 1) * N / pieces) of the
/// enclosure) as `STEM_piece.vtu` beside `path`, and also the summary `path`, naming all the
/// pieces, when `summary`.
/// Writes directly: the tools write into a temporary directory and move the files. Throws
/// iaa::Error when VTK fails to write.
void write_enclosure_pvtu(const std::string& path, const Enclosure& enc, const EnclosureInfo& info,
                          int piece, int pieces, bool summary);

}  // namespace iaa::viz
